// Image-space warp pass (thesis §4.2–4.4), fragment stage, shared by image_warp.frag and
// image_warp_dump.frag (which also writes the synthetic image s_{s,t}, thesis Figs 4.5–4.8).
//
// Per pixel of the target camera t where t sees the front of a surface: project the
// surface point into the source camera s; where s sees it too (in front of s, inside its
// image, facing it, and not occluded according to s's depth map) sample r_s there — the
// synthetic image s_{s,t} — and compare it with r_t at the pixel. The result is the pixel
// pair's χ² (≥ 0), or kNotSeenBySource (−1) where only t sees the surface; pixels where t
// sees no surface keep the clear value (−2).
//
// Noise model (pipelines/model/Evaluation.h, docs/IMAGE_SPACE.md): r_t at the pixel carries noise
// σ², the sample of r_s ν_s σ² (ν_s < 1 because bilinear interpolation and prefiltering
// average pixels), and each image δ²|∇I|² more for a projection uncertain by δ pixels. So
// the difference of the two has variance σ² (1 + ν_s + b_t² + b_s²) per channel with
// b = δ|∇I|/σ — 2σ² for two raw pixels on a flat texture — and
//   χ² = ‖r_t − s_{s,t}‖² / (σ² (1 + ν_s + b_t² + b_s²)),  capped at 3·cap,
// has expectation 3 (its degrees of freedom) at the truth.
#include "image_warp_push.glsl"

layout(set = 0, binding = 2) uniform sampler2D source_reference;  // r_s: mips = pyramid, alpha = |∇I|
layout(set = 0, binding = 3) uniform sampler2D source_depth;      // s's depth map at this level, nearest
layout(set = 0, binding = 4) uniform sampler2D target_reference;  // r_t, read texel by texel
// 1 where r_s / r_t may be compared: their masks and lens borders (ReferenceImages.h), the
// same mips as the references. Read only where the camera has one (PairWarpPass.cpp).
layout(set = 0, binding = 5) uniform sampler2D source_validity;
layout(set = 0, binding = 6) uniform sampler2D target_validity;
layout(constant_id = 0) const uint kCheckTarget = 0u;
layout(constant_id = 1) const uint kCheckSource = 0u;

layout(location = 0) in vec4 clip_s;
layout(location = 1) in vec3 world;
layout(location = 2) in vec3 normal;

layout(location = 0) out float result;
#ifdef WRITE_SYNTHETIC
layout(location = 1) out vec4 synthetic;  // rgb: s_{s,t}, a: 1 where compared
#endif

const float kNotSeenBySource = -1.0;

// Noise variance of a bilinear sample relative to one texel's: Σ w² over the four weights.
float BilinearVariance(vec2 uv, int mip) {
  const vec2 f = fract(uv * vec2(textureSize(source_reference, mip)) - 0.5);
  const vec2 g = f * f + (1.0 - f) * (1.0 - f);
  return g.x * g.y;
}

void main() {
  result = kNotSeenBySource;
#ifdef WRITE_SYNTHETIC
  synthetic = vec4(0.0);
#endif
  const vec4 t = cameras[pc.target].centre_fx_fy;
  const vec4 s = cameras[pc.source].centre_fx_fy;
  const vec3 n = normalize(normal);
  const float cos_t = dot(n, normalize(t.xyz - world));
  // t sees the back of a face: no surface it could observe (the surface likelihood's rule).
  if (cos_t <= 0.0) discard;
  // t's pixel is masked or outside its undistorted frame: t observed nothing here.
  if (kCheckTarget != 0u) {
    const ivec2 last_t = textureSize(target_reference, int(pc.level)) - 1;
    if (texelFetch(target_validity, min(ivec2(gl_FragCoord.xy), last_t), int(pc.level)).r < 0.999) discard;
  }

  const float z_s = clip_s.w;  // depth in s
  if (z_s <= pc.near) return;
  const vec2 ndc = clip_s.xy / z_s;
  if (abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return;
  const vec3 to_s = s.xyz - world;
  const float cos_s = dot(n, normalize(to_s));
  if (cos_s <= 0.0) return;
  const vec2 uv = ndc * 0.5 + 0.5;
  // Shadow-map test in s (§4.3) with the slope-scaled tolerance of view_texture.frag: across
  // one pixel a surface tilted by θ changes depth by about z·tanθ / f.
  const float tan_s = min(sqrt(max(1.0 - cos_s * cos_s, 0.0)) / cos_s, 10.0);
  const float pixel_s = exp2(pc.level) / sqrt(s.w);
  if (pc.near / z_s < texture(source_depth, uv).r * (1.0 - pc.depth_tolerance - 1.5 * tan_s * pixel_s)) return;

  // The footprint of t's pixel (at this level) in s's full-resolution pixels: its surface
  // area 4^level z_t² / (f_t² cos θ_t), seen from s at f_s² cos θ_s / z_s². Where it covers
  // several pixels of s, sample the pyramid level that averages them (LOD ½ log₂ footprint),
  // never finer than the level compared.
  const float z_t = 1.0 / gl_FragCoord.w;
  const float footprint = exp2(2.0 * pc.level) * (s.w / t.w) * (z_t * z_t) / (z_s * z_s) * (cos_s / cos_t);
  const float top = float(textureQueryLevels(source_reference) - 1);
  const float lod = max(min(0.5 * log2(max(footprint, 1e-12)), top), pc.level);
  const vec4 rs = textureLod(source_reference, uv, lod);
  if (kCheckSource != 0u && textureLod(source_validity, uv, lod).r < 0.999) return;  // touches masked pixels
  const int level = int(pc.level);
  const ivec2 last = textureSize(target_reference, level) - 1;
  const vec4 rt = texelFetch(target_reference, min(ivec2(gl_FragCoord.xy), last), level);

  // ν_s: the bilinear weights of the finer mip read, and ¼ per level of prefiltering above
  // the compared level (a box filter's factor; the pyramid's binomial averages a little more).
  const float nu_s = BilinearVariance(uv, int(lod)) * exp2(-2.0 * (lod - pc.level));
  // b² = δ²|∇I|²/σ², from the gradient of the signal: the stored |∇I| is measured on the
  // noisy image, whose central differences add σ²·4^−m to |∇I|² at mip m (exact at m = 0,
  // the box filter's factor above it). Left in, that noise would count twice.
  const float g2 = pc.position_sd_over_sigma * pc.position_sd_over_sigma;
  const float inv_sigma2 = pc.inv_sigma2;
  const float b2_t = g2 * max(rt.a * rt.a - exp2(-2.0 * pc.level) / inv_sigma2, 0.0);
  const float b2_s = g2 * max(rs.a * rs.a - exp2(-2.0 * lod) / inv_sigma2, 0.0);
  const vec3 d = rt.rgb - rs.rgb;
  result = min(dot(d, d) * pc.inv_sigma2 / (1.0 + nu_s + b2_t + b2_s), 3.0 * pc.cap);
#ifdef WRITE_SYNTHETIC
  synthetic = vec4(rs.rgb, 1.0);
#endif
}
