// LikelihoodTarget::ScoreModes (recon/LikelihoodTarget.h): two modes compared without the bias of a
// calibration made at one of them. The case is the peers bench's poster at σ 16, noise seed
// 4, where the chains settled with the column 10 % of its prior too short: calibrated there,
// the clutter masks take out the column's top in the photographs (what that mode fails to
// explain) and the colour correction fits it, and under both it outscores the true poster.
// Scored as ScoreModes scores them, the truth wins; and the target scores as before after.
// RefitAt, what `run` does once it adopts the truth, gives it its own correction and masks.
// The trap needs the edge term off: with it (the default) the column's true top edge keeps
// the truth ahead even under the short column's calibration.

#include <gtest/gtest.h>

#include <memory>

#include "recon/LikelihoodTarget.h"
#include "recon/SearchSetup.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr::recon {
namespace {

namespace fs = std::filesystem;
const fs::path kPoster = fs::path(VKRECON_SOURCE_DIR) / "assets/poster";

// The chains' mode of that run (x, y, diameter, height).
const std::vector<double> kShortColumn = {-0.051884, 0.101007, 0.498159, 1.048527};

class ScoreModesTest : public test::GpuTest {
 protected:
  // The poster's photographs as `vkrecon bench --only peers` makes them, and its scene with
  // the edge term as given.
  Scene PosterScene(const test::TempDir& dir, bool edges) {
    SynthOptions synth;
    synth.scene_file = kPoster / "scene.json";
    synth.at_file = kPoster / "truth.json";
    synth.output_dir = dir / "images";
    synth.noise_sigma = 16.0;
    synth.seed = 4;
    synth.scale = 0.25;
    SynthesiseImages(synth, device());
    return LoadSearchScene(kPoster / "scene.json", {{"cameras", (dir / "images/cameras.json").string()},
                                                    {"images", (dir / "images").string()},
                                                    {"likelihood.sigma", "auto"},
                                                    {"likelihood.edges", edges ? "true" : "false"}});
  }
};

TEST_F(ScoreModesTest, TheEdgeTermKeepsTheTruthAheadUnderTheWrongModesCalibration) {
  test::TempDir dir;
  const Scene scene = PosterScene(dir, true);
  const std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device(), scene, 2);
  LikelihoodTarget target(*likelihood, scene, true, true, dir / "run", true);
  target.Calibrate(kShortColumn, {});
  target.SetLevel(0);
  const std::vector<double> scores = target.Evaluate({kShortColumn, scene.ValuesFromFile(kPoster / "truth.json")});
  EXPECT_GT(scores[1], scores[0]) << "calibrated at the short column, the truth still wins on its edges";
}

TEST_F(ScoreModesTest, MasksAndColoursFittedAtAWrongModeNoLongerProtectIt) {
  test::TempDir dir;
  const Scene scene = PosterScene(dir, false);
  const std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device(), scene, 2);
  LikelihoodTarget target(*likelihood, scene, true, true, dir / "run", true);

  const std::vector<double> truth = scene.ValuesFromFile(kPoster / "truth.json");
  const std::vector<double>& short_column = kShortColumn;
  ASSERT_EQ(scene.ParameterIndex("height"), 3);

  const nlohmann::json calibration = target.Calibrate(short_column, {});
  ASSERT_TRUE(calibration.contains("clutter")) << calibration.dump();
  double masked = 0.0;
  for (double share : calibration["clutter"]["share"]) masked += share;
  EXPECT_GT(masked, 0.0) << "nothing masked at the short column: the case no longer shows the trap";
  target.SetLevel(0);
  const std::vector<double> before = target.Evaluate({short_column, truth});
  ASSERT_GT(before[0], before[1]) << "calibrated at the short column, it should outscore the truth";

  const std::vector<double> scores = target.ScoreModes({short_column, truth});
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_GT(scores[1], scores[0]);

  // The calibration is back as it was: the same values to the bit.
  target.SetLevel(0);
  EXPECT_EQ(target.Evaluate({short_column, truth}), before);

  // Adopted, the truth gets its own colour correction, noise level and masks (what `run`
  // then polishes and writes out with); κ stays the one the chains sampled with.
  const nlohmann::json refit = target.RefitAt(truth);
  EXPECT_EQ(refit.at("kappa"), calibration.at("kappa"));
  EXPECT_NE(refit.at("photometric"), calibration.at("photometric"));
  EXPECT_LT(refit.at("sigma").get<double>(), calibration.at("sigma").get<double>())
      << "the photographs' noise, no longer inflated by the short column's misfit";
  double masked_at_truth = 0.0;
  if (refit.contains("clutter"))
    for (double share : refit["clutter"]["share"]) masked_at_truth += share;
  EXPECT_LT(masked_at_truth, masked) << "the column's top is no clutter at the truth";
  target.SetLevel(0);
  const std::vector<double> refitted = target.Evaluate({short_column, truth});
  EXPECT_GT(refitted[1], refitted[0]);
  EXPECT_GT(refitted[1], before[1]);
  // RestoreCalibration undoes it, to the bit.
  target.RestoreCalibration(calibration);
  target.SetLevel(0);
  EXPECT_EQ(target.Evaluate({short_column, truth}), before);
}

}  // namespace
}  // namespace vkr::recon
