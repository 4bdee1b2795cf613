#version 460
// Interior (occlusion) pass (§7.1.1–7.1.4): marks each surface texel 1 (exterior) or 2
// (inside, or on the boundary of, another primitive: a box's underside on the ground, a
// roof's base on its walls, faces of interpenetrating primitives). Texels outside every
// chart stay 0. The ground plane is solid below it, so what stands on it seals its base.
#extension GL_GOOGLE_include_directive : require
#include "interior_io.glsl"

layout(location = 0) in vec3 world;
layout(location = 1) flat in uint node;
layout(location = 2) flat in uvec4 candidate_kinds;
layout(location = 3) flat in uint all_nodes;
layout(location = 4) in vec3 local[kCandidates];
layout(location = 0) out uint mask;

// 0: no face of the hypothesis tests every node (InteriorPass picks the pipeline per slot),
// and the search below is compiled out: lavapipe would run its loop's first pass under the
// mask for every texel (a third of the house interior pass).
layout(constant_id = 0) const uint kSearchAllNodes = 1u;

const float kEps = 1e-3;  // in the other node's unit frame: "on the boundary" counts as inside
const uint kPlane = 1u, kBox = 2u, kPrism = 3u, kCylinder = 4u;

bool Inside(uint k, vec3 p) {
  const bool in_xy = abs(p.x) <= 0.5 + kEps && abs(p.y) <= 0.5 + kEps;
  const bool in_z = p.z >= -kEps && p.z <= 1.0 + kEps;
  if (k == kPlane) return in_xy && p.z <= kEps;
  if (k == kBox) return in_xy && in_z;
  if (k == kPrism) return abs(p.x) <= 0.5 + kEps && in_z && abs(p.y) <= 0.5 * (1.0 - p.z) + kEps;
  if (k == kCylinder) return dot(p.xy, p.xy) <= (0.5 + kEps) * (0.5 + kEps) && in_z;
  return false;  // none, meshes and transform-only nodes contain nothing
}

void main() {
  bool inside = false;
  if (kSearchAllNodes != 0u && all_nodes != 0u) {
    for (uint n = 0u; n < pc.node_count && !inside; ++n)
      if (n != node) inside = Inside(kind[n], (node_from_world[pc.node_offset + n] * vec4(world, 1.0)).xyz);
  } else {
    for (uint i = 0u; i < kCandidates; ++i) inside = inside || Inside(candidate_kinds[i], local[i]);
  }
  mask = inside ? 2u : 1u;
}
