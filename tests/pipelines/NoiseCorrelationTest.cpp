// κ from the residuals' own correlation (NoiseCorrelation.h): independent noise counts once,
// noise that a filter spreads over k×k texels counts k² times, and texels a view does not
// count never enter.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "pipelines/likelihood/NoiseCorrelation.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace vkr {
namespace {

constexpr int kSide = 128;

// Standard normal noise per channel, summed over k×k windows (k = 1: independent texels),
// every texel counted.
Image FilteredNoise(int k, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  const int n = kSide + k - 1;
  std::vector<float> white(size_t(n) * n * 3);
  for (float& v : white) v = normal(rng);
  Image out(kSide, kSide, 1.0f);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x)
      for (int c = 0; c < 3; ++c) {
        float s = 0.0f;
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i) s += white[(size_t(y + j) * n + x + i) * 3 + c];
        out.At(x, y)[c] = s;
      }
  return out;
}

TEST(NoiseCorrelation, IndependentNoiseCountsOnce) {
  const NoiseCorrelationEstimate e = ResidualCorrelation({FilteredNoise(1, 1), FilteredNoise(1, 2)}, 6);
  EXPECT_GE(e.kappa, 1.0);
  EXPECT_LT(e.kappa, 1.25);
  ASSERT_EQ(e.rings.size(), 7u);
  EXPECT_DOUBLE_EQ(e.rings[0], 1.0);
  EXPECT_LT(std::abs(e.rings[1]), 0.02);
  EXPECT_DOUBLE_EQ(e.samples, 2.0 * kSide * kSide * 3);
}

TEST(NoiseCorrelation, NoiseSpreadOverThreeByThreeTexelsCountsNineTimes) {
  // ρ(dx, dy) = (3 − |dx|)(3 − |dy|)/9 for |dx|, |dy| < 3: Σρ = 9, nothing beyond ring 2.
  const NoiseCorrelationEstimate e = ResidualCorrelation({FilteredNoise(3, 3), FilteredNoise(3, 4)}, 6);
  EXPECT_GT(e.kappa, 8.0);
  EXPECT_LT(e.kappa, 10.0);
  EXPECT_NEAR(e.rings[1], (4 * 6.0 / 9 + 4 * 4.0 / 9) / 8, 0.05);  // edge and corner neighbours
  EXPECT_LT(std::abs(e.rings[4]), 0.03);
  // A window too small for the spread misses part of it.
  EXPECT_LT(ResidualCorrelation({FilteredNoise(3, 3)}, 1).kappa, 7.0);
}

TEST(NoiseCorrelation, TexelsAViewDoesNotCountNeverEnter) {
  Image noise = FilteredNoise(1, 5);
  const double alone = ResidualCorrelation({noise}, 4).kappa;
  // The right half: left out, and filled with one large value that would correlate perfectly.
  for (int y = 0; y < kSide; ++y)
    for (int x = kSide / 2; x < kSide; ++x) {
      float* e = noise.At(x, y);
      e[0] = e[1] = e[2] = 1000.0f;
      e[3] = 0.0f;
    }
  const NoiseCorrelationEstimate half = ResidualCorrelation({noise}, 4);
  EXPECT_LT(half.kappa, 1.3);
  EXPECT_NEAR(half.kappa, alone, 0.3);
  EXPECT_DOUBLE_EQ(half.samples, kSide * kSide / 2 * 3.0);
}

TEST(NoiseCorrelation, NoResidualsLeaveKappaOne) {
  EXPECT_DOUBLE_EQ(ResidualCorrelation({}, 6).kappa, 1.0);
  EXPECT_DOUBLE_EQ(ResidualCorrelation({Image(8, 8, 0.0f)}, 6).kappa, 1.0);
}

// One texel seen by two views, one by a single view: only the first has residuals, each view's
// deviation from the consensus over the noise model's sd; an outlier view is left out.
TEST(NoiseCorrelation, ResidualsAreEachViewsStandardisedDeviationFromTheConsensus) {
  SurfaceDump dump;
  for (int v = 0; v < 2; ++v) {
    dump.view_textures.emplace_back(2, 1, 0.0f);
    dump.view_noise.emplace_back(2, 1, 0.0f);
  }
  dump.composite = Image(2, 1, 0.0f);
  // Texel 0: views 0.50 and 0.52 (every channel), consensus 0.51, pixel mass 1, no texture.
  // Texel 1: view 0 alone.
  for (int v = 0; v < 2; ++v) {
    float* c = dump.view_textures[size_t(v)].At(0, 0);
    c[0] = c[1] = c[2] = v == 0 ? 0.50f : 0.52f;
    c[3] = 1.0f;
    dump.view_noise[size_t(v)].At(0, 0)[1] = 1.0f;
  }
  float* lone = dump.view_textures[0].At(1, 0);
  lone[0] = lone[1] = lone[2] = 0.3f;
  lone[3] = 1.0f;
  float* mean = dump.composite.At(0, 0);
  mean[0] = mean[1] = mean[2] = 0.51f;
  mean[3] = 2.0f;
  dump.composite.At(1, 0)[3] = 1.0f;
  LikelihoodModel model;
  model.sigma = 2.55;  // 0.01 on the 0–1 scale
  model.position_sd = 0.0;
  const std::vector<Image> e = StandardisedResiduals(dump, model, PhotometricCorrection::Identity(2));
  ASSERT_EQ(e.size(), 2u);
  EXPECT_NEAR(e[0].At(0, 0)[0], -1.0, 1e-4);
  EXPECT_NEAR(e[1].At(0, 0)[2], 1.0, 1e-4);
  EXPECT_EQ(e[0].At(0, 0)[3], 1.0f);
  EXPECT_EQ(e[0].At(1, 0)[3], 0.0f);
  // A tenth of σ: each view is 10 sds off in every channel, e² = 300 > K = 27.
  model.sigma = 0.255;
  EXPECT_EQ(StandardisedResiduals(dump, model, PhotometricCorrection::Identity(2))[0].At(0, 0)[3], 0.0f);
}

}  // namespace
}  // namespace vkr
