#version 460
// View-specific texture pass, fragment stage: the colour camera i saw at this texel, its
// weight (§6.3) and the image's texture there, or weight 0 where the camera cannot see it:
// behind the near plane, outside the image, back-facing, or occluded according to the
// depth pass.
#extension GL_GOOGLE_include_directive : require
#include "view_texel.glsl"
#include "view_texture_push.glsl"

layout(set = 0, binding = 1) uniform sampler2D reference;  // mip chain = image pyramid, trilinear
layout(set = 0, binding = 2) uniform sampler2D depth_map;  // nearest filter, reversed depth
layout(set = 0, binding = 3) uniform sampler2D validity;   // reference's mips: 1 = comparable (ReferenceImages.h)
layout(constant_id = 0) const uint kCheckValidity = 0u;    // 0: every pixel counts, binding 3 unread

layout(location = 0) in vec4 clip;
layout(location = 1) in vec3 world;
layout(location = 2) in vec3 normal;
layout(location = 3) flat in float texel_area;  // world area of one full-resolution texel of this chart
layout(location = 0) out uvec2 view;  // view_texel.glsl

void main() {
  view = uvec2(0u);
  const float z = clip.w;  // camera-space depth
  const float near = pc.params.w;
  if (z <= near) return;
  const vec2 ndc = clip.xy / z;
  if (abs(ndc.x) > 1.0 || abs(ndc.y) > 1.0) return;
  const vec3 to_camera = pc.centre.xyz - world;
  const float distance = length(to_camera);
  const float cos_theta = dot(normalize(normal), to_camera / distance);
  if (cos_theta <= 0.0) return;
  const vec2 uv = ndc * 0.5 + 0.5;
  // Reversed depth near/z: larger is nearer. Visible unless the depth pass found a
  // surface nearer than z by more than the tolerance. The depth map holds one depth per
  // pixel centre; across a pixel a surface tilted by θ changes depth by about
  // z·tanθ / f (f in pixels at this level), so the tolerance grows with tanθ — a fixed
  // one leaves stripes of "occluded" texels on oblique surfaces (shadow acne).
  const float tan_theta = min(sqrt(max(1.0 - cos_theta * cos_theta, 0.0)) / cos_theta, 10.0);
  const float pixel = exp2(pc.level) / sqrt(pc.params.x);  // one level pixel, in units of z
  const float tolerance = pc.params.y + 1.5 * tan_theta * pixel;
  if (near / z < texture(depth_map, uv).r * (1.0 - tolerance)) return;
  // The texel's footprint in full-resolution pixels. Where a texel covers several pixels,
  // the colour comes from the pyramid level that averages them (mip LOD ½·log₂ footprint):
  // a point sample would alias, and aliasing disagrees between views like misregistration.
  const float footprint = texel_area * cos_theta * pc.params.x / (z * z);
  const float lod = pc.level + max(0.0, 0.5 * log2(max(footprint, 1e-12)));
  // Masked pixels and the undistorted photograph's empty border are not evidence: a sample
  // that touches any of them (the same uv and LOD) is dropped, never compared as black. It
  // is marked (mass −1), so that a texel the camera would see but for a mask is not taken
  // for surface no camera can check (composite.comp).
  if (kCheckValidity != 0u && textureLod(validity, uv, lod).r < 0.999) {
    view = PackViewTexel(vec3(0.0), 0.0, 0.0, -1.0);
    return;
  }
  float weight = 1.0;
  if (pc.params.z > 0.5) {
    // Angle weight: foreshortening times the footprint (Figs 6.7–6.8), capped at one
    // pixel: a texel smaller than a pixel repeats its neighbours' evidence.
    weight = cos_theta * min(1.0, footprint);
  }
  // Alpha of the reference holds |∇I| (Pyramid.h StoreGradientInAlpha): the composite's
  // noise model for this view grows with it (Evaluation.h).
  const vec4 sampled = textureLod(reference, uv, lod);
  // The sample averages max(1, footprint) pixels of its level, each 4^level of full
  // resolution: its noise variance is that many times smaller than a pixel's.
  view = PackViewTexel(sampled.rgb, sampled.a, weight, max(1.0, footprint) * exp2(2.0 * pc.level));
}
