// Image-space warp pass (thesis §4.2–4.4), fragment stage, shared by image_warp.frag and
// image_warp_dump.frag (which also writes the synthetic image s_{s,t}, thesis Figs 4.5–4.8).
//
// Per pixel of the target camera t where t sees the front of a surface, for each source
// camera s of the draw: project the surface point into s; where s sees it too (in front of
// s, inside its image, facing it, and not occluded according to s's depth map) sample r_s
// there — the synthetic image s_{s,t} — and compare it with r_t at the pixel. The result sums
// the pixel pairs' χ² and counts the sources that compared and those that did not see the
// point; pixels where t sees no surface keep the clear value (all 0).
//
// One draw compares t with all its sources, so t's surface is rasterised and tested against
// t's depth map once, not once per pair (docs/internals/IMAGE_SPACE.md "Cost"). No blending: a
// surface coincident with the visible one passes the depth-equal test too and may overwrite the
// pixel, which a sum over draws would count twice.
//
// Noise model (pipelines/model/Evaluation.h, docs/internals/IMAGE_SPACE.md): r_t at the pixel
// carries noise σ², the sample of r_s ν_s σ² (ν_s < 1 because bilinear interpolation and
// prefiltering average pixels), and each image δ²|∇I|² more for a projection uncertain by δ pixels.
// So the difference of the two has variance σ² (1 + ν_s + b_t² + b_s²) per channel with b = δ|∇I|/σ
// — 2σ² for two raw pixels on a flat texture — and
//   χ² = ‖r_t − s_{s,t}‖² / (σ² (1 + ν_s + b_t² + b_s²)),  capped at 3·cap,
// has expectation 3 (its degrees of freedom) at the truth.
#include "image_warp_push.glsl"

// Per source s of the draw (its index in pc.sources): r_s (mips = pyramid, alpha = |∇I|),
// s's depth map at this level (nearest), and 1 where r_s may be compared (its mask and lens
// border, ReferenceImages.h; read only where kCheckSources says s has one). Indexed by
// constants only (SOURCE below), which needs no dynamic-indexing device feature.
layout(set = 0, binding = 2) uniform sampler2D source_reference[kMaxSources];
layout(set = 0, binding = 3) uniform sampler2D source_depth[kMaxSources];
layout(set = 0, binding = 4) uniform sampler2D target_reference;  // r_t, read texel by texel
layout(set = 0, binding = 5) uniform sampler2D source_validity[kMaxSources];
layout(set = 0, binding = 6) uniform sampler2D target_validity;
layout(constant_id = 0) const uint kCheckTarget = 0u;
layout(constant_id = 1) const uint kCheckSources = 0u;  // bit i: source i has a validity image
layout(constant_id = 2) const uint kSources = 1u;       // sources of the draw, ≤ kMaxSources

layout(location = 0) in vec3 world;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 clip_s[kMaxSources];

// r: Σ χ² over the sources that compared, g: how many compared, b: how many did not see
// the point, a: 1 (t sees surface here).
layout(location = 0) out vec4 result;
#ifdef WRITE_SYNTHETIC
layout(location = 1) out vec4 synthetic;  // rgb: s_{s,t} of the draw's first source, a: 1 where compared
#endif

// What t observed at the pixel, shared by every source.
struct TargetPixel {
  vec3 n;         // unit normal
  float cos_t;
  float z_t;      // depth in t
  float fx_fy_t;  // t's fx·fy at full resolution
  vec4 rt;        // r_t, alpha = |∇I|
};

const float kNotSeenBySource = -1.0;

// Noise variance of a bilinear sample relative to one texel's: Σ w² over the four weights.
float BilinearVariance(sampler2D reference, vec2 uv, int mip) {
  const vec2 f = fract(uv * vec2(textureSize(reference, mip)) - 0.5);
  const vec2 g = f * f + (1.0 - f) * (1.0 - f);
  return g.x * g.y;
}

// The pixel pair's χ² of source `i` against t, or kNotSeenBySource; `rs` receives the sample
// of r_s where compared (the synthetic image).
float PairChi2(uint i, sampler2D reference, sampler2D depth, sampler2D validity, bool check_validity,
               const TargetPixel t, out vec3 rs_rgb) {
  rs_rgb = vec3(0.0);
  const vec4 clip = clip_s[i];
  const vec4 s = cameras[pc.sources[i]].centre_fx_fy;
  const float z_s = clip.w;  // depth in s
  if (z_s <= pc.near) return kNotSeenBySource;
  const vec2 ndc = clip.xy / z_s;
  if (abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return kNotSeenBySource;
  const vec3 to_s = s.xyz - world;
  const float cos_s = dot(t.n, normalize(to_s));
  if (cos_s <= 0.0) return kNotSeenBySource;
  const vec2 uv = ndc * 0.5 + 0.5;
  // Shadow-map test in s (§4.3) with the slope-scaled tolerance of view_texture.frag: across
  // one pixel a surface tilted by θ changes depth by about z·tanθ / f.
  const float tan_s = min(sqrt(max(1.0 - cos_s * cos_s, 0.0)) / cos_s, 10.0);
  const float pixel_s = exp2(pc.level) / sqrt(s.w);
  if (pc.near / z_s < texture(depth, uv).r * (1.0 - pc.depth_tolerance - 1.5 * tan_s * pixel_s))
    return kNotSeenBySource;

  // The footprint of t's pixel (at this level) in s's full-resolution pixels: its surface
  // area 4^level z_t² / (f_t² cos θ_t), seen from s at f_s² cos θ_s / z_s². Where it covers
  // several pixels of s, sample the pyramid level that averages them (LOD ½ log₂ footprint),
  // never finer than the level compared.
  const float footprint =
      exp2(2.0 * pc.level) * (s.w / t.fx_fy_t) * (t.z_t * t.z_t) / (z_s * z_s) * (cos_s / t.cos_t);
  const float top = float(textureQueryLevels(reference) - 1);
  const float lod = max(min(0.5 * log2(max(footprint, 1e-12)), top), pc.level);
  const vec4 rs = textureLod(reference, uv, lod);
  if (check_validity && textureLod(validity, uv, lod).r < 0.999) return kNotSeenBySource;  // touches masked pixels

  // ν_s: the bilinear weights of the finer mip read, and ¼ per level of prefiltering above
  // the compared level (a box filter's factor; the pyramid's binomial averages a little more).
  const float nu_s = BilinearVariance(reference, uv, int(lod)) * exp2(-2.0 * (lod - pc.level));
  // b² = δ²|∇I|²/σ², from the gradient of the signal: the stored |∇I| is measured on the
  // noisy image, whose central differences add σ²·4^−m to |∇I|² at mip m (exact at m = 0,
  // the box filter's factor above it). Left in, that noise would count twice.
  const float g2 = pc.position_sd_over_sigma * pc.position_sd_over_sigma;
  const float inv_sigma2 = pc.inv_sigma2;
  const float b2_t = g2 * max(t.rt.a * t.rt.a - exp2(-2.0 * pc.level) / inv_sigma2, 0.0);
  const float b2_s = g2 * max(rs.a * rs.a - exp2(-2.0 * lod) / inv_sigma2, 0.0);
  const vec3 d = t.rt.rgb - rs.rgb;
  rs_rgb = rs.rgb;
  return min(dot(d, d) * pc.inv_sigma2 / (1.0 + nu_s + b2_t + b2_s), 3.0 * pc.cap);
}

// Adds source `i`'s pixel pair to the result.
void AddSource(uint i, sampler2D reference, sampler2D depth, sampler2D validity, bool check_validity,
               const TargetPixel t) {
  vec3 rs;
  const float chi2 = PairChi2(i, reference, depth, validity, check_validity, t, rs);
  if (chi2 >= 0.0) {
    result.r += chi2;
    result.g += 1.0;
#ifdef WRITE_SYNTHETIC
    if (i == 0u) synthetic = vec4(rs, 1.0);
#endif
  } else {
    result.b += 1.0;
  }
}

void main() {
  result = vec4(0.0, 0.0, 0.0, 1.0);
#ifdef WRITE_SYNTHETIC
  synthetic = vec4(0.0);
#endif
  TargetPixel t;
  t.n = normalize(normal);
  const vec4 camera_t = cameras[pc.target].centre_fx_fy;
  t.cos_t = dot(t.n, normalize(camera_t.xyz - world));
  t.fx_fy_t = camera_t.w;
  // t sees the back of a face: no surface it could observe (the surface likelihood's rule).
  if (t.cos_t <= 0.0) discard;
  const int level = int(pc.level);
  const ivec2 pixel = min(ivec2(gl_FragCoord.xy), textureSize(target_reference, level) - 1);
  // t's pixel is masked or outside its undistorted frame: t observed nothing here.
  if (kCheckTarget != 0u && texelFetch(target_validity, pixel, level).r < 0.999) discard;
  t.z_t = 1.0 / gl_FragCoord.w;
  t.rt = texelFetch(target_reference, pixel, level);

  // Constant indices into the arrays; a source beyond kSources is compiled out.
#define SOURCE(i)                                                                                   \
  if (kSources > i)                                                                                 \
    AddSource(i, source_reference[i], source_depth[i], source_validity[i], ((kCheckSources >> i) & 1u) != 0u, t)
  SOURCE(0u);
  SOURCE(1u);
  SOURCE(2u);
  SOURCE(3u);
  SOURCE(4u);
  SOURCE(5u);
  SOURCE(6u);
  SOURCE(7u);
#undef SOURCE
}
