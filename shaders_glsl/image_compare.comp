#version 460
// Image-space likelihood (thesis §4.4), first level of the reduction: per pixel the sum over
// the warp pass's results (one layer per warp draw: a target t and a group of its sources,
// each pixel already summed over the group), then one partial sum per workgroup. reduce.comp sums the partials per hypothesis. A workgroup is
// one subgroup (as composite.comp): each invocation sums a column of kRows pixels, then
// the subgroup adds its lanes.
//   sum_squares = σ² Σ χ²  over compared pixel pairs       dof = 3 per compared pair
//   seen_multi  = compared pixel pairs (t and s see the surface point)
//   seen_once   = pixel pairs where only t sees the surface point
// (seen_none and interior stay 0: the image-space likelihood sees only what t sees.)
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "subgroup_reduction.glsl"

layout(local_size_x_id = 0, local_size_y = 1) in;
// The number of layers, fixed when the pipeline is made (ImageComparePass.cpp): a loop the
// driver can unroll, as in composite.comp.
layout(constant_id = 1) const uint kLayers = 1u;

// r: Σ χ² over the layer's compared pixel pairs, g: their count, b: pixel pairs where only t
// sees the point (image_warp.glsl).
layout(set = 0, binding = 0, rgba32f) uniform readonly image2DArray results;
layout(std430, set = 0, binding = 1) readonly buffer LayerSizes { uvec2 sizes[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Partials { Scalars partials[]; };

layout(push_constant) uniform Push {
  uint size_offset;     // first of this level's sizes[] (one per layer: t's image at the level)
  uint partial_offset;  // first partial of this hypothesis
  float sigma2;         // σ² on the [0,1] colour scale
} pc;

// Pixels per invocation, a column (ImageComparePass.cpp mirrors it as kCompareRows).
const uint kRows = 16u;

Scalars ComparePixel(uvec2 pixel) {
  float chi2 = 0.0;
  uint compared = 0u, once = 0u;
  for (uint l = 0u; l < kLayers; ++l) {
    const uvec2 size = sizes[pc.size_offset + l];
    if (pixel.x >= size.x || pixel.y >= size.y) continue;
    const vec4 v = imageLoad(results, ivec3(pixel, l));
    chi2 += v.r;
    compared += uint(v.g);
    once += uint(v.b);
  }
  return Scalars(chi2 * pc.sigma2, 3.0 * float(compared), 0.0, 0.0, compared, once, 0u, 0u, 0u, 0u, 0u, 0u);
}

void main() {
  Scalars mine = ZeroScalars();
  const uint x = gl_GlobalInvocationID.x;
  for (uint r = 0u; r < kRows; ++r) mine = AddScalars(mine, ComparePixel(uvec2(x, gl_WorkGroupID.y * kRows + r)));
  const Scalars total = ReduceSubgroup(mine);
  if (subgroupElect()) {
    const uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    partials[pc.partial_offset + group] = total;
  }
}
