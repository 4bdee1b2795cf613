// Clutter masks (ClutterMasks.h): at the truth of photographs that show a pole the scene
// leaves out, the regions of outlier views drawn back into the photographs cover the pole's
// pixels — what `synth --mask-nodes` knows to be the pole — and little else; photographs of
// exactly the scene give (almost) no clutter; masking the clutter moves no profile; and a
// calibration finds the same masks whatever masks the last one left.

#include <gtest/gtest.h>

#include "pipelines/likelihood/ClutterMasks.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "pipelines/likelihood/NoiseCalibration.h"
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

// A run calibrates at every settling round (NoiseCalibration.h). Were σ estimated with the
// last round's masks in place, it would come out smaller, find more clutter, and masking
// that would make σ smaller still: on real photographs the masks grew round after round and
// κ never settled. Here the last round's masks are exaggerated (the whole left half of every
// photograph) so that a calibration which depends on them cannot hide it.
TEST_F(GpuTest, CalibratingFindsTheSameClutterWhateverTheLastRoundMasked) {
  TempDir dir;
  std::vector<double> truth;
  ShootBox(device(), {std::nullopt, true, 4.0}, dir, true, &truth);
  Scene scene = ReloadBox({std::nullopt, true, 4.0}, dir, false);
  nlohmann::json block = nlohmann::json::parse(scene.settings.count("likelihood") ? scene.settings["likelihood"] : "{}");
  block["atlas"] = 128;
  block["levels"] = 1;
  scene.settings["likelihood"] = block.dump();
  const NoiseCalibration fresh = CalibrateNoise(*MakeLikelihood(device(), scene, {}), truth, {}, 1.0, true, true);

  // The same calibration by a likelihood alike but for the masks it starts with.
  const std::unique_ptr<Likelihood> masked = MakeLikelihood(device(), scene, {});
  std::vector<Image> half = fresh.clutter.masks;
  for (Image& mask : half)
    for (int y = 0; y < mask.height; ++y)
      for (int x = 0; x < mask.width / 2; ++x) std::fill(mask.At(x, y), mask.At(x, y) + 3, 0.0f);
  masked->SetClutterMasks(half);
  const NoiseCalibration again = CalibrateNoise(*masked, truth, {}, 1.0, true, true);

  ASSERT_EQ(again.clutter.share.size(), fresh.clutter.share.size());
  double found = 0.0;
  for (size_t i = 0; i < fresh.clutter.share.size(); ++i) {
    std::printf("  camera %zu: masked %.2f %% fresh, %.2f %% after the half masks\n", i, 100 * fresh.clutter.share[i],
                100 * again.clutter.share[i]);
    EXPECT_NEAR(again.clutter.share[i], fresh.clutter.share[i], 1e-9) << "camera " << i;
    found = std::max(found, fresh.clutter.share[i]);
  }
  EXPECT_GT(found, 0.005) << "the pole is found";
  EXPECT_NEAR(again.sigma, fresh.sigma, 1e-9 * fresh.sigma);
}

}  // namespace
}  // namespace vkr::test
