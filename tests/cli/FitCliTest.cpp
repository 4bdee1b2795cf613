// `vkrecon fit` as a user meets it: a MAP-only search on quarter-size box images lands near
// the truth and writes map.json and at_map.json; a coarse-to-fine search spends its budget
// in full-resolution equivalents; bad options are bad input naming the option.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::ExpectBadInput;
using test::Quote;
using test::RunCommand;
using test::SynthBoxImages;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// The box asset on the images in `dir`, with a small atlas (quick on lavapipe; below 128² texels
// the likelihood's mode drifts a few degrees of yaw from the truth).
std::string SmallFit(const test::TempDir& dir, int atlas = 64) {
  return kVkrecon + " fit " + Quote(kBox / "scene.json") + " --set cameras=" + Quote(dir / "images/cameras.json") +
         " --set images=" + Quote(dir / "images") + " --set likelihood.atlas=" + std::to_string(atlas) +
         " --set likelihood.levels=2";
}

nlohmann::json ReadJson(const fs::path& file) { return nlohmann::json::parse(test::ReadText(file)); }

TEST(FitCli, BobyqaLandsNearTheTruthAndWritesAMapOnlyResult) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), " --noise 4"));
  const auto r = RunCommand(SmallFit(dir, 128) + " --method bobyqa --evaluations 150 -o " + Quote(dir / "out"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.err.find("vkrecon fit: level 1"), std::string::npos) << "progress on stderr:\n" << r.err;
  const nlohmann::json map = ReadJson(dir / "out/map.json");
  const nlohmann::json truth = ReadJson(kBox / "truth.json");
  const nlohmann::json scene = ReadJson(kBox / "scene.json");
  EXPECT_TRUE(map.at("map_only").get<bool>());
  EXPECT_EQ(map.at("method"), "bobyqa");
  // Coarse to fine, then restarted at level 0 (each restart listed) while it moves the MAP.
  const auto levels = map.at("levels").get<std::vector<int>>();
  ASSERT_GE(levels.size(), 2u);
  EXPECT_EQ(levels[0], 1);
  for (size_t i = 1; i < levels.size(); ++i) EXPECT_EQ(levels[i], 0);
  EXPECT_EQ(map.at("restarts").get<size_t>(), levels.size() - 2);
  EXPECT_EQ(map.at("settings").at("restarts"), 3);
  EXPECT_LE(map.at("full_resolution_equivalents").get<double>(), 150.0 + 1e-9);
  EXPECT_GT(map.at("evaluations").get<int>(), 20);
  EXPECT_TRUE(std::isfinite(map.at("log_posterior").get<double>()));
  EXPECT_FALSE(map.at("parameters").at("x").contains("sd")) << "MAP only: no intervals";
  // Within 2 % of each prior width of the truth (quarter-size images, a 128² atlas: coarse).
  const nlohmann::json at = ReadJson(dir / "out/at_map.json");
  for (const auto& [name, value] : truth.items()) {
    const auto& range = scene["parameters"][name]["prior"]["uniform"];
    const double width = range[1].get<double>() - range[0].get<double>();
    EXPECT_NEAR(map["parameters"][name]["map"].get<double>(), value.get<double>(), 0.02 * width) << name;
    EXPECT_EQ(at.at(name), map["parameters"][name]["map"]) << name;
  }
}

TEST(FitCli, TheOtherMethodsRunWithinTheirBudget) {
  test::TempDir dir;
  ASSERT_TRUE(SynthBoxImages(dir.path(), ""));
  for (const char* method : {"neldermead", "sbplx", "crs2lm", "isres"}) {
    const fs::path out = dir / method;
    const auto r = RunCommand(SmallFit(dir) + " -q --levels 1 --method " + method + " --evaluations 12 -o " + Quote(out));
    ASSERT_EQ(r.exit_status, 0) << method << ": " << r.err;
    EXPECT_TRUE(r.err.empty()) << "-q: " << r.err;
    const nlohmann::json map = ReadJson(out / "map.json");
    EXPECT_EQ(map.at("method"), method);
    for (const auto& level : map.at("levels")) EXPECT_EQ(level, 0) << method;  // restarts too
    EXPECT_LE(map.at("evaluations").get<int>(), 12) << method;
    EXPECT_GE(map.at("evaluations").get<int>(), 6) << method;
  }
}

TEST(FitCli, BadMethodOrBudgetIsBadInputNamingTheOption) {
  test::TempDir dir;
  const std::string fit = kVkrecon + " fit " + Quote(kBox / "scene.json") + " -o " + Quote(dir / "out");
  ExpectBadInput(RunCommand(fit + " --method simplex"), {"--method", "simplex", "bobyqa"});
  ExpectBadInput(RunCommand(fit + " --evaluations 0"), {"--evaluations"});
  ExpectBadInput(RunCommand(fit + " --evaluations -5"), {"--evaluations"});
  ExpectBadInput(RunCommand(fit + " --evaluations lots"), {"--evaluations"});
  ExpectBadInput(RunCommand(fit + " --levels -1"), {"--levels"});
  ExpectBadInput(RunCommand(fit + " --restarts -1"), {"--restarts"});
  EXPECT_FALSE(fs::exists(dir / "out/map.json"));
  const auto help = RunCommand(kVkrecon + " fit --help");
  EXPECT_EQ(help.exit_status, 0);
  EXPECT_NE(help.out.find("MAP only"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("crs2lm"), std::string::npos) << help.out;
}

}  // namespace
}  // namespace vkr
