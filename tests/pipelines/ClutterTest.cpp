// Clutter masks (ClutterMasks.h): at the truth of photographs that show a pole the scene
// leaves out, the regions of outlier views drawn back into the photographs cover the pole's
// pixels — what `synth --mask-nodes` knows to be the pole — and little else; photographs of
// exactly the scene give (almost) no clutter; and masking the clutter moves no profile.

#include <gtest/gtest.h>

#include "pipelines/likelihood/ClutterMasks.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"
#include "tests/common/GpuTest.h"
#include "tests/pipelines/RealCameraScenes.h"

namespace vkr::test {
namespace {

// Over all cameras: the share of the pole's pixels (0 in the true mask) that the clutter
// mask covers, and the share of the other pixels it covers.
struct Overlap {
  double pole = 0.0, rest = 0.0;
};
Overlap Compare(const Scene& scene, const ClutterMasks& clutter) {
  double pole = 0, pole_hit = 0, rest = 0, rest_hit = 0;
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    const Image truth = LoadImage(scene.cameras[i].mask);
    const Image& found = clutter.masks[i];
    for (size_t p = 0; p < truth.rgba.size(); p += 4) {
      const bool is_pole = truth.rgba[p] < 0.5f, masked = found.rgba[p] < 0.5f;
      (is_pole ? pole : rest) += 1.0;
      (is_pole ? pole_hit : rest_hit) += masked;
    }
  }
  return {pole_hit / pole, rest_hit / rest};
}

// One level of a 128² atlas, at the photographs' noise.
SurfaceLikelihoodOptions SmallOptions(const Scene& scene) {
  SurfaceLikelihoodOptions options = SurfaceLikelihoodOptions::FromScene(scene);
  options.atlas = 128;
  options.levels = 1;
  options.model.sigma = 4.0;
  return options;
}

TEST_F(GpuTest, ClutterMasksCoverWhatTheSceneLeavesOut) {
  TempDir dir;
  std::vector<double> truth;
  ShootBox(device(), {std::nullopt, true, 4.0}, dir, true, &truth);
  const Scene with_masks = ReloadBox({std::nullopt, true, 4.0}, dir, true);  // for the pole's true mask
  const Scene scene = ReloadBox({std::nullopt, true, 4.0}, dir, false);
  SurfaceLikelihood likelihood(device(), scene, SmallOptions(scene));
  const ClutterMasks clutter = FindClutter(device(), likelihood, truth);
  ASSERT_EQ(clutter.masks.size(), scene.cameras.size());
  const Overlap o = Compare(with_masks, clutter);
  std::printf("  pole pixels masked %.0f %%, other pixels %.2f %%\n", 100 * o.pole, 100 * o.rest);
  EXPECT_GT(o.pole, 0.5) << "most of the pole is found";
  EXPECT_LT(o.rest, 0.02) << "and little else";

  // Masking it leaves the truth's evaluation neither worse nor with fewer compared texels
  // than it loses to the pole.
  const Evaluation before = likelihood.Evaluate({truth})[0];
  likelihood.SetClutterMasks(clutter.masks);
  const Evaluation after = likelihood.Evaluate({truth})[0];
  EXPECT_LT(after.scalars.outlier_views, before.scalars.outlier_views / 2);
  EXPECT_GT(after.scalars.masked, 0u);
  EXPECT_GT(after.scalars.seen_multi, 0.9 * before.scalars.seen_multi);
}

TEST_F(GpuTest, PhotographsOfExactlyTheSceneHaveNoClutter) {
  TempDir dir;
  std::vector<double> truth;
  const Scene scene = ShootBox(device(), {std::nullopt, false, 4.0}, dir, false, &truth);
  SurfaceLikelihood likelihood(device(), scene, SmallOptions(scene));
  const ClutterMasks clutter = FindClutter(device(), likelihood, truth);
  double worst = 0.0;
  for (double share : clutter.share) worst = std::max(worst, share);
  std::printf("  largest share masked %.3f %%\n", 100 * worst);
  EXPECT_LT(worst, 0.01);
}

}  // namespace
}  // namespace vkr::test
