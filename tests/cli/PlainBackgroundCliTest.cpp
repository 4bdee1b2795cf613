// A house in front of a plain grey cloth (assets/house_cloth: the photographs show two
// chimneys the scene leaves out), reconstructed as a user would, with the likelihood's
// defaults. Surface moved out over the plain cloth looks alike from every camera, so
// photo-consistency cannot say where the block ends; the edge term (on by default) can.
// Quarter size, 300 iterations, a 128² atlas: about a minute on lavapipe. When this was
// written the run gave d 0.816 [0.797, 0.848] (truth 0.8); with `likelihood.edges=false`
// 0.986 [0.838, 0.980], rh 0.403 (truth 0.35) and w 1.064 (truth 1.0): every check below
// fails without the term.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kCloth = fs::path(VKRECON_SOURCE_DIR) / "assets/house_cloth";

TEST(PlainBackgroundCli, TheDefaultRunFindsTheBlockOverAPlainCloth) {
  test::TempDir dir;
  ASSERT_EQ(RunCommand(kVkrecon + " synth -q " + Quote(kCloth / "synth.json") + " --at " +
                       Quote(kCloth / "truth.json") + " --scale 0.25 --noise 8 --seed 1 -o " + Quote(dir / "images"))
                .exit_status,
            0);
  const auto r = RunCommand(kVkrecon + " run -q " + Quote(kCloth / "scene.json") + " --set cameras=" +
                            Quote(dir / "images/cameras.json") + " --set images=" + Quote(dir / "images") +
                            " --set likelihood.atlas=128 --set sampler.iterations=300 -o " + Quote(dir / "run"));
  ASSERT_TRUE(r.exit_status == 0 || r.exit_status == 1) << r.err;  // 1: a diagnosis that is not ok
  const nlohmann::json map = nlohmann::json::parse(test::ReadText(dir / "run/map.json"));
  EXPECT_EQ(map["settings"]["likelihood"]["edges"], true) << "the scene leaves the edge term at its default";
  const nlohmann::json truth = nlohmann::json::parse(test::ReadText(kCloth / "truth.json"));
  const nlohmann::json& p = map["parameters"];
  const double d = truth["d"].get<double>();
  EXPECT_NEAR(p["d"]["map"].get<double>(), d, 0.03) << "the block's depth";
  EXPECT_LE(p["d"]["q025"].get<double>(), d);
  EXPECT_GE(p["d"]["q975"].get<double>(), d);
  EXPECT_NEAR(p["rh"]["map"].get<double>(), truth["rh"].get<double>(), 0.02) << "the roof's height";
  EXPECT_NEAR(p["w"]["map"].get<double>(), truth["w"].get<double>(), 0.02) << "the walls' width";
}

}  // namespace
}  // namespace vkr
