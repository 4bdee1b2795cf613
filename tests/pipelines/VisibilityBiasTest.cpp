// §7.4: without the χ² sample-size correction the likelihood prefers a hypothesis that
// hides surface; with it, the truth. A textured sign stands in front of the cameras; the
// wrong hypothesis turns it to face away from all of them. It occludes the same ground, but
// its own texels become back-facing and drop out of the comparison, and with them their
// noise: −S/2σ² rewards that. With the correction, texels at the noise level are neutral
// and the occlusion prior (surface no view sees) decides for the truth.

#include <gtest/gtest.h>

#include <cmath>

#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"
#include "tests/pipelines/SignScene.h"

namespace vkr {
namespace {

using test::GpuTest;

TEST_F(GpuTest, ChiSquareCorrectionStopsHiddenSurfaceFromWinning) {
  test::TempDir dir;
  const Scene scene = test::SignScene(device(), dir);

  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 512;
  options.levels = 1;
  options.weights = ViewWeights::Uniform;
  options.model.sigma = 16.0;
  // Only the occlusion prior of §7.1 (one degree of freedom per unseen texel), so that the χ²
  // correction's own effect shows; the default also charges texels one view sees (checked last).
  const double default_unverified = options.model.unverified_penalty;
  options.model.unverified_penalty = 0.0;
  const std::vector<std::vector<double>> batch = {{90.0}, {-90.0}};
  auto evaluate = [&](bool correction) {
    options.model.chi2_correction = correction;
    SurfaceLikelihood likelihood(device(), scene, options);
    return likelihood.Evaluate(batch);
  };
  const std::vector<Evaluation> plain = evaluate(false), corrected = evaluate(true);
  const Evaluation &truth = plain[0], &hidden = plain[1];
  // The wrong hypothesis really hides surface: fewer texels compared, more seen by none.
  EXPECT_LT(hidden.scalars.dof, 0.95 * truth.scalars.dof);
  EXPECT_GT(hidden.scalars.seen_none, truth.scalars.seen_none + 500);
  EXPECT_GT(plain[1].total(), plain[0].total()) << "without the correction hiding the sign should look better";
  EXPECT_GT(corrected[0].total(), corrected[1].total()) << "with the correction the truth should win";
  options.model.unverified_penalty = default_unverified;
  const std::vector<Evaluation> defaults = evaluate(true);
  EXPECT_GT(defaults[0].total(), defaults[1].total()) << "with the default occlusion prior too";
}

}  // namespace
}  // namespace vkr
