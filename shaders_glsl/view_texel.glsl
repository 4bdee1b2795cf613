#ifndef VIEW_TEXEL_GLSL
#define VIEW_TEXEL_GLSL
// One view-specific texel (thesis §5.2) in two 32-bit words of an R32G32_UINT image,
// mirrored by pipelines/ViewTexel.h: the colour the camera saw at 10 bits per channel (the
// references are 8-bit; their trilinear blend needs a little more), then, as halves, the
// view's weight w (§6.3; 0 where the camera cannot see the texel) and the image texture
// g = |∇I| where it sampled (the composite's noise model grows with it, Evaluation.h).

uvec2 PackViewTexel(vec3 colour, float weight, float texture) {
  const uvec3 c = uvec3(round(clamp(colour, 0.0, 1.0) * 1023.0));
  return uvec2(c.r | (c.g << 10) | (c.b << 20), packHalf2x16(vec2(weight, texture)));
}

vec3 ViewColour(uvec2 t) {
  return vec3(t.x & 1023u, (t.x >> 10) & 1023u, (t.x >> 20) & 1023u) / 1023.0;
}
float ViewWeight(uvec2 t) { return unpackHalf2x16(t.y).x; }
float ViewTexture(uvec2 t) { return unpackHalf2x16(t.y).y; }
#endif
