// The polish at the finer atlas (recon/FinerAtlasPolish.h) finds the mode of the likelihood at
// twice the atlas's side, starting from the run's MAP, and measures how far it lies in
// posterior sds.
// On photographs of the box at its truth: from the truth it stays put, from a MAP five sds
// off in one parameter it climbs back and names that parameter; and it says why it skips.

#include <gtest/gtest.h>

#include <cmath>

#include "recon/FinerAtlasPolish.h"
#include "recon/SearchSetup.h"
#include "pipelines/rendering/ViewRendering.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr::recon {
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

  // A finished run's summary with its MAP at `map`, posterior sds of 0.5 % of each
  // parameter's prior width, and 95 % intervals of ±1.96 sds about the MAP.
  opt::SamplerSummary Summary(const std::vector<double>& map) const {
    opt::SamplerSummary summary;
    summary.map = map;
    summary.calibration = {{"kappa", 1.0}};
    for (size_t i = 0; i < scene_.parameters.size(); ++i) {
      opt::ParameterSummary p;
      p.name = scene_.parameters[i].name;
      p.map = map[i];
      p.sd = 0.005 * (scene_.parameters[i].prior.b - scene_.parameters[i].prior.a);
      p.mean = map[i];
      p.q025 = map[i] - 1.96 * p.sd;
      p.q975 = map[i] + 1.96 * p.sd;
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

  // Adopted, the MAP takes the interval with it: the truth, 5 sds outside the chains'
  // interval, lies inside the moved one, of the same width.
  opt::SamplerSummary adopted = summary;
  AdoptPolishedMap(check, scene_, &adopted);
  EXPECT_EQ(adopted.map, check.map);
  const opt::ParameterSummary& before = summary.parameters[size_t(w)];
  const opt::ParameterSummary& after = adopted.parameters[size_t(w)];
  EXPECT_GT(before.q025, truth_[size_t(w)]);
  EXPECT_LE(after.q025, truth_[size_t(w)]);
  EXPECT_GE(after.q975, truth_[size_t(w)]);
  EXPECT_NEAR(after.q975 - after.q025, before.q975 - before.q025, 1e-12);
  EXPECT_DOUBLE_EQ(after.interval_shift, check.map[size_t(w)] - off[size_t(w)]);
  for (const opt::ParameterSummary& p : adopted.parameters) {
    EXPECT_LE(p.q025, p.map) << p.name;
    EXPECT_GE(p.q975, p.map) << p.name;
  }
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

// The move keeps the interval inside the parameter's support, and without a polish nothing
// moves.
TEST(AdoptPolishedMap, TheMovedIntervalStaysInsideThePriorAndTheBounds) {
  Scene scene;
  scene.parameters.resize(2);
  scene.parameters[0].name = "a";
  scene.parameters[0].prior = {Prior::Kind::Uniform, 0.0, 1.0};
  scene.parameters[1].name = "b";
  scene.parameters[1].prior = {Prior::Kind::Normal, 0.0, 1.0};
  scene.parameters[1].bounds = std::make_pair(-0.5, 0.5);
  opt::SamplerSummary summary;
  summary.map = {0.9, 0.3};
  for (size_t i = 0; i < 2; ++i) {
    opt::ParameterSummary p;
    p.name = scene.parameters[i].name;
    p.map = summary.map[i];
    p.mean = summary.map[i];
    p.q025 = summary.map[i] - 0.05;
    p.q975 = summary.map[i] + 0.05;
    summary.parameters.push_back(p);
  }
  FinerAtlasPolish polish;
  polish.map_at_atlas = summary.map;
  polish.map = {0.97, 0.48};

  opt::SamplerSummary unchanged = summary;
  AdoptPolishedMap(polish, scene, &unchanged);  // did not run
  EXPECT_EQ(unchanged.map, summary.map);
  EXPECT_EQ(unchanged.parameters[0].q975, summary.parameters[0].q975);
  EXPECT_EQ(unchanged.parameters[0].interval_shift, 0.0);

  polish.ran = true;
  AdoptPolishedMap(polish, scene, &summary);
  EXPECT_EQ(summary.map, polish.map);
  EXPECT_NEAR(summary.parameters[0].q025, 0.92, 1e-12);
  EXPECT_EQ(summary.parameters[0].q975, 1.0);  // the uniform prior's end, not 1.02
  EXPECT_NEAR(summary.parameters[0].interval_shift, 0.07, 1e-12);
  EXPECT_NEAR(summary.parameters[1].q025, 0.43, 1e-12);
  EXPECT_EQ(summary.parameters[1].q975, 0.5);  // the bound (the normal prior has none), not 0.53
  EXPECT_NEAR(summary.parameters[1].mean, 0.48, 1e-12);
}

}  // namespace
}  // namespace vkr::recon
