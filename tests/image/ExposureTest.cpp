// RandomExposure draws within the ranges it documents, and applying an exposure is the
// gain·c^γ + offset it says, clamped.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/image/Exposure.h"

namespace vkr {
namespace {

TEST(Exposure, RandomExposuresStayInsideTheirDocumentedRanges) {
  std::mt19937_64 rng(5);
  double lo_gain = 9, hi_gain = 0, lo_gamma = 9, hi_gamma = 0;
  for (int k = 0; k < 2000; ++k) {
    const Exposure e = RandomExposure(0.35, rng);
    for (double g : e.gain) {
      EXPECT_GE(g, 0.65 * (1 - 0.07) - 1e-12);
      EXPECT_LE(g, 1.35 * (1 + 0.07) + 1e-12);
      lo_gain = std::min(lo_gain, g), hi_gain = std::max(hi_gain, g);
    }
    EXPECT_LE(std::abs(e.offset * 255.0), 15.05 + 1e-9);
    EXPECT_GE(e.gamma, std::exp(-0.64 * 0.35) - 1e-12);
    EXPECT_LE(e.gamma, std::exp(0.64 * 0.35) + 1e-12);
    lo_gamma = std::min(lo_gamma, e.gamma), hi_gamma = std::max(hi_gamma, e.gamma);
  }
  // …and use them: the draws spread over most of the range.
  EXPECT_LT(lo_gain, 0.7);
  EXPECT_GT(hi_gain, 1.3);
  EXPECT_LT(lo_gamma, 0.82);
  EXPECT_GT(hi_gamma, 1.22);
  // Spread 0 is the identity.
  const Exposure same = RandomExposure(0.0, rng);
  for (double c : {0.0, 0.3, 1.0}) EXPECT_DOUBLE_EQ(same.Apply(c, 1), c);
}

TEST(Exposure, AppliesGainGammaAndOffsetThenClamps) {
  Exposure e;
  e.gain[0] = 1.2;
  e.gain[1] = 0.5;
  e.gain[2] = 1.0;
  e.offset = 0.05;
  e.gamma = 2.0;
  EXPECT_NEAR(e.Apply(0.5, 0), 1.2 * 0.25 + 0.05, 1e-12);
  EXPECT_NEAR(e.Apply(0.5, 1), 0.5 * 0.25 + 0.05, 1e-12);
  EXPECT_DOUBLE_EQ(e.Apply(1.0, 0), 1.0);  // 1.25 clamped
  e.offset = -0.2;
  EXPECT_DOUBLE_EQ(e.Apply(0.1, 2), 0.0);  // negative clamped
}

}  // namespace
}  // namespace vkr
