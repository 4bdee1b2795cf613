#version 460
// Colour of the surface from the atlas (albedo for synth, composite for render); alpha 1
// marks covered pixels. Mode 1 writes the interpolated world position instead, which the
// tests use to check the projection to a hundredth of a pixel. Mode 2 lights the albedo
// like a photograph (synth): a directional sun with cast shadows plus ambient sky light,
// applied in linear light to the encoded albedo (docs/reference/COLOUR.md).
#extension GL_GOOGLE_include_directive : require
#include "novel_view_push.glsl"

layout(set = 0, binding = 1) uniform sampler2D atlas;
// The scene's depth seen from the sun (reversed, orthographic; pipelines/rendering/SunLight.h), read
// with depth comparison off: the shader compares itself, over 3×3 texels (soft edges).
layout(set = 0, binding = 2) uniform sampler2D shadow_map;
layout(std140, set = 0, binding = 3) uniform Lighting {
  mat4 shadow_from_world;  // world → [-1,1]² × depth of the shadow map
  vec4 to_sun;             // unit direction towards the sun (xyz), its strength (w)
  vec4 params;             // ambient strength (x), depth bias (y), shadow-map texel (z)
} light;

layout(location = 0) in vec2 atlas_uv;
layout(location = 1) in vec3 world_position;
layout(location = 2) in vec3 world_normal;
layout(location = 0) out vec4 colour;

vec3 SrgbToLinear(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}
vec3 LinearToSrgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

// Share of the sun this point receives: 1 lit, 0 in shadow (3×3 percentage closer).
float Sunlit(vec3 world, float cos_sun) {
  const vec4 p = light.shadow_from_world * vec4(world, 1.0);
  const vec2 uv = p.xy * 0.5 + 0.5;
  // Reversed depth: larger is nearer the sun. The bias grows on surfaces grazing the light.
  const float bias = light.params.y * (1.0 + 4.0 * sqrt(max(1.0 - cos_sun * cos_sun, 0.0)) / max(cos_sun, 0.1));
  float lit = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float occluder = texture(shadow_map, uv + vec2(dx, dy) * light.params.z).r;
      lit += p.z >= occluder - bias ? 1.0 : 0.0;
    }
  return lit / 9.0;
}

void main() {
  if (pc.mode == 1u) {
    colour = vec4(world_position, 1.0);
    return;
  }
  const vec3 albedo = texture(atlas, atlas_uv).rgb;
  if (pc.mode == 0u) {
    colour = vec4(albedo, 1.0);
    return;
  }
  // Both sides of a face are lit as the side facing the camera would be.
  vec3 n = normalize(world_normal);
  const float cos_sun = dot(n, light.to_sun.xyz);
  const float direct = cos_sun > 0.0 ? light.to_sun.w * cos_sun * Sunlit(world_position, cos_sun) : 0.0;
  colour = vec4(LinearToSrgb(SrgbToLinear(albedo) * (light.params.x + direct)), 1.0);
}
