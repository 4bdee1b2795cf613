#pragma once
// The host's side of shaders_glsl/view_texel.glsl: one view-specific texel packed into the
// two 32-bit words of the R32G32_UINT view-texture array (dumps and tests unpack it).

#include <cstdint>

#include "pipelines/passes/HalfFloat.h"

namespace vkr {

struct ViewTexel {
  float colour[3] = {0, 0, 0};  // encoded, [0,1], 8 bits each
  float texture = 0.0f;         // |∇I| of the reference where it was sampled, 8 bits
  float weight = 0.0f;          // 0: the camera does not see the texel
  float mass = 0.0f;            // full-resolution pixels the sample averages (≥ 1)
};

inline ViewTexel UnpackViewTexel(uint32_t colour_word, uint32_t weight_word) {
  ViewTexel t;
  for (int c = 0; c < 3; ++c) t.colour[c] = float((colour_word >> (8 * c)) & 255u) / 255.0f;
  t.texture = float(colour_word >> 24) / 255.0f;
  t.weight = HalfToFloat(uint16_t(weight_word & 0xffffu));
  t.mass = HalfToFloat(uint16_t(weight_word >> 16));
  return t;
}

}  // namespace vkr
