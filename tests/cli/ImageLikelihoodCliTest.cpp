// `vkrecon likelihood` with the image-space likelihood (`--set likelihood.kind=image`), on the
// `box` asset at quarter size: one evaluation, a sweep peaking at the truth, --dump writing the
// synthetic images s_{s,t} and consistency images of every ordered camera pair (thesis Figs
// 4.5–4.8), --profile naming the image-space passes, and a kind that does not exist.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::RunCommand;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

std::string Quote(const fs::path& p) { return "'" + p.string() + "'"; }

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class ImageLikelihoodCli : public ::testing::Test {
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
  static std::string Command(const std::string& extra, const std::string& kind = "image") {
    return kVkrecon + " likelihood " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
           " --set cameras=" + Quote(*dir_ / "images/cameras.json") + " --set images=" + Quote(*dir_ / "images") +
           " --set likelihood.kind=" + kind + " " + extra;
  }
  static test::TempDir* dir_;
};
test::TempDir* ImageLikelihoodCli::dir_ = nullptr;

TEST_F(ImageLikelihoodCli, OneEvaluation) {
  const auto r = RunCommand(Command("-q"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("kind                  image"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("seen_none             0\n"), std::string::npos) << r.out;
  for (const std::string& line : Lines(r.out))
    if (line.rfind("chi2_per_dof", 0) == 0) {
      const double chi2 = std::stod(line.substr(line.find_last_of(' ') + 1));
      EXPECT_GT(chi2, 0.0) << line;
      EXPECT_LT(chi2, 1.0) << line;  // noise-free images, σ = 8
    }
}

TEST_F(ImageLikelihoodCli, SweepPeaksAtTheTruth) {
  const auto r = RunCommand(Command("-q --sweep x=-0.5:0.5:11"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<std::string> lines = Lines(r.out);
  ASSERT_EQ(lines.size(), 12u) << r.out;
  double best = -INFINITY, best_x = 0.0;
  for (size_t k = 1; k < lines.size(); ++k) {
    const double x = std::stod(lines[k]), loglik = std::stod(lines[k].substr(lines[k].find(',') + 1));
    if (loglik > best) best = loglik, best_x = x;
  }
  EXPECT_LE(std::abs(best_x - 0.12), 0.1 + 1e-9) << "peak at x = " << best_x;
}

TEST_F(ImageLikelihoodCli, DumpWritesSyntheticAndConsistencyImagesOfEveryPair) {
  test::TempDir out;
  const auto d = RunCommand(Command("-q --dump " + Quote(out / "dump")));
  ASSERT_EQ(d.exit_status, 0) << d.err;
  const Scene scene = LoadScene(kBox / "scene.json", {}, {.require_images = false});
  int pairs = 0;
  for (const CameraModel& t : scene.cameras)
    for (const CameraModel& s : scene.cameras) {
      if (&s == &t) continue;
      ++pairs;
      const std::string pair = t.name + "_from_" + s.name;
      for (const std::string name : {"synthetic_" + pair, "consistency_" + pair})
        for (const char* ext : {".exr", ".png"}) {
          const fs::path file = out / "dump" / (name + ext);
          ASSERT_TRUE(fs::exists(file)) << file;
          const Image image = LoadImage(file);
          EXPECT_EQ(image.width, 160) << file;
          EXPECT_EQ(image.height, 120) << file;
        }
    }
  EXPECT_EQ(pairs, 72);
  EXPECT_TRUE(fs::exists(out / "dump/evaluation.json"));
  EXPECT_FALSE(fs::exists(out / "dump/composite.exr")) << "surface-space textures in an image-space dump";
  // The consistency image holds data: χ² ≥ 0, dof 3 exactly where the synthetic image has
  // alpha 1 (compared), and plenty of compared pixels.
  const Image consistency = LoadImage(out / "dump/consistency_cam0_from_cam1.exr");
  const Image synthetic = LoadImage(out / "dump/synthetic_cam0_from_cam1.exr");
  int compared = 0;
  for (int y = 0; y < consistency.height; ++y)
    for (int x = 0; x < consistency.width; ++x) {
      const float* c = consistency.At(x, y);
      EXPECT_GE(c[0], 0.0f);
      const bool has_dof = SrgbToLinear(c[1]) > 2.5f;  // the file stores the dof itself
      EXPECT_EQ(has_dof, synthetic.At(x, y)[3] > 0.5f) << x << "," << y;
      compared += has_dof;
    }
  EXPECT_GT(compared, 160 * 120 / 3);
}

TEST_F(ImageLikelihoodCli, ProfileNamesTheImageSpacePasses) {
  const auto r = RunCommand(Command("-q --profile --set sampler.batch=2 --level 1"));
  ASSERT_EQ(r.exit_status, 0) << r.err;
  for (const char* field : {"gpu_ms.depth", "gpu_ms.warp", "gpu_ms.compare", "gpu_ms.reduce", "hypotheses_per_s"})
    EXPECT_NE(r.out.find(field), std::string::npos) << field << " missing in:\n" << r.out;
}

TEST_F(ImageLikelihoodCli, UnknownKindIsBadInput) {
  const auto r = RunCommand(Command("-q", "volume"));
  EXPECT_EQ(r.exit_status, 2) << r.err;
  EXPECT_NE(r.err.find("likelihood.kind"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace vkr
