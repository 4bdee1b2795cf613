#version 460
// Composite + deviation pass (thesis §6) fused with the first level of the reduction: per
// texel a robust consensus colour over the views and each view's robust deviation from it
// (pipelines/Evaluation.h gives the model and the formulas), then one partial sum per
// workgroup. A workgroup is one subgroup (local_size_x = its size, CompositePass.cpp); each
// invocation sums a column of kRows texels, then the subgroup adds its lanes.
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "subgroup_reduction.glsl"
#include "view_texel.glsl"

layout(local_size_x_id = 0, local_size_y = 1) in;
// The number of views, fixed when the pipeline is made (CompositePass.cpp): loops the
// driver can unroll and arrays it can keep in registers.
layout(constant_id = 1) const uint kViews = 1u;

layout(set = 0, binding = 0, rg32ui) uniform readonly uimage2DArray views;
layout(set = 0, binding = 1, r32ui) uniform readonly uimage2D mask;
layout(std430, set = 0, binding = 2) writeonly buffer Partials { Scalars partials[]; };
layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D composite_out;
layout(set = 0, binding = 4, rgba32f) uniform writeonly image2D deviation_out;
// Per view: gain (xyz; w = their mean, which scales the image texture too) and offset (xyz)
// of the photometric correction c' = gain·c + offset (pipelines/Photometric.h).
layout(std430, set = 0, binding = 5) readonly buffer Photometric { vec4 photometric[]; };
layout(set = 0, binding = 6, rgba32f) uniform writeonly image2D noise_out;

layout(push_constant) uniform Push {
  uint size;            // atlas side at this level
  uint partial_offset;  // first partial of this hypothesis
  uint write_images;    // 1: also write composite_out, deviation_out and noise_out (dumps)
  float sigma2;         // σ² of the noise model, [0,1] colour scale
  float delta2;         // δ² (level pixels²): the noise grows by δ²|∇I|² where the image is textured
  float outlier;        // K: the χ² (3 channels) at which a view's loss saturates
} pc;

// Texels per invocation, a column (CompositePass.cpp mirrors it as kCompositeRows): fewer
// partials to reduce.
const uint kRows = 16u;
// Reweighting rounds of the consensus (an M-estimator over the views of one texel).
const uint kRounds = 3u;

Scalars CompositeTexel(uvec2 texel) {
  Scalars mine = ZeroScalars();
  vec3 mean = vec3(0.0);
  float chi2 = 0.0, expected = 0.0, texture_share = 0.0;
  uint n = 0u, outliers = 0u, masked = 0u;
  const uint m = imageLoad(mask, ivec2(texel)).r;
  if (m == 2u) {
    mine.interior = 1u;
  } else if (m == 1u) {
    vec3 c[kViews];
    float w[kViews], v[kViews], k[kViews], omega[kViews], e2[kViews];
    float sw = 0.0, swk = 0.0, share = 0.0;
    for (uint i = 0u; i < kViews; ++i) {
      const uvec2 t = imageLoad(views, ivec3(texel, i)).xy;
      w[i] = ViewWeight(t);
      if (ViewMasked(t)) masked += 1u;
      const vec4 gain = photometric[2u * i], offset = photometric[2u * i + 1u];
      c[i] = gain.xyz * ViewColour(t) + offset.xyz;
      const float g = gain.w * ViewTexture(t);
      const float textured = pc.delta2 * g * g;
      // A sample averaging m pixels carries 1/m of their noise. (Its loss still saturates at
      // K, not m·K: clutter that covers many pixels is not made costlier to explain, which
      // would reward hypotheses that grow over it; docs/LIKELIHOOD.md.)
      v[i] = pc.sigma2 / max(ViewMass(t), 1.0) + textured;
      k[i] = pc.outlier;
      omega[i] = 1.0;
      if (w[i] > 0.0) {
        n += 1u;
        sw += w[i];
        swk += w[i] * k[i];
        share += w[i] * textured / v[i];
      }
    }
    if (n >= 2u) {
      // Consensus: the precision-weighted mean, reweighted by each view's Welsch weight
      // e^(−e²/K) relative to the closest view's (so that a texel whose views all disagree
      // keeps a finite mean): a view far from the others (an occluder the scene lacks, a
      // highlight) stops pulling it.
      for (uint round = 0u; round <= kRounds; ++round) {
        float sp = 0.0;
        vec3 spc = vec3(0.0);
        for (uint i = 0u; i < kViews; ++i) {
          const float p = omega[i] * w[i] / v[i];
          sp += p;
          spc += p * c[i];
        }
        mean = spc / sp;
        float closest = 3.0e38;
        for (uint i = 0u; i < kViews; ++i) {
          const vec3 d = c[i] - mean;
          e2[i] = dot(d, d) / v[i];
          if (w[i] > 0.0) closest = min(closest, e2[i] / k[i]);
        }
        if (round < kRounds)
          for (uint i = 0u; i < kViews; ++i) omega[i] = exp(closest - e2[i] / k[i]);
      }
      // The loss, Σ w_i K_i (1 − e^(−e²_i/K_i)), and its expectation under the noise model: a
      // view's residual from the (plain) precision-weighted mean has variance a_i·v_i per
      // channel, and E[K(1 − e^(−X/K))] = K(1 − (1 + 2a/K)^(−3/2)) for X = a·χ²₃.
      float sp = 0.0, spw = 0.0;
      for (uint i = 0u; i < kViews; ++i) {
        const float p = w[i] / v[i];
        sp += p;
        spw += p * w[i];
      }
      for (uint i = 0u; i < kViews; ++i) {
        if (!(w[i] > 0.0)) continue;
        const float p = w[i] / v[i];
        const float a = max(1.0 - 2.0 * p / sp + spw / (v[i] * sp * sp), 0.0);
        chi2 += w[i] * k[i] * (1.0 - exp(-e2[i] / k[i]));
        expected += w[i] * k[i] * (1.0 - pow(1.0 + 2.0 * a / k[i], -1.5));
        if (e2[i] > k[i]) outliers += 1u;
      }
      // Views that all disagree are one event, not many: the texel is not what the cameras
      // see (something the scene lacks stands on it). It costs one average view's
      // saturation beyond the expectation, so hiding it gains no more than that.
      chi2 = min(chi2, expected + swk / float(n));
      texture_share = share / sw;
      mine.sum_squares = chi2 * pc.sigma2;
      mine.dof = expected;
      mine.seen_multi = 1u;
      mine.views = n;
      mine.outlier_views = outliers;
    } else if (masked > 0u) {
      // A camera sees it, but a mask (the user's, clutter) hides it there and leaves fewer
      // than two to compare: unknown, not unverifiable surface; neither compared nor charged.
      for (uint i = 0u; i < kViews; ++i)
        if (w[i] > 0.0) mean = c[i];
      mine.masked = 1u;
    } else if (n == 1u) {
      for (uint i = 0u; i < kViews; ++i)
        if (w[i] > 0.0) mean = c[i];
      mine.seen_once = 1u;
      // What its view would cost were it an outlier: no texel can gain by escaping where
      // only one camera sees it (the cap above bounds every compared texel's excess by an
      // average view's saturation).
      mine.unverified = swk;
    } else {
      mine.seen_none = 1u;
    }
  }
  if (pc.write_images != 0u) {
    imageStore(composite_out, ivec2(texel), vec4(mean, float(n)));
    imageStore(deviation_out, ivec2(texel), vec4(chi2, expected, m == 2u ? 1.0 : 0.0, m != 0u ? 1.0 : 0.0));
    imageStore(noise_out, ivec2(texel), vec4(texture_share, float(outliers), float(n), float(masked)));
  }
  return mine;
}

void main() {
  Scalars mine = ZeroScalars();
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
