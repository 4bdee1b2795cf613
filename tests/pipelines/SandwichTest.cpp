// The block sandwich behind κ (NoiseCalibration.h): where the per-texel scores are
// correlated over regions larger than the smallest blocks, κ must measure the regions, not
// the blocks; where they are independent, the choice among block sizes must not inflate it.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "pipelines/likelihood/NoiseCalibration.h"

namespace vkr {
namespace {

constexpr int kSide = 256;  // texels: a 256² atlas, as the assets use
constexpr int kParameters = 2;

// Row-major d × d identity scaled by `s`.
std::vector<double> ScaledIdentity(double s) {
  std::vector<double> m(kParameters * kParameters, 0.0);
  for (int i = 0; i < kParameters; ++i) m[i * kParameters + i] = s;
  return m;
}

// Per parameter, per texel: standard normal scores, constant over square patches of
// `patch` texels per side (1: independent texels).
std::vector<std::vector<double>> Scores(int patch, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const int patches = kSide / patch;
  std::vector<std::vector<double>> gradient(kParameters, std::vector<double>(kSide * kSide));
  for (int i = 0; i < kParameters; ++i) {
    std::vector<double> value(patches * patches);
    for (double& v : value) v = normal(rng);
    for (int y = 0; y < kSide; ++y)
      for (int x = 0; x < kSide; ++x) gradient[i][y * kSide + x] = value[(y / patch) * patches + x / patch];
  }
  return gradient;
}

// Scores constant over 32×32 patches (Scores(kPatch, 11)) and the H⁻¹ that makes their κ 1
// when measured over blocks that hold whole patches: J = 1024²·patches·I there.
constexpr int kPatch = 32;
std::vector<double> InverseCurvatureForPatches() {
  const double patches = double(kSide / kPatch) * (kSide / kPatch);
  return ScaledIdentity(1.0 / (double(kPatch * kPatch) * (kPatch * kPatch) * patches));
}

TEST(Sandwich, IndependentTexelsGiveTheCurvaturesKappaWhateverTheBlocks) {
  // J = N·I per texel-independent unit scores; with H⁻¹ = I/N the sandwich is κ = 1 in
  // expectation at every block size. Taking the largest over sizes may add estimation noise,
  // not a factor of the block area (64 for 64×64 over 8×8).
  const std::optional<BlockSandwich> s =
      SandwichOverBlocks(Scores(1, 7), kSide, ScaledIdentity(1.0 / (kSide * kSide)), kSandwichBlocksAuto);
  ASSERT_TRUE(s.has_value());
  EXPECT_GT(s->kappa, 0.8);
  EXPECT_LT(s->kappa, 1.6);
}

TEST(Sandwich, ScoresCorrelatedOverPatchesAreMeasuredOverBlocksAsLargeAsThePatches) {
  // 32×32 patches of one score each: J over blocks of 32 or more is 1024²·patches·I, over 8×8
  // blocks 16× less. With H⁻¹ for the former, κ must be about 1 — 8×8 blocks alone give 1/16.
  const std::optional<BlockSandwich> s =
      SandwichOverBlocks(Scores(kPatch, 11), kSide, InverseCurvatureForPatches(), kSandwichBlocksAuto);
  ASSERT_TRUE(s.has_value());
  EXPECT_GE(s->block, kPatch);
  EXPECT_GT(s->kappa, 0.5);
  EXPECT_LT(s->kappa, 2.0);
}

TEST(Sandwich, BlocksOfAGivenSizeMeasureOnlyWhatTheyHold) {
  // The same scores over the default 8×8 blocks: each patch counts as 16 independent blocks,
  // so κ comes out about 16× too small — why `sandwich_blocks: auto` exists.
  const std::optional<BlockSandwich> s = SandwichOverBlocks(Scores(kPatch, 11), kSide, InverseCurvatureForPatches(), 8);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->block, 8);
  EXPECT_EQ(s->blocks, (kSide / 8) * (kSide / 8));
  EXPECT_GT(s->kappa, 1.0 / 32);
  EXPECT_LT(s->kappa, 1.0 / 8);
}

TEST(Sandwich, TooFewBlocksLeaveKappaAtOne) {
  // 16×16 texels hold four 8×8 blocks, fewer than the 2d = 6 needed for d = 3.
  std::vector<std::vector<double>> gradient(3, std::vector<double>(16 * 16, 1.0));
  std::vector<double> inverse(9, 0.0);
  for (int i = 0; i < 3; ++i) inverse[i * 3 + i] = 1.0;
  const std::optional<BlockSandwich> s = SandwichOverBlocks(gradient, 16, inverse, kSandwichBlocksAuto);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->blocks, 4);
  EXPECT_EQ(s->kappa, 1.0);
}

TEST(Sandwich, SummedBlocksAddToJAtEverySide) {
  // Texel scores that are zero leave J to the summed blocks (the edge term's, one per camera
  // and edge), here g = ±(2, −1), J = Σ g gᵀ = [[8, −4], [−4, 2]].
  const std::vector<std::vector<double>> zero(kParameters, std::vector<double>(kSide * kSide, 0.0));
  std::vector<std::vector<double>> summed;
  for (int k = 0; k < 2; ++k) summed.push_back({k ? -2.0 : 2.0, k ? 1.0 : -1.0});
  summed.push_back({0.0, 0.0});  // an edge no camera saw carries nothing and is no block
  for (const int side : {8, kSandwichBlocksAuto}) {
    const std::optional<BlockSandwich> s = SandwichOverBlocks(zero, kSide, ScaledIdentity(0.2), side, summed);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->blocks, 2);
    EXPECT_EQ(s->kappa, 1.0);  // fewer than 2d blocks: too few to measure J
  }
  // With texel blocks beside them, both count.
  std::vector<std::vector<double>> ones(kParameters, std::vector<double>(16 * 16, 0.0));
  for (int i = 0; i < kParameters; ++i) ones[i][0] = 1.0;  // one texel in one 8×8 block
  for (int k = 0; k < 4; ++k) summed.push_back({1.0, 1.0});
  const std::optional<BlockSandwich> s = SandwichOverBlocks(ones, 16, ScaledIdentity(1.0), 8, summed);
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->blocks, 1 + 6);
  // J = [[8, −4], [−4, 2]] + 4·[[1,1],[1,1]] + [[1,1],[1,1]] = [[13, 1], [1, 7]]; κ = tr(J)/2.
  EXPECT_DOUBLE_EQ(s->kappa, 10.0);
  EXPECT_EQ(s->j, (std::vector<double>{13.0, 1.0, 1.0, 7.0}));
  // A block of the wrong length is refused.
  EXPECT_FALSE(SandwichOverBlocks(ones, 16, ScaledIdentity(1.0), 8, {{1.0}}).has_value());
}

TEST(Sandwich, MismatchedScoresAreRefused) {
  std::vector<std::vector<double>> gradient = {std::vector<double>(64, 1.0), std::vector<double>(32, 1.0)};
  EXPECT_FALSE(SandwichOverBlocks(gradient, 8, ScaledIdentity(1.0)).has_value());
  EXPECT_FALSE(SandwichOverBlocks({std::vector<double>(64, 1.0)}, 8, ScaledIdentity(1.0)).has_value());
  EXPECT_FALSE(SandwichOverBlocks({std::vector<double>(64, 1.0)}, 8, {1.0}, -8).has_value());
}

// What a run's summary carries is what later steps divide by (the finer-atlas polish, the
// adopted MAP's score); a summary without a calibration scores with κ = 1.
TEST(Sandwich, KappaReadBackFromACalibrationsJson) {
  NoiseCalibration c;
  c.sigma = 6.5;
  c.kappa = 74.25;
  EXPECT_EQ(KappaFromJson(ToJson(c)), 74.25);
  EXPECT_EQ(KappaFromJson(nlohmann::json()), 1.0);
  EXPECT_EQ(KappaFromJson(nlohmann::json::object()), 1.0);
  EXPECT_EQ(KappaFromJson({{"kappa", "auto"}}), 1.0);
}

}  // namespace
}  // namespace vkr
