#version 460
// Colour of the surface from the atlas (albedo for synth, composite for render); alpha 1
// marks covered pixels. Mode 1 writes the interpolated world position instead, which the
// tests use to check the projection to a hundredth of a pixel.

layout(set = 0, binding = 1) uniform sampler2D atlas;

layout(push_constant) uniform Push {
  mat4 clip_from_world;
  uint node_offset;
  uint mode;
} pc;

layout(location = 0) in vec2 atlas_uv;
layout(location = 1) in vec3 world_position;
layout(location = 0) out vec4 colour;

void main() {
  colour = pc.mode == 0u ? vec4(texture(atlas, atlas_uv).rgb, 1.0) : vec4(world_position, 1.0);
}
