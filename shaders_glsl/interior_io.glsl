// Shared by interior.vert and interior.frag: push constants, the per-node buffers, and how
// many candidate volumes a node's vertices carry (InteriorPass.cpp mirrors kCandidates).
layout(push_constant) uniform Push {
  uint node_offset;
  uint node_count;
} pc;

layout(std430, set = 0, binding = 1) readonly buffer NodeInverse { mat4 node_from_world[]; };
layout(std430, set = 0, binding = 2) readonly buffer NodeKinds { uint kind[]; };

const uint kCandidates = 4u;
const uint kAllNodes = 0xffffffffu;  // more candidates than that: test every node per texel
