#version 460
// Interior (occlusion) pass, vertex stage: faces in atlas space carrying world positions.
#extension GL_GOOGLE_include_directive : require
#include "atlas_space.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 2) in vec2 in_atlas_uv;
layout(location = 3) in uint in_node;

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };

layout(push_constant) uniform Push {
  uint node_offset;
  uint node_count;
} pc;

layout(location = 0) out vec3 world;
layout(location = 1) flat out uint node;

void main() {
  world = (world_from_node[pc.node_offset + in_node] * vec4(in_position, 1.0)).xyz;
  node = in_node;
  gl_Position = AtlasPosition(in_atlas_uv);
}
