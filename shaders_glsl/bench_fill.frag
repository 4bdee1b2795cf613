#version 460
// `vkrecon bench` fill ceiling: the cheapest fragment there is, a constant colour (varied
// per draw through the push constant) written into an RGBA16F target like the view textures.

layout(push_constant) uniform Push {
  vec4 colour;
} pc;

layout(location = 0) out vec4 colour;

void main() { colour = pc.colour; }
