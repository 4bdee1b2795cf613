#version 460
// Composite + deviation pass (thesis §6) fused with the first level of the reduction:
// per texel the weighted mean over views and the weighted squared deviation from it
// (pipelines/Evaluation.h gives the formulas), then one partial sum per workgroup.
// A workgroup is one subgroup (local_size_x = its size, CompositePass.cpp); each invocation
// sums a column of kRows texels, then the subgroup adds its lanes.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "subgroup_reduction.glsl"

layout(local_size_x_id = 0, local_size_y = 1) in;
// The number of views, fixed when the pipeline is made (CompositePass.cpp): a loop the
// driver can unroll (on lavapipe 20 % of the pass, against the count in push constants).
layout(constant_id = 1) const uint kViews = 1u;

layout(set = 0, binding = 0, rgba16f) uniform readonly image2DArray views;
layout(set = 0, binding = 1, r32ui) uniform readonly uimage2D mask;
layout(std430, set = 0, binding = 2) writeonly buffer Partials { Scalars partials[]; };
layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D composite_out;
layout(set = 0, binding = 4, rgba32f) uniform writeonly image2D deviation_out;

layout(push_constant) uniform Push {
  uint size;            // atlas side at this level
  uint partial_offset;  // first partial of this hypothesis
  uint write_images;    // 1: also write composite_out and deviation_out (dumps)
  float inv_sigma2;     // 1 / σ² on the [0,1] colour scale
  float cap;            // per-dof cap of s_t / σ²
} pc;

// Texels per invocation, a column (CompositePass.cpp mirrors it as kCompositeRows): fewer
// partials to reduce.
const uint kRows = 16u;

Scalars CompositeTexel(uvec2 texel) {
  Scalars mine = Scalars(0.0, 0.0, 0u, 0u, 0u, 0u, 0u, 0u);
  vec3 mean = vec3(0.0);
  float chi2 = 0.0, n = 0.0;
  const uint m = imageLoad(mask, ivec2(texel)).r;
  if (m == 2u) {
    mine.interior = 1u;
  } else if (m == 1u) {
    float sw = 0.0, sww = 0.0, swcc = 0.0;
    vec3 swc = vec3(0.0);
    for (uint i = 0u; i < kViews; ++i) {
      const vec4 v = imageLoad(views, ivec3(texel, i));
      if (v.a > 0.0) {
        n += 1.0;
        sw += v.a;
        sww += v.a * v.a;
        swc += v.a * v.rgb;
        swcc += v.a * dot(v.rgb, v.rgb);
      }
    }
    if (n >= 2.0) {
      mean = swc / sw;
      // Σ w‖c − μ‖² = Σ w‖c‖² − ‖Σ w c‖² / Σ w (Evaluation.h).
      const float s = max(swcc - dot(swc, swc) / sw, 0.0);
      // Effective degrees of freedom: E[s] = 3σ²(Σw − Σw²/Σw) under noise σ (Evaluation.h).
      const float dof = 3.0 * max(sw - sww / sw, 0.0);
      chi2 = min(s * pc.inv_sigma2, pc.cap * dof);
      mine.sum_squares = chi2 / pc.inv_sigma2;
      mine.dof = dof;
      mine.seen_multi = 1u;
    } else if (n == 1.0) {
      mean = swc / sw;
      mine.seen_once = 1u;
    } else {
      mine.seen_none = 1u;
    }
  }
  if (pc.write_images != 0u) {
    imageStore(composite_out, ivec2(texel), vec4(mean, n));
    imageStore(deviation_out, ivec2(texel),
               vec4(chi2, mine.dof, m == 2u ? 1.0 : 0.0, m != 0u ? 1.0 : 0.0));
  }
  return mine;
}

void main() {
  Scalars mine = Scalars(0.0, 0.0, 0u, 0u, 0u, 0u, 0u, 0u);
  const uint x = gl_GlobalInvocationID.x;
  const uint y0 = gl_WorkGroupID.y * kRows;
  for (uint r = 0u; r < kRows; ++r)
    if (x < pc.size && y0 + r < pc.size) mine = AddScalars(mine, CompositeTexel(uvec2(x, y0 + r)));
  const Scalars total = ReduceSubgroup(mine);
  if (subgroupElect()) {
    const uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    partials[pc.partial_offset + group] = total;
  }
}
