#pragma once
// How a camera turns light into stored values, one photograph at a time: auto-exposure and
// white balance scale each channel (gain), the black level shifts them (offset), and the
// tone curve bends them (gamma). Photographs of one scene differ in all three; `synth`
// draws each camera's from a spread so tests see what real photo sets look like.

#include <cstdint>
#include <random>

#include "engine/image/Image.h"

namespace vkr {

struct Exposure {
  double gain[3] = {1.0, 1.0, 1.0};  // per channel
  double offset = 0.0;               // added after the gain, encoded [0,1] scale
  double gamma = 1.0;                // applied to the encoded value before the gain

  // Encoded c → clamp(gain · c^gamma + offset, 0, 1).
  double Apply(double encoded, int channel) const;
};

// A random exposure around the identity with relative spread s ∈ [0, 1): overall gain
// uniform in [1 − s, 1 + s], each channel's white balance within ±s/5 of it, offset uniform
// in ±s·43/255 and gamma log-uniform in [e^(−0.64 s), e^(0.64 s)]. At s = 0.35: gain
// 0.65–1.35, offset ±15 (0–255) and gamma 0.8–1.25, what auto-exposure does between shots.
Exposure RandomExposure(double spread, std::mt19937_64& rng);

// Applies `exposure` to the RGB of every pixel (alpha unchanged).
void ApplyExposure(const Exposure& exposure, Image& image);

}  // namespace vkr
