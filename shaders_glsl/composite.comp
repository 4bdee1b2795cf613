#version 460
// Composite + deviation pass (thesis §6) fused with the first level of the reduction: per
// texel a robust consensus colour over the views and each view's robust deviation from it
// (pipelines/model/Evaluation.h gives the model and the formulas), then one partial sum per
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
// 1: also write composite_out, deviation_out and noise_out (dumps). A constant, not a push
// constant: lavapipe runs the stores' lane loops under the mask even where none is taken
// (0.7 of the house composite's 2.7 ms), so the pass of every evaluation is made without them.
layout(constant_id = 2) const uint kWriteImages = 0u;

layout(set = 0, binding = 0, rg32ui) uniform readonly uimage2DArray views;
layout(set = 0, binding = 1, r32ui) uniform readonly uimage2D mask;
layout(std430, set = 0, binding = 2) writeonly buffer Partials { Scalars partials[]; };
layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D composite_out;
layout(set = 0, binding = 4, rgba32f) uniform writeonly image2D deviation_out;
// Per view: gain (xyz; w = their mean, which scales the image texture too) and offset (xyz)
// of the photometric correction c' = gain·c + offset (pipelines/model/Photometric.h).
layout(std430, set = 0, binding = 5) readonly buffer Photometric { vec4 photometric[]; };
layout(set = 0, binding = 6, rgba32f) uniform writeonly image2D noise_out;
// The workgroup tiles that touch a chart (CompositePass.cpp): texels off the charts are no
// surface and are not visited.
layout(std430, set = 0, binding = 7) readonly buffer Tiles { uvec2 tiles[]; };

layout(push_constant) uniform Push {
  uint size;            // atlas side at this level
  uint partial_offset;  // first partial of this hypothesis
  float sigma2;         // σ² of the noise model, [0,1] colour scale
  float delta2;         // δ² (level pixels²): the noise grows by δ²|∇I|² where the image is textured
  float outlier;        // K: the χ² (3 channels) at which a view's loss saturates
  uint tile_offset;     // this level's first tile
} pc;

// Texels per invocation, a column (CompositePass.cpp mirrors it as kCompositeRows): fewer
// partials to reduce.
const uint kRows = 16u;
// Reweighting rounds of the consensus (an M-estimator over the views of one texel), and the
// share of K up to which a view's weight stays 1 (the flat top: views that agree as well as
// noise allows keep the plain mean, at no cost).
const uint kRounds = 3u;
const float kFlat = 1.0 / 3.0;

// The photometric correction, read once per invocation (not per texel: lavapipe's buffer
// reads were a quarter of the pass).
vec4 gains[kViews], offsets[kViews];

// One view of a texel as the statistic needs it: corrected colour, weight, variance.
struct View {
  vec3 c;
  float w, r;      // weight, 1/variance
  bool masked;
  float textured;  // the texture term of the variance
};

View ReadView(uvec2 texel, uint i) {
  const uvec2 t = imageLoad(views, ivec3(texel, i)).xy;
  View view;
  // Unseen views weigh exactly 0: the loops below select rather than `continue` (a
  // `continue` per view made lavapipe's composite a fifth slower; bench/RESULTS.md).
  view.w = ViewWeight(t);
  if (!(view.w > 0.0)) view.w = 0.0;
  view.masked = ViewMasked(t);
  const vec4 gain = gains[i], offset = offsets[i];
  view.c = gain.xyz * ViewColour(t) + offset.xyz;
  const float g = gain.w * ViewTexture(t);
  view.textured = pc.delta2 * g * g;
  // A sample averaging m pixels carries 1/m of their noise. (Its loss still saturates at
  // K, not m·K: clutter that covers many pixels is not made costlier to explain, which
  // would reward hypotheses that grow over it; docs/internals/LIKELIHOOD.md.)
  view.r = 1.0 / (pc.sigma2 / max(ViewMass(t), 1.0) + view.textured);
  return view;
}

// The texel's views, read once (lavapipe's R32G32_UINT image loads are dear).
View texel_views[kViews];
View LoadView(uvec2 texel, uint i) { return texel_views[i]; }

// A view's loss: quadratic up to e² = kFlat·K, then saturating smoothly (with a continuous
// slope) to K: ρ = T + (K − T)(1 − e^(−(e² − T)/(K − T))) beyond T. Views that agree as well
// as noise allows cost exactly their χ², and only outliers need an exp.
float Loss(float e2) {
  const float t = kFlat * pc.outlier, s = pc.outlier - t;
  return e2 <= t ? e2 : t + s * (1.0 - exp((t - e2) / s));
}

// Σ w_i ρ(e²_i) at consensus `mean`, and the number of outlier views (e² > K).
void LossAtMean(uvec2 texel, vec3 mean, out float chi2, out uint outliers) {
  chi2 = 0.0;
  outliers = 0u;
  for (uint i = 0u; i < kViews; ++i) {
    const View view = LoadView(texel, i);
    const vec3 d = view.c - mean;
    const float e2 = view.w > 0.0 ? dot(d, d) * view.r : 0.0;
    chi2 += view.w * Loss(e2);
    outliers += e2 > pc.outlier ? 1u : 0u;
  }
}

// One texel's scalars; `m` is its interior-mask value (0 no surface, 1 exterior, 2 interior).
// `robust` (a constant at each call, so the compiler drops what it skips): run the
// reweighting and the saturating loss; without it the loss is the plain χ², exact while every
// view lies within the flat top, and `needs_rounds` says where one does not.
Scalars CompositeTexel(uvec2 texel, uint m, const bool robust, out bool needs_rounds) {
  Scalars mine = ZeroScalars();
  needs_rounds = false;
  vec3 mean = vec3(0.0);
  float chi2 = 0.0, expected = 0.0, texture_share = 0.0;
  uint n = 0u, outliers = 0u, masked = 0u;
  if (m == 2u) {
    mine.interior = 1u;
  } else if (m == 1u) {
    float sw = 0.0, share = 0.0, sp = 0.0, spw = 0.0;
    vec3 spc = vec3(0.0), single = vec3(0.0);
    for (uint i = 0u; i < kViews; ++i) {
      const View view = ReadView(texel, i);
      texel_views[i] = view;
      masked += view.masked ? 1u : 0u;
      const bool seen = view.w > 0.0;
      n += seen ? 1u : 0u;
      sw += view.w;
      const float p = seen ? view.w * view.r : 0.0;
      share += p * view.textured;
      sp += p;
      spw += p * view.w;
      spc += p * view.c;
      single = seen ? view.c : single;
    }
    if (n >= 2u) {
      // Consensus: the precision-weighted mean, reweighted by Welsch weights e^(−e²/K)
      // that are flat (1) up to e² = kFlat·K and relative to the best-agreeing view beyond
      // (so a texel whose views all disagree keeps a finite mean): a view far from the
      // others (an occluder the scene lacks, a highlight) stops pulling it. When every view
      // is within the flat top of the plain mean, that mean is the consensus.
      mean = spc / sp;
      // The loss's expectation under the noise model: a view's residual from the plain
      // precision-weighted mean has variance a_i·v_i per channel, a_i = 1 − 2p_i/P + Σp_j w_j/(v_i P²),
      // and Σ w_i·3a_i = 3(Σw − Σwp/P). (The loss's saturation beyond kFlat·K lowers it by
      // under 0.3 %: docs/internals/LIKELIHOOD.md.)
      expected = 3.0 * max(sw - spw / sp, 0.0);
      const float flat_top = kFlat * pc.outlier;
      float farthest = 0.0;
      for (uint i = 0u; i < kViews; ++i) {
        const View view = LoadView(texel, i);
        const vec3 d = view.c - mean;
        const float e2 = view.w > 0.0 ? dot(d, d) * view.r : 0.0;
        chi2 += view.w * e2;
        farthest = max(farthest, e2);
      }
      needs_rounds = farthest > flat_top;
      if (robust) for (uint round = 0u; round < kRounds; ++round) {
        float closest = 3.0e38;
        for (uint i = 0u; i < kViews; ++i) {
          const View view = LoadView(texel, i);
          const vec3 d = view.c - mean;
          closest = min(closest, view.w > 0.0 ? dot(d, d) * view.r : 3.0e38);
        }
        const float base = max(closest, flat_top);
        float rp = 0.0;
        vec3 rpc = vec3(0.0);
        for (uint i = 0u; i < kViews; ++i) {
          const View view = LoadView(texel, i);
          const vec3 d = view.c - mean;
          const float omega = exp((base - max(dot(d, d) * view.r, flat_top)) / pc.outlier);
          const float p = view.w > 0.0 ? omega * view.w * view.r : 0.0;
          rp += p;
          rpc += p * view.c;
        }
        mean = rpc / rp;
      }
      if (robust) LossAtMean(texel, mean, chi2, outliers);
      // Views that all disagree are one event, not many: the texel is not what the cameras
      // see (something the scene lacks stands on it). It costs one average view's
      // saturation beyond the expectation, so hiding it gains no more than that.
      chi2 = min(chi2, expected + pc.outlier * sw / float(n));
      texture_share = share / sw;
      mine.sum_squares = chi2 * pc.sigma2;
      mine.dof = expected;
      mine.seen_multi = 1u;
      mine.views = n;
      mine.outlier_views = outliers;
    } else if (masked > 0u) {
      // A camera sees it, but a mask (the user's, clutter) hides it there and leaves fewer
      // than two to compare: unknown, not unverifiable surface; neither compared nor charged.
      mean = single;
      mine.masked = 1u;
    } else if (n == 1u) {
      mean = single;
      mine.seen_once = 1u;
      // What its view would cost were it an outlier: no texel can gain by escaping where
      // only one camera sees it (the cap above bounds every compared texel's excess by an
      // average view's saturation).
      mine.unverified = pc.outlier * sw;
    } else {
      mine.seen_none = 1u;
    }
  }
  if (kWriteImages != 0u) {
    imageStore(composite_out, ivec2(texel), vec4(mean, float(n)));
    imageStore(deviation_out, ivec2(texel), vec4(chi2, expected, m == 2u ? 1.0 : 0.0, m != 0u ? 1.0 : 0.0));
    imageStore(noise_out, ivec2(texel), vec4(texture_share, float(outliers), float(n), float(masked)));
  }
  return mine;
}

// Row r's sum_squares into a[r / 4][r % 4] (kRows <= 16), by selects: indexed at run time,
// a float[kRows] went to lavapipe's per-lane scratch memory and cost the `house` composite
// more than the robust pass saved.
void KeepRow(inout vec4 a[4], uint r, float v) {
  const uint q = r >> 2u, c = r & 3u;
  const bvec4 put = equal(uvec4(0u, 1u, 2u, 3u), uvec4(c));
  a[0] = q == 0u ? mix(a[0], vec4(v), put) : a[0];
  a[1] = q == 1u ? mix(a[1], vec4(v), put) : a[1];
  a[2] = q == 2u ? mix(a[2], vec4(v), put) : a[2];
  a[3] = q == 3u ? mix(a[3], vec4(v), put) : a[3];
}

void main() {
  for (uint i = 0u; i < kViews; ++i) {
    gains[i] = photometric[2u * i];
    offsets[i] = photometric[2u * i + 1u];
  }
  // Two passes over the column. lavapipe runs a shader's `if` under a lane mask, every
  // branch for every SIMD group, but leaves a loop once no lane goes on; so the texels whose
  // views do not all agree within the flat top (a few per column) are redone robustly in a
  // loop of their own, instead of every texel paying for the rounds (house: composite 3.1 ->
  // 2.7 ms, bench/RESULTS.md). Each texel's sum_squares is kept and added in row order at
  // the end: bit-identical to one pass.
  Scalars mine = ZeroScalars();
  const uvec2 tile = tiles[pc.tile_offset + gl_WorkGroupID.x];
  const uint x = tile.x * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  const uint y0 = tile.y * kRows;
  vec4 sum_squares[4];
  for (uint k = 0u; k < 4u; ++k) sum_squares[k] = vec4(0.0);
  uint pending = 0u;  // bit r: row r needs the robust pass
  // The rows' mask values, 2 bits each, and the rows to visit: the exterior surface texels
  // (for dumps every texel, whose images show the interior too); interior texels are only
  // counted. A loop over the visited rows leaves the rows off the surface out where no lane
  // of the SIMD group needs them (house composite −6 %); their terms were zero, so the sums
  // are as before.
  uint marks = 0u, visit = 0u;
  for (uint r = 0u; r < kRows; ++r) {
    if (x < pc.size && y0 + r < pc.size) {
      const uint m = imageLoad(mask, ivec2(x, y0 + r)).r;
      marks |= (m & 3u) << (2u * r);
      visit |= kWriteImages != 0u || m == 1u ? 1u << r : 0u;
      mine.interior += kWriteImages == 0u && m == 2u ? 1u : 0u;
    }
  }
  while (visit != 0u) {
    const uint r = uint(findLSB(visit));
    visit &= visit - 1u;
    bool needs_rounds;
    Scalars texel = CompositeTexel(uvec2(x, y0 + r), (marks >> (2u * r)) & 3u, false, needs_rounds);
    KeepRow(sum_squares, r, texel.sum_squares);
    texel.sum_squares = 0.0;
    mine = AddScalars(mine, texel);
    pending |= needs_rounds ? 1u << r : 0u;
  }
  while (pending != 0u) {
    const uint r = uint(findLSB(pending));
    pending &= pending - 1u;
    bool unused;
    const Scalars texel = CompositeTexel(uvec2(x, y0 + r), 1u, true, unused);
    KeepRow(sum_squares, r, texel.sum_squares);
    mine.outlier_views += texel.outlier_views;
  }
  for (uint k = 0u; k < 4u; ++k)
    for (uint c = 0u; c < 4u; ++c) mine.sum_squares += sum_squares[k][c];
  const Scalars total = ReduceSubgroup(mine);
  if (subgroupElect()) {
    partials[pc.partial_offset + gl_WorkGroupID.x] = total;
  }
}
