// The polish at the finer atlas (apps/FinerAtlasPolish.h) finds the mode of the likelihood at
// twice the atlas's side, starting from the run's MAP, and measures how far it lies in
// posterior sds.
// On photographs of the box at its truth: from the truth it stays put, from a MAP five sds
// off in one parameter it climbs back and names that parameter; and it says why it skips.

#include <gtest/gtest.h>

#include <cmath>

#include "apps/FinerAtlasPolish.h"
#include "apps/SceneTarget.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr::app {
namespace {

namespace fs = std::filesystem;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

class FinerAtlasPolishTest : public test::GpuTest {
 protected:
  // The box's photographs at quarter size, and its scene reading them with a 64² atlas.
  void SetUp() override {
    GpuTest::SetUp();
    SynthOptions synth;
    synth.scene_file = kBox / "scene.json";
    synth.at_file = kBox / "truth.json";
    synth.output_dir = dir_ / "images";
    synth.scale = 0.25;
    synth.atlas = 256;
    SynthesiseImages(synth, device());
    overrides_ = {{"cameras", (dir_ / "images/cameras.json").string()},
                  {"images", (dir_ / "images").string()},
                  {"likelihood.atlas", "64"}};
    scene_ = LoadSearchScene(kBox / "scene.json", overrides_);
    truth_ = scene_.ValuesFromFile(kBox / "truth.json");
  }

  // A finished run's summary with its MAP at `map` and posterior sds of 0.5 % of each
  // parameter's prior width.
  opt::SamplerSummary Summary(const std::vector<double>& map) const {
    opt::SamplerSummary summary;
    summary.map = map;
    summary.calibration = {{"kappa", 1.0}};
    for (size_t i = 0; i < scene_.parameters.size(); ++i) {
      opt::ParameterSummary p;
      p.name = scene_.parameters[i].name;
      p.map = map[i];
      p.sd = 0.005 * (scene_.parameters[i].prior.b - scene_.parameters[i].prior.a);
      summary.parameters.push_back(p);
    }
    return summary;
  }

  test::TempDir dir_;
  std::vector<SceneOverride> overrides_;
  Scene scene_;
  std::vector<double> truth_;
};

TEST_F(FinerAtlasPolishTest, FromTheTruthTheModeAtTheDoubledAtlasStaysWithinTheIntervals) {
  const opt::SamplerSummary summary = Summary(truth_);
  const FinerAtlasPolish check = PolishAtFinerAtlas(device(), scene_, overrides_, summary, 60, true);
  ASSERT_TRUE(check.ran) << check.skipped;
  EXPECT_EQ(check.atlas, 128);
  EXPECT_GT(check.evaluations, 0);
  EXPECT_LT(check.MaxShiftSd(), kFinerAtlasShiftSd) << "worst " << check.worst;
  EXPECT_FALSE(check.Moved());
  EXPECT_TRUE(FinerAtlasNote(check, summary).empty());
}

TEST_F(FinerAtlasPolishTest, AMapOffTheModeIsFoundAndNamed) {
  const int w = scene_.ParameterIndex("w");
  ASSERT_GE(w, 0);
  std::vector<double> off = truth_;
  const double sd = 0.005 * (scene_.parameters[size_t(w)].prior.b - scene_.parameters[size_t(w)].prior.a);
  off[size_t(w)] += 5.0 * sd;
  const opt::SamplerSummary summary = Summary(off);
  const FinerAtlasPolish check = PolishAtFinerAtlas(device(), scene_, overrides_, summary, 60, true);
  ASSERT_TRUE(check.ran) << check.skipped;
  EXPECT_EQ(check.worst, w);
  EXPECT_LT(check.shift_sd[size_t(w)], -kFinerAtlasShiftSd);  // back towards the truth
  EXPECT_NEAR(check.map[size_t(w)], truth_[size_t(w)], 2.0 * sd);
  EXPECT_TRUE(check.Moved());
  const std::string note = FinerAtlasNote(check, summary);
  EXPECT_NE(note.find("polished at a 128² atlas"), std::string::npos) << note;
  EXPECT_NE(note.find("(w "), std::string::npos) << note;
  EXPECT_NE(note.find("--set likelihood.atlas=128"), std::string::npos) << note;
  const nlohmann::json json = ToJson(check, summary);
  EXPECT_TRUE(json["moved"].get<bool>());
  EXPECT_LT(json["shift_sd"]["w"].get<double>(), -kFinerAtlasShiftSd);
}

TEST_F(FinerAtlasPolishTest, SaysWhyItSkips) {
  const opt::SamplerSummary summary = Summary(truth_);
  EXPECT_FALSE(PolishAtFinerAtlas(device(), scene_, overrides_, summary, 0, true).ran);
  EXPECT_EQ(PolishAtFinerAtlas(device(), scene_, overrides_, opt::SamplerSummary(), 60, true).skipped,
            "the run has no MAP");
  std::vector<SceneOverride> image = overrides_;
  image.push_back({"likelihood.kind", "image"});
  const Scene image_scene = LoadSearchScene(kBox / "scene.json", image);
  EXPECT_NE(PolishAtFinerAtlas(device(), image_scene, image, summary, 60, true).skipped.find("no atlas"),
            std::string::npos);
  std::vector<SceneOverride> large = overrides_;
  large.push_back({"likelihood.atlas", "2048"});
  const Scene large_scene = LoadSearchScene(kBox / "scene.json", large);
  EXPECT_NE(PolishAtFinerAtlas(device(), large_scene, large, summary, 60, true).skipped.find("2048²"),
            std::string::npos);
}

}  // namespace
}  // namespace vkr::app
