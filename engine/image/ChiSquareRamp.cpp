#include "engine/image/ChiSquareRamp.h"

#include <algorithm>
#include <iterator>

namespace vkr {

void ChiSquareRamp(double v, float rgb[3]) {
  struct Stop {
    double at;
    float c[3];
  };
  static constexpr Stop kStops[] = {{0.0, {0.05f, 0.05f, 0.45f}},
                                    {1.0, {0.10f, 0.75f, 0.25f}},
                                    {2.0, {1.00f, 0.90f, 0.10f}},
                                    {4.0, {0.85f, 0.05f, 0.05f}}};
  v = std::clamp(v, 0.0, 4.0);
  for (size_t k = 1; k < std::size(kStops); ++k) {
    if (v > kStops[k].at && k + 1 < std::size(kStops)) continue;
    const double t = (v - kStops[k - 1].at) / (kStops[k].at - kStops[k - 1].at);
    for (int c = 0; c < 3; ++c) rgb[c] = float(kStops[k - 1].c[c] + t * (kStops[k].c[c] - kStops[k - 1].c[c]));
    return;
  }
}

}  // namespace vkr
