// `vkrecon compare` as a user meets it (docs/guide/WHICH_SCENE.md): two scenes of one set of
// photographs run under one likelihood into a table whose probabilities sum to 1, a finished
// run read back from its folder, and bad input (a missing file, other photographs) refused
// with exit status 2 before anything runs.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::ExpectBadInput;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kHouse = fs::path(VKRECON_SOURCE_DIR) / "assets/house";

// Quarter-size photographs of the house at its truth in dir/images, noise 8.
bool SynthHouseImages(const fs::path& dir) {
  return RunCommand(kVkrecon + " synth -q " + Quote(kHouse / "scene.json") + " --at " + Quote(kHouse / "truth.json") +
                    " --scale 0.25 --noise 8 -o " + Quote(dir / "images"))
             .exit_status == 0;
}

// An asset's scene file written to `file`, looking at the photographs in `images`.
void WriteSceneOn(const fs::path& asset_scene, const fs::path& images, const fs::path& file) {
  nlohmann::json scene = nlohmann::json::parse(test::ReadText(asset_scene));
  scene["images"] = images.string();
  scene["cameras"] = (images / "cameras.json").string();
  for (nlohmann::json& node : scene["nodes"])
    if (node.contains("albedo")) node["albedo"] = (asset_scene.parent_path() / node["albedo"].get<std::string>()).string();
  std::ofstream(file) << scene.dump();
}

// Every scene on dir/images, small and short: the ladder records 160 iterations of 4 rungs.
std::string Small(const fs::path& dir) {
  return " --set cameras=" + Quote(dir / "images/cameras.json") + " --set images=" + Quote(dir / "images") +
         " --set likelihood.atlas=64 --set likelihood.levels=2 --set sampler.iterations=400"
         " --set sampler.chains=2 --set sampler.batch=4 --rungs 4 -q";
}

TEST(CompareCli, TwoScenesGiveOneTableUnderOneLikelihood) {
  test::TempDir dir;
  ASSERT_TRUE(SynthHouseImages(dir.path()));
  const fs::path out = dir / "out";
  const auto r = RunCommand(kVkrecon + " compare " + Quote(kHouse / "scene.json") + " " + Quote(kHouse / "box.json") +
                            Small(dir.path()) + " -o " + Quote(out));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("| house |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| box |"), std::string::npos) << r.out;
  EXPECT_EQ(test::ReadText(out / "compare.md"), r.out);
  const nlohmann::json table = nlohmann::json::parse(test::ReadText(out / "compare.json"));
  ASSERT_EQ(table["scenes"].size(), 2u);
  double total = 0.0;
  for (const nlohmann::json& row : table["scenes"]) {
    EXPECT_TRUE(row["log_z"].is_number()) << row.dump();
    total += row["probability"].get<double>();
  }
  EXPECT_NEAR(total, 1.0, 1e-9);
  // The box ran with the house run's σ, δ and κ fixed, and both maps say so.
  const nlohmann::json house = nlohmann::json::parse(test::ReadText(out / "house/map.json"));
  const nlohmann::json box = nlohmann::json::parse(test::ReadText(out / "box/map.json"));
  EXPECT_FALSE(house["evidence"]["likelihood"]["kappa_fixed"].get<bool>());
  EXPECT_TRUE(box["evidence"]["likelihood"]["kappa_fixed"].get<bool>());
  EXPECT_TRUE(box["evidence"]["likelihood"]["sigma_fixed"].get<bool>());
  for (const char* key : {"sigma", "position_sd", "kappa"})
    EXPECT_EQ(house["evidence"]["likelihood"][key], box["evidence"]["likelihood"][key]) << key;
  EXPECT_EQ(box["calibration"]["kappa"], house["calibration"]["kappa"]);
  EXPECT_FALSE(box["settings"]["likelihood"]["clutter"].get<bool>());
  // How every run ended, the reference's first, under one header.
  const std::string summary = test::ReadText(out / "summary.csv");
  EXPECT_EQ(summary.rfind("scene,", 0), 0u) << summary;
  EXPECT_EQ(summary.find("scene,", 1), std::string::npos) << summary;
  const size_t house_row = summary.find("\nhouse,"), box_row = summary.find("\nbox,");
  EXPECT_NE(house_row, std::string::npos) << summary;
  EXPECT_NE(box_row, std::string::npos) << summary;
  EXPECT_LT(house_row, box_row) << summary;

  // The finished runs read back from their folders give the same table, without running.
  const auto again = RunCommand(kVkrecon + " compare " + Quote(out / "house") + " " + Quote(out / "box") + " -q -o " +
                                Quote(dir / "again"));
  ASSERT_EQ(again.exit_status, 0) << again.err;
  EXPECT_EQ(again.out, r.out);
}

TEST(CompareCli, BadInputIsRefusedBeforeAnythingRuns) {
  test::TempDir dir;
  ExpectBadInput(RunCommand(kVkrecon + " compare " + Quote(kHouse / "scene.json") + " " + Quote(dir / "nope.json") +
                            " -o " + Quote(dir / "out")),
                 {"nope.json"});
  ExpectBadInput(RunCommand(kVkrecon + " compare " + Quote(kHouse / "scene.json") + " -o " + Quote(dir / "out")),
                 {"scenes"});
  // The house on the house's photographs against the box asset on its own.
  ASSERT_TRUE(SynthHouseImages(dir.path()));
  ASSERT_TRUE(test::SynthBoxImages(dir / "box", ""));
  WriteSceneOn(kHouse / "scene.json", dir / "images", dir / "house.json");
  WriteSceneOn(fs::path(VKRECON_SOURCE_DIR) / "assets/box/scene.json", dir / "box/images", dir / "other.json");
  ExpectBadInput(RunCommand(kVkrecon + " compare " + Quote(dir / "house.json") + " " + Quote(dir / "other.json") +
                            " -o " + Quote(dir / "out")),
                 {"other.json", "cameras", "same photographs"});
  EXPECT_FALSE(fs::exists(dir / "out/house/map.json"));
}

}  // namespace
}  // namespace vkr
