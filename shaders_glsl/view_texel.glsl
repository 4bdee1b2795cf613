#ifndef VIEW_TEXEL_GLSL
#define VIEW_TEXEL_GLSL
// One view-specific texel (thesis §5.2) in two 32-bit words of an R32G32_UINT image,
// mirrored by pipelines/passes/ViewTexel.h: the colour the camera saw at 8 bits per channel (the
// references are 8-bit) with the image texture g = |∇I| where it sampled (the composite's
// noise model grows with it), then, as halves, the view's weight w (§6.3; 0 where the
// camera cannot see the texel) and its pixel mass: how many full-resolution pixels the
// prefiltered sample averages (at least one), which sets its noise (Evaluation.h); −1 with
// weight 0 where the camera sees the texel but its photograph is masked there.

// A half float by its bits: lavapipe's unpackHalf2x16 costs a third of the composite.
// Exact for every finite half.
float HalfToFloat(uint h) {
  const uint magnitude = h & 0x7fffu;
  const float a = (magnitude & 0x7c00u) == 0u ? float(magnitude) * exp2(-24.0)  // subnormal
                                              : uintBitsToFloat((magnitude << 13) + (112u << 23));
  return (h & 0x8000u) != 0u ? -a : a;
}

uvec2 PackViewTexel(vec3 colour, float texture, float weight, float mass) {
  return uvec2(packUnorm4x8(vec4(colour, texture)), packHalf2x16(vec2(weight, min(mass, 65504.0))));
}

vec3 ViewColour(uvec2 t) { return unpackUnorm4x8(t.x).rgb; }
float ViewTexture(uvec2 t) { return unpackUnorm4x8(t.x).a; }
float ViewWeight(uvec2 t) { return HalfToFloat(t.y & 0xffffu); }
float ViewMass(uvec2 t) { return HalfToFloat(t.y >> 16); }
bool ViewMasked(uvec2 t) { return (t.y >> 31) != 0u; }  // only the mass −1 is negative
#endif
