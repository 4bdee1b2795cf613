#include "engine/image/Exposure.h"

#include <algorithm>
#include <cmath>

namespace vkr {

double Exposure::Apply(double encoded, int channel) const {
  const double bent = std::pow(std::max(encoded, 0.0), gamma);
  return std::clamp(gain[channel] * bent + offset, 0.0, 1.0);
}

Exposure RandomExposure(double spread, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Exposure e;
  const double overall = 1.0 + spread * unit(rng);
  for (double& g : e.gain) g = overall * (1.0 + 0.2 * spread * unit(rng));
  e.offset = spread * 43.0 / 255.0 * unit(rng);
  e.gamma = std::exp(0.64 * spread * unit(rng));
  return e;
}

void ApplyExposure(const Exposure& exposure, Image& image) {
  for (size_t i = 0; i < image.rgba.size(); i += 4)
    for (int c = 0; c < 3; ++c) image.rgba[i + c] = float(exposure.Apply(image.rgba[i + c], c));
}

}  // namespace vkr
