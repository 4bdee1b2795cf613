#ifndef VIEW_TEXEL_GLSL
#define VIEW_TEXEL_GLSL
// One view-specific texel (thesis §5.2) in two 32-bit words of an R32G32_UINT image,
// mirrored by pipelines/ViewTexel.h: the colour the camera saw at 8 bits per channel (the
// references are 8-bit) with the image texture g = |∇I| where it sampled (the composite's
// noise model grows with it), then, as halves, the view's weight w (§6.3; 0 where the
// camera cannot see the texel) and its pixel mass: how many full-resolution pixels the
// prefiltered sample averages (at least one), which sets its noise (Evaluation.h); −1 with
// weight 0 where the camera sees the texel but its photograph is masked there.

uvec2 PackViewTexel(vec3 colour, float texture, float weight, float mass) {
  return uvec2(packUnorm4x8(vec4(colour, texture)), packHalf2x16(vec2(weight, min(mass, 65504.0))));
}

vec3 ViewColour(uvec2 t) { return unpackUnorm4x8(t.x).rgb; }
float ViewTexture(uvec2 t) { return unpackUnorm4x8(t.x).a; }
float ViewWeight(uvec2 t) { return unpackHalf2x16(t.y).x; }
float ViewMass(uvec2 t) { return unpackHalf2x16(t.y).y; }
bool ViewMasked(uvec2 t) { return unpackHalf2x16(t.y).y < 0.0; }
#endif
