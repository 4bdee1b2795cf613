// Real cameras on the command line: `synth --distortion --colmap --mask-nodes` make
// distorted, masked photographs with a COLMAP model that `likelihood` and `render` read
// back; a bad mask, an unsupported lens model or a malformed `distortion` stop with exit
// status 2 and one line naming the file, the field and the problem.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/image/Image.h"
#include "tests/cli/CliTestUtil.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

namespace fs = std::filesystem;
using test::ExpectBadInput;
using test::Quote;
using test::RunCommand;
using test::TempDir;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// `vkrecon likelihood` of the box asset at its truth reading the photographs in `images`
// through `cameras` (a --set value), plus `extra` arguments.
test::CommandResult Likelihood(const fs::path& images, const std::string& cameras, const std::string& extra = "") {
  return RunCommand(kVkrecon + " likelihood " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                    " --set " + Quote("images=" + images.string()) + " --set " + Quote("cameras=" + cameras) +
                    " --set likelihood.atlas=128 --set likelihood.levels=2 " + extra);
}

TEST(RealCameraCli, SynthThroughALensWithMasksReadsBackThroughColmap) {
  TempDir dir;
  const auto synth = RunCommand(kVkrecon + " synth " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                                " --scale 0.25 -o " + Quote(dir / "images") +
                                " --distortion OPENCV:k1=-0.12,k2=0.03 --colmap --mask-nodes ground");
  ASSERT_EQ(synth.exit_status, 0) << synth.err;
  EXPECT_NE(synth.err.find("9 masks in"), std::string::npos) << synth.err;
  for (const char* f : {"images/cam0.png", "images/sparse/cameras.txt", "images/sparse/images.txt", "masks/cam0.png.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_NE(test::ReadText(dir / "images/sparse/cameras.txt").find("1 OPENCV 160 120 140 140 80 60 -0.12 0.03 0 0\n"),
            std::string::npos);
  EXPECT_NE(test::ReadText(dir / "images/cameras.json").find("\"distortion\""), std::string::npos);

  // Masks beside the images folder are found; the ground is masked, so fewer texels compare.
  const std::string colmap = R"({"colmap": ")" + (dir / "images/sparse").string() + R"("})";
  const auto masked = Likelihood(dir / "images", colmap);
  ASSERT_EQ(masked.exit_status, 0) << masked.err;
  fs::create_directories(dir / "none");
  const auto unmasked = Likelihood(dir / "images", colmap, "--set " + Quote("masks=" + (dir / "none").string()));
  ASSERT_EQ(unmasked.exit_status, 0) << unmasked.err;
  auto seen_multi = [](const std::string& table) {
    const size_t at = table.find("seen_multi");
    return at == std::string::npos ? -1L : std::stol(table.substr(table.find_first_not_of(' ', at + 10)));
  };
  EXPECT_GT(seen_multi(masked.out), 300);  // the box alone
  EXPECT_LT(seen_multi(masked.out), seen_multi(unmasked.out) * 3 / 4);

  // render draws through the lens too: its view is the photograph, up to the background
  // (which synth fills and render leaves transparent).
  const auto render = RunCommand(kVkrecon + " render -q " + Quote(kBox / "scene.json") + " --at " +
                                 Quote(kBox / "truth.json") + " --set " + Quote("cameras=" + colmap) +
                                 " --camera cam0 --atlas 2048 -o " + Quote(dir / "view.exr") + " --png");
  ASSERT_EQ(render.exit_status, 0) << render.err;
  const Image view = LoadImage(dir / "view.png"), photo = LoadImage(dir / "images/cam0.png");
  ASSERT_EQ(view.width, photo.width);
  double sum = 0;
  int n = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x)
      if (view.At(x, y)[3] == 1.0f) {
        for (int c = 0; c < 3; ++c) sum += std::abs(view.At(x, y)[c] - photo.At(x, y)[c]) / 3;
        ++n;
      }
  EXPECT_GT(n, view.width * view.height / 2);
  EXPECT_LT(sum / n, 1.5 / 255);
}

TEST(RealCameraCli, BadMasksAreOneLine) {
  TempDir dir;
  ASSERT_EQ(RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                       " --scale 0.25 -o " + Quote(dir / "images")).exit_status, 0);
  const std::string cameras = (dir / "images/cameras.json").string();
  fs::create_directories(dir / "masks");
  WritePng(dir / "masks/cam3.png.png", Image(40, 30, 1.0f));
  ExpectBadInput(Likelihood(dir / "images", cameras), {"scene.json: masks: mask", "cam3.png.png is 40×30 but camera cam3 is 160×120"});
  test::WriteText(dir / "masks/cam3.png.png", "garbage");
  ExpectBadInput(Likelihood(dir / "images", cameras), {"scene.json: masks: cannot read mask", "camera cam3"});
  ExpectBadInput(Likelihood(dir / "images", cameras, "--set masks=nowhere"), {"masks: masks folder", "not found"});
}

TEST(RealCameraCli, UnsupportedOrMalformedLensesAreOneLine) {
  TempDir dir;
  ASSERT_EQ(RunCommand(kVkrecon + " synth -q " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                       " --scale 0.25 -o " + Quote(dir / "images")).exit_status, 0);
  auto cameras = nlohmann::json::parse(test::ReadText(dir / "images/cameras.json"));
  cameras["cameras"][2]["distortion"] = {{"model", "OPENCV_FISHEYE"}, {"k1", 0.1}};
  test::WriteText(dir / "fisheye.json", cameras.dump());
  ExpectBadInput(Likelihood(dir / "images", (dir / "fisheye.json").string()),
                 {"fisheye.json: cameras[2].distortion.model: unknown distortion model 'OPENCV_FISHEYE'"});
  cameras["cameras"][2]["distortion"] = {{"model", "OPENCV"}, {"k1", 0.1}, {"k2", 0}, {"p1", 0}};
  test::WriteText(dir / "missing.json", cameras.dump());
  ExpectBadInput(Likelihood(dir / "images", (dir / "missing.json").string()),
                 {"missing.json: cameras[2].distortion.p2: missing"});

  test::WriteText(dir / "sparse/cameras.txt", "1 THIN_PRISM_FISHEYE 160 120 140 140 80 60 0 0 0 0 0 0 0 0 0 0 0 0\n");
  test::WriteText(dir / "sparse/images.txt", "1 1 0 0 0 0 0 4 1 cam0.png\n");
  ExpectBadInput(Likelihood(dir / "images", R"({"colmap": ")" + (dir / "sparse").string() + R"("})"),
                 {"cameras.txt: line 1: camera model THIN_PRISM_FISHEYE is not supported (supported: "});

  ExpectBadInput(RunCommand(kVkrecon + " synth " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                            " -o " + Quote(dir / "o") + " --distortion OPENCV:k7=1"),
                 {"--distortion", "k1, k2, p1, p2"});
  ExpectBadInput(RunCommand(kVkrecon + " synth " + Quote(kBox / "scene.json") + " --at " + Quote(kBox / "truth.json") +
                            " -o " + Quote(dir / "o") + " --mask-nodes pole"),
                 {"--mask-nodes", "no node named 'pole' (nodes: ground, box)"});
}

}  // namespace
}  // namespace vkr
