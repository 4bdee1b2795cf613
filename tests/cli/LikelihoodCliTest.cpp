// `vkrecon likelihood` as a user meets it, on the `box` asset at quarter size: one evaluation
// prints every field, a sweep of x writes the CSV contract and peaks at the truth, --dump
// writes readable textures of the atlas size, and bad input exits 2 with one line.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::ExpectBadInput;
using test::Quote;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";
constexpr int kAtlas = 128;

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, sep);) parts.push_back(part);
  return parts;
}

// Quarter-size reference images of the box at its truth, made once for the whole suite.
class LikelihoodCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    const auto r = RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " +
                              Quote(kBox / "truth.json") + " --scale 0.25 -o " + Quote(*dir_ / "images"));
    ASSERT_EQ(r.exit_status, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  // `vkrecon likelihood` on the small images, at the truth unless `at` says otherwise.
  static std::string Command(const std::string& extra, const std::string& at = "") {
    return kVkrecon + " likelihood " + Quote(kBox / "scene.json") + " --at " +
           (at.empty() ? Quote(kBox / "truth.json") : at) + " --set cameras=" +
           Quote(*dir_ / "images/cameras.json") + " --set images=" + Quote(*dir_ / "images") +
           " --set likelihood.atlas=" + std::to_string(kAtlas) + " " + extra;
  }
  static test::TempDir* dir_;
};
test::TempDir* LikelihoodCli::dir_ = nullptr;

TEST_F(LikelihoodCli, OneEvaluationPrintsEveryField) {
  const auto r = RunCommand(Command("-q"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  for (const char* field : {"log_likelihood", "log_occlusion_prior", "total", "sum_squares", "dof",
                            "seen_multi", "seen_once", "seen_none", "interior", "level", "chi2_per_dof"})
    EXPECT_NE(r.out.find(std::string(field) + " "), std::string::npos) << field << " missing in:\n" << r.out;
  // Noise-free images at the truth: the per-dof χ² is small and finite.
  for (const std::string& line : Split(r.out, '\n'))
    if (line.rfind("chi2_per_dof", 0) == 0) {
      const double chi2 = std::stod(line.substr(line.find_last_of(' ') + 1));
      EXPECT_TRUE(std::isfinite(chi2)) << line;
      EXPECT_LT(chi2, 1.0) << line;
    }
}

TEST_F(LikelihoodCli, SweepWritesTheCsvContractAndPeaksAtTheTruth) {
  test::TempDir out;
  const auto r = RunCommand(Command("--sweep x=-0.5:0.5:11 -o " + Quote(out / "sweep.csv")));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<std::string> lines = Split(test::ReadText(out / "sweep.csv"), '\n');
  ASSERT_EQ(lines.size(), 12u);  // header + one row per step
  EXPECT_EQ(lines[0].rfind("value,loglik,", 0), 0u) << lines[0];
  EXPECT_EQ(lines[0],
            "value,loglik,log_likelihood,log_occlusion_prior,sum_squares,dof,seen_multi,seen_once,"
            "seen_none,interior,log_edges,edge_length");
  const size_t columns = Split(lines[0], ',').size();
  double best_value = 0.0, best = -INFINITY;
  for (size_t k = 1; k < lines.size(); ++k) {
    const std::vector<std::string> cells = Split(lines[k], ',');
    ASSERT_EQ(cells.size(), columns) << lines[k];
    const double value = std::stod(cells[0]), loglik = std::stod(cells[1]);
    EXPECT_NEAR(value, -0.5 + 0.1 * double(k - 1), 1e-12);
    EXPECT_TRUE(std::isfinite(loglik)) << lines[k];
    if (loglik > best) best = loglik, best_value = value;
  }
  EXPECT_LE(std::abs(best_value - 0.12), 0.1 + 1e-9) << "peak at x = " << best_value;
  // The plot lies beside the CSV.
  const Image plot = LoadImage(out / "sweep.png");
  EXPECT_GT(plot.width, 0);
}

TEST_F(LikelihoodCli, SweepToStdoutWritesThePlotOnlyWhenAsked) {
  test::TempDir out;
  const auto r = RunCommand(Command("-q --sweep w=0.6:1.0:3 --level 1 --plot " + Quote(out / "w.png")));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<std::string> lines = Split(r.out, '\n');
  ASSERT_EQ(lines.size(), 4u) << r.out;
  EXPECT_EQ(lines[0].rfind("value,loglik,", 0), 0u);
  EXPECT_EQ(lines[3].rfind("1,", 0), 0u) << lines[3];  // HI exactly
  EXPECT_TRUE(fs::exists(out / "w.png"));
}

TEST_F(LikelihoodCli, DumpWritesReadableTexturesOfTheAtlasSize) {
  test::TempDir out;
  const auto r = RunCommand(Command("-q --dump " + Quote(out / "dump")));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("log_likelihood"), std::string::npos);
  const Scene scene = LoadScene(kBox / "scene.json", {}, {.require_images = false});
  ASSERT_FALSE(scene.cameras.empty());
  for (const CameraModel& c : scene.cameras) {
    const Image view = LoadImage(out / ("dump/view_" + c.name + ".exr"));
    EXPECT_EQ(view.width, kAtlas) << c.name;
    EXPECT_EQ(view.height, kAtlas) << c.name;
  }
  for (const char* name : {"composite.exr", "deviation.exr", "composite.png", "deviation.png"}) {
    const Image image = LoadImage(out / "dump" / name);
    EXPECT_EQ(image.width, kAtlas) << name;
    EXPECT_EQ(image.height, kAtlas) << name;
  }
  // The deviation holds data: χ² ≥ 0 everywhere, some surface (alpha 1) and some texels with dof.
  const Image deviation = LoadImage(out / "dump/deviation.exr");
  int surface = 0, with_dof = 0;
  for (int y = 0; y < deviation.height; ++y)
    for (int x = 0; x < deviation.width; ++x) {
      const float* p = deviation.At(x, y);
      EXPECT_GE(p[0], 0.0f);
      surface += p[3] > 0.5f;
      with_dof += SrgbToLinear(p[1]) > 2.5f;  // the file stores d_t itself (no transfer curve)
    }
  EXPECT_GT(surface, 100);
  EXPECT_GT(with_dof, 100);
  EXPECT_TRUE(fs::exists(out / "dump/evaluation.json"));
}

TEST_F(LikelihoodCli, ProfilePrintsPassTimes) {
  const auto r = RunCommand(Command("-q --profile --set sampler.batch=2 --level 2"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  for (const char* field : {"gpu_ms.depth", "gpu_ms.total", "hypotheses_per_s", "profile_batch         2"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " missing in:\n" << r.out;
}

TEST_F(LikelihoodCli, BadInputExitsTwoWithOneLine) {
  ExpectBadInput(RunCommand(Command("--sweep z=0:1:5")), {"--sweep", "'z'"});
  ExpectBadInput(RunCommand(Command("--sweep x=1:0:5")), {"--sweep", "x=1:0:5"});
  ExpectBadInput(RunCommand(Command("--sweep x=0:1")), {"--sweep", "x=0:1"});
  ExpectBadInput(RunCommand(Command("--sweep x=a:b:c")), {"--sweep", "x=a:b:c"});
  ExpectBadInput(RunCommand(Command("--sweep x=0:0.5:1")), {"--sweep", "N"});
  ExpectBadInput(RunCommand(Command("--sweep x=-2:0.5:5")), {"--sweep", "uniform [-0.5, 0.5]"});
  ExpectBadInput(RunCommand(Command("--level 3")), {"--level"});
  ExpectBadInput(RunCommand(Command("--level -1")), {"--level"});
  ExpectBadInput(RunCommand(kVkrecon + " likelihood " + Quote(kBox / "scene.json")), {"--at"});
  ExpectBadInput(RunCommand(Command("--set likelihood.kind=volume")), {"likelihood.kind"});
  ExpectBadInput(RunCommand(Command("--dump d --sweep x=0:1:3")), {"--dump"});
}

TEST(LikelihoodHelp, ListedAndDocumented) {
  const auto top = RunCommand(kVkrecon + " --help");
  EXPECT_NE(top.out.find("  likelihood  "), std::string::npos) << top.out;
  const auto r = RunCommand(kVkrecon + " likelihood --help");
  EXPECT_EQ(r.exit_status, 0);
  for (const char* option : {"--at", "--sweep", "--dump", "--profile", "--level", "--no-correction", "--plot"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace vkr
