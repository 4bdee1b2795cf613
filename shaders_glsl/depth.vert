#version 460
// Depth pass (docs/internals/LIKELIHOOD.md, "Passes, per hypothesis"): the scene seen from one
// camera, depth only, reversed depth (Projection.h). The view-texture pass reads it as a shadow
// map.

layout(location = 0) in vec3 in_position;
layout(location = 3) in uint in_node;

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };

layout(push_constant) uniform Push {
  mat4 clip_from_world;
  uint node_offset;
} pc;

void main() {
  gl_Position = pc.clip_from_world * (world_from_node[pc.node_offset + in_node] * vec4(in_position, 1.0));
}
