// Chain statistics against cases whose answer is known: iid draws (ESS ≈ n, R̂ ≈ 1), an AR(1)
// chain (ESS ≈ n (1 − φ)/(1 + φ)), chains stuck in different places (R̂ ≫ 1), quantiles.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "optimiser/Random.h"
#include "optimiser/Statistics.h"

namespace vkr::opt {
namespace {

std::vector<std::vector<double>> Iid(int chains, int n, double mean, uint64_t seed) {
  std::vector<std::vector<double>> out(static_cast<size_t>(chains));
  for (int c = 0; c < chains; ++c) {
    Rng rng = Rng::ForStream(seed, uint64_t(c));
    for (int i = 0; i < n; ++i) out[size_t(c)].push_back(mean + rng.Normal());
  }
  return out;
}

std::vector<std::vector<double>> Ar1(int chains, int n, double phi, uint64_t seed) {
  std::vector<std::vector<double>> out(static_cast<size_t>(chains));
  for (int c = 0; c < chains; ++c) {
    Rng rng = Rng::ForStream(seed, uint64_t(c));
    double x = rng.Normal() / std::sqrt(1 - phi * phi);  // stationary start
    for (int i = 0; i < n; ++i) {
      x = phi * x + rng.Normal();
      out[size_t(c)].push_back(x);
    }
  }
  return out;
}

TEST(Statistics, MeanSdQuantile) {
  EXPECT_DOUBLE_EQ(Mean({1, 2, 3, 4}), 2.5);
  EXPECT_DOUBLE_EQ(StandardDeviation({2, 4, 4, 4, 5, 5, 7, 9}), std::sqrt(32.0 / 7.0));
  EXPECT_DOUBLE_EQ(Quantile({5, 1, 4, 2, 3}, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(Quantile({5, 1, 4, 2, 3}, 0.25), 2.0);
  EXPECT_DOUBLE_EQ(Quantile({1, 2, 3, 4}, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(Quantile({1, 2, 3, 4}, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(Quantile({1, 2, 3, 4}, 1.0), 4.0);
  EXPECT_TRUE(std::isnan(Quantile({}, 0.5)));
  EXPECT_TRUE(std::isnan(StandardDeviation({1.0})));
}

TEST(Statistics, IidDrawsHaveEssNearTheirCountAndRhatNearOne) {
  const auto chains = Iid(4, 2000, 0.0, 11);
  const double n = 8000;
  const double ess = EffectiveSampleSize(chains);
  EXPECT_GT(ess, 0.8 * n);
  EXPECT_LT(ess, 1.25 * n);
  EXPECT_LT(SplitRhat(chains), 1.01);
  EXPECT_GT(SplitRhat(chains), 0.99);
}

TEST(Statistics, AutocorrelatedChainHasSmallEss) {
  const double phi = 0.95;
  const auto chains = Ar1(4, 4000, phi, 12);
  const double n = 16000;
  const double expected = n * (1 - phi) / (1 + phi);  // ≈ 410
  const double ess = EffectiveSampleSize(chains);
  EXPECT_LT(ess, 0.1 * n);
  EXPECT_GT(ess, 0.5 * expected);
  EXPECT_LT(ess, 2.0 * expected);
  EXPECT_LT(SplitRhat(chains), 1.05);  // mixing slowly but in one place
}

TEST(Statistics, ChainsInDifferentPlacesHaveLargeRhat) {
  auto chains = Iid(2, 1000, 0.0, 13);
  for (double& x : chains[1]) x += 3.0;
  EXPECT_GT(SplitRhat(chains), 1.5);
  // A chain that drifts (its halves disagree) is caught by the split, even alone.
  std::vector<std::vector<double>> drift(1);
  for (int i = 0; i < 1000; ++i) drift[0].push_back(i < 500 ? 0.01 * (i % 7) : 5.0 + 0.01 * (i % 5));
  EXPECT_GT(SplitRhat(drift), 1.5);
}

TEST(Statistics, UndefinedCasesAreNaNAndMisuseThrows) {
  EXPECT_TRUE(std::isnan(SplitRhat({{1, 2, 3}})));
  EXPECT_TRUE(std::isnan(EffectiveSampleSize({{1, 2, 3}})));
  EXPECT_TRUE(std::isnan(SplitRhat({{1, 1, 1, 1, 1, 1}})));
  EXPECT_TRUE(std::isnan(EffectiveSampleSize({{1, 1, 1, 1, 1, 1}})));
  EXPECT_THROW(SplitRhat({{1, 2, 3, 4}, {1, 2, 3}}), std::invalid_argument);
  EXPECT_THROW(EffectiveSampleSize({{1, 2, 3, 4}, {1, 2, 3}}), std::invalid_argument);
}

// Vehtari et al. (2021): rank normalisation makes R̂ and ESS blind to monotone transforms
// and able to see what the plain statistics miss — chains with one mean but different
// spreads (the folded R̂) — while iid chains pass the 1.01 threshold.
TEST(Statistics, RankNormalizedRhatAndBulkEss) {
  const auto iid = Iid(4, 2000, 0.0, 11);
  EXPECT_LT(RankNormalizedSplitRhat(iid), 1.01);
  EXPECT_NEAR(BulkEffectiveSampleSize(iid), 8000.0, 0.15 * 8000.0);

  // A monotone transform does not change the bulk ESS, and heavy tails do not make R̂ fail
  // (the folded part depends on the scale, so only the bulk is exactly invariant).
  auto transformed = iid;
  for (auto& c : transformed)
    for (double& x : c) x = std::exp(3.0 * x);
  EXPECT_DOUBLE_EQ(BulkEffectiveSampleSize(transformed), BulkEffectiveSampleSize(iid));
  EXPECT_LT(RankNormalizedSplitRhat(transformed), 1.01);

  // One chain with three times the spread: the plain split-R̂ sees nothing, the folded one does.
  auto wide = iid;
  for (double& x : wide[0]) x *= 3.0;
  EXPECT_LT(SplitRhat(wide), 1.02);
  EXPECT_GT(RankNormalizedSplitRhat(wide), 1.05);

  // One chain elsewhere.
  auto shifted = iid;
  for (double& x : shifted[1]) x += 1.0;
  EXPECT_GT(RankNormalizedSplitRhat(shifted), 1.1);

  // AR(1), φ = 0.9: ESS ≈ n (1 − φ)/(1 + φ).
  EXPECT_NEAR(BulkEffectiveSampleSize(Ar1(4, 4000, 0.9, 5)), 16000.0 / 19.0, 0.3 * 16000.0 / 19.0);

  // A trend within each chain (the first half lower than the second): splitting sees it.
  auto trending = iid;
  for (auto& c : trending)
    for (size_t k = 0; k < c.size(); ++k) c[k] += k < c.size() / 2 ? -1.0 : 1.0;
  EXPECT_GT(RankNormalizedSplitRhat(trending), 1.3);
  EXPECT_LT(BulkEffectiveSampleSize(trending), 0.1 * BulkEffectiveSampleSize(iid));

  // Undefined as the plain statistics: too short, or no variance.
  EXPECT_TRUE(std::isnan(RankNormalizedSplitRhat({{1, 2, 3}, {1, 2, 3}})));
  EXPECT_TRUE(std::isnan(BulkEffectiveSampleSize({{1, 1, 1, 1, 1, 1, 1, 1}, {1, 1, 1, 1, 1, 1, 1, 1}})));
}

}  // namespace
}  // namespace vkr::opt
