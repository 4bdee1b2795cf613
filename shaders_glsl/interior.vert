#version 460
// Interior (occlusion) pass, vertex stage: faces in atlas space carrying world positions
// and, for the few primitives whose volume may hold this node's surface (InteriorPass.cpp
// picks them per hypothesis), the position in each one's unit frame. Within a triangle
// both are affine in atlas space, so interpolating them is exact, and the fragment stage
// tests without a matrix per texel (on lavapipe those loads were most of the pass).
#extension GL_GOOGLE_include_directive : require
#include "atlas_space.glsl"
#include "interior_io.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 2) in vec2 in_atlas_uv;
layout(location = 3) in uint in_node;

layout(std430, set = 0, binding = 0) readonly buffer NodeMatrices { mat4 world_from_node[]; };
// Per slot and node: the candidate nodes (unused entries 0) and their count, or
// kAllNodes when there are more than kCandidates.
layout(std430, set = 0, binding = 3) readonly buffer Candidates { uvec4 candidates[]; };

layout(location = 0) out vec3 world;
layout(location = 1) flat out uint node;
layout(location = 2) flat out uvec4 candidate_kinds;
layout(location = 3) flat out uint all_nodes;
layout(location = 4) out vec3 local[kCandidates];

void main() {
  world = (world_from_node[pc.node_offset + in_node] * vec4(in_position, 1.0)).xyz;
  node = in_node;
  const uint entry = 2u * (pc.node_offset + in_node);
  const uvec4 others = candidates[entry];
  const uint count = candidates[entry + 1u].x;
  all_nodes = count == kAllNodes ? 1u : 0u;
  candidate_kinds = uvec4(0u);
  for (uint i = 0u; i < kCandidates; ++i) {
    local[i] = vec3(0.0);
    if (i < count && count != kAllNodes) {
      candidate_kinds[i] = kind[others[i]];
      local[i] = (node_from_world[pc.node_offset + others[i]] * vec4(world, 1.0)).xyz;
    }
  }
  gl_Position = AtlasPosition(in_atlas_uv);
}
