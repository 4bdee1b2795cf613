#version 460
// Image-space likelihood (thesis §4.4), first level of the reduction: per pixel the sum over
// camera pairs of the warp pass's results (one layer per ordered pair (s, t)), then one
// partial sum per workgroup. reduce.comp sums the partials per hypothesis.
//   sum_squares = σ² Σ χ²  over compared pixel pairs       dof = 3 per compared pair
//   seen_multi  = compared pixel pairs (t and s see the surface point)
//   seen_once   = pixel pairs where only t sees the surface point
// (seen_none and interior stay 0: the image-space likelihood sees only what t sees.)
#extension GL_GOOGLE_include_directive : require
#include "reduction.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 0, r32f) uniform readonly image2DArray results;
layout(std430, set = 0, binding = 1) readonly buffer PairSizes { uvec2 sizes[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Partials { Scalars partials[]; };

layout(push_constant) uniform Push {
  uint pair_count;
  uint size_offset;     // first of this level's sizes[] (one per pair: t's image at the level)
  uint partial_offset;  // first partial of this hypothesis
  float sigma2;         // σ² on the [0,1] colour scale
} pc;

void main() {
  const uvec2 pixel = gl_GlobalInvocationID.xy;
  float chi2 = 0.0;
  uint compared = 0u, once = 0u;
  for (uint p = 0u; p < pc.pair_count; ++p) {
    const uvec2 size = sizes[pc.size_offset + p];
    if (pixel.x >= size.x || pixel.y >= size.y) continue;
    const float v = imageLoad(results, ivec3(pixel, p)).r;
    if (v >= 0.0) {
      chi2 += v;
      ++compared;
    } else if (v > -1.5) {
      ++once;
    }
  }
  Scalars mine = Scalars(chi2 * pc.sigma2, 3.0 * float(compared), compared, once, 0u, 0u, 0u, 0u);
  const Scalars total = ReduceWorkgroup(gl_LocalInvocationIndex, mine);
  if (gl_LocalInvocationIndex == 0u) {
    const uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    partials[pc.partial_offset + group] = total;
  }
}
