#version 460
// Image-space warp pass (thesis §4.2–4.3), vertex stage: the hypothesis seen from the target
// camera t, carrying each vertex's clip position in every source camera s of the draw.
// Projective mapping is done per vertex, where it is linear in homogeneous coordinates, so
// the fragment stage only divides (LAVAPIPE.md: a 4×4 per fragment halves the rate).
#extension GL_GOOGLE_include_directive : require
#include "image_warp_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 3) in uint in_node;

layout(location = 0) out vec3 world;
layout(location = 1) out vec3 normal;
layout(location = 2) out vec4 clip_s[kMaxSources];

void main() {
  const mat4 m = world_from_node[pc.node_offset + in_node];
  const vec4 w = m * vec4(in_position, 1.0);
  world = w.xyz;
  normal = transpose(inverse(mat3(m))) * in_normal;
  // A loop over the push constant rather than a specialisation constant: vertices are few,
  // and the fragment stage, which is specialised, reads only the draw's sources.
  for (uint i = 0u; i < kMaxSources; ++i)
    clip_s[i] = i < pc.source_count ? cameras[pc.sources[i]].clip_from_world * w : vec4(0.0);
  // The same product as depth.vert, so that the depth-equal test against t's depth map passes
  // exactly the visible surface. Reversed depth is near/z: scaling clip.z by 1 + ε moves
  // every fragment nearer by a relative ε, which absorbs rounding differences between the
  // two shaders (a surface within ε·z behind the visible one also passes; it can only
  // overwrite the same pixel, never add to it).
  gl_Position = cameras[pc.target].clip_from_world * w;
  gl_Position.z *= 1.0 + pc.depth_equal;
}
