// The bar of the surface likelihood (docs/internals/LIKELIHOOD.md, "Profiles"): on each bundled
// asset, at noise σ = 0 and σ = 16, the profile of every parameter (the others at the truth, 41
// steps across its prior range) peaks within one step of the truth. Small images (quarter size,
// 160×120) and a 128² atlas keep it to seconds on lavapipe.

#include <gtest/gtest.h>

#include <cmath>

#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SynthesisedAsset.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;

struct ProfileCase {
  std::string asset;
  double noise;
};

class SurfaceProfile : public test::GpuTest, public ::testing::WithParamInterface<ProfileCase> {};

TEST_P(SurfaceProfile, EveryParameterPeaksWithinOneStepOfTheTruth) {
  const ProfileCase c = GetParam();
  test::TempDir dir;
  std::vector<double> truth;
  const Scene scene = test::SynthesisedScene(device(), c.asset, c.noise, dir, &truth);
  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 128;
  options.levels = 1;
  options.max_batch = 41;
  // σ of the model matches the noise (a floor of 4 for noise-free images: anti-aliasing
  // and resampling still leave a few grey levels of disagreement).
  options.model.sigma = std::max(4.0, c.noise);
  SurfaceLikelihood likelihood(device(), scene, options);
  constexpr int kSteps = 41;
  for (size_t p = 0; p < scene.parameters.size(); ++p) {
    const Parameter& param = scene.parameters[p];
    ASSERT_EQ(param.prior.kind, Prior::Kind::Uniform) << "the assets use uniform priors";
    const double lo = param.prior.a, hi = param.prior.b, step = (hi - lo) / (kSteps - 1);
    std::vector<std::vector<double>> batch(kSteps, truth);
    for (int k = 0; k < kSteps; ++k) batch[k][p] = lo + k * step;
    const std::vector<Evaluation> e = likelihood.Evaluate(batch);
    int best = 0;
    for (int k = 1; k < kSteps; ++k)
      if (e[k].total() > e[best].total()) best = k;
    const double peak = lo + best * step;
    EXPECT_LE(std::abs(peak - truth[p]), step * 1.0001)
        << c.asset << " σ=" << c.noise << ": " << param.name << " peaks at " << peak << ", truth "
        << truth[p] << " (step " << step << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(Assets, SurfaceProfile,
                         ::testing::Values(ProfileCase{"box", 0}, ProfileCase{"box", 16},
                                           ProfileCase{"house", 0}, ProfileCase{"house", 16},
                                           ProfileCase{"stairs", 0}, ProfileCase{"stairs", 16},
                                           ProfileCase{"poster", 0}, ProfileCase{"poster", 16}),
                         [](const auto& info) {
                           return info.param.asset + "_noise" + std::to_string(int(info.param.noise));
                         });

}  // namespace
}  // namespace vkr
