// The command line as a user meets it: exit status 0 / 2 / 1, one-line errors naming the
// file, field and problem, and synth + render of every bundled asset producing images that
// a standard reader opens with the objects where the cameras say they are.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

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
using test::TempDir;

const std::string kVkrecon = VKRECON_BINARY;
const fs::path kAssets = fs::path(VKRECON_SOURCE_DIR) / "assets";

TEST(Cli, HelpListsEverySubcommand) {
  const auto r = RunCommand(kVkrecon + " --help");
  EXPECT_EQ(r.exit_status, 0);
  for (const char* cmd : {"synth", "render", "devices"}) EXPECT_NE(r.out.find(cmd), std::string::npos);
  EXPECT_EQ(RunCommand(kVkrecon + " synth --help").exit_status, 0);
}

TEST(Cli, UnknownCommandAndMissingOptionsAreBadInput) {
  ExpectBadInput(RunCommand(kVkrecon + " reconstruct"), {"unknown command"});
  ExpectBadInput(RunCommand(kVkrecon + " synth x.json"), {"--at"});
  ExpectBadInput(RunCommand(kVkrecon + " synth x.json --at a.json -o o --noise abc"), {"--noise"});
}

TEST(Cli, DevicesListsLavapipeOrAGpu) {
  const auto r = RunCommand(kVkrecon + " devices");
  EXPECT_EQ(r.exit_status, 0);
  EXPECT_NE(r.out.find("0: "), std::string::npos) << r.out;
}

TEST(Cli, MissingSceneFileIsNamed) {
  TempDir dir;
  ExpectBadInput(RunCommand(kVkrecon + " synth " + Quote(dir / "nope.json") + " --at x.json -o " + Quote(dir / "o")),
                 {"nope.json"});
}

TEST(Cli, MalformedSceneIsNamed) {
  TempDir dir;
  test::WriteText(dir / "scene.json", "{\"version\": 1, \"nodes\": [}");
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(dir / "scene.json") + " -o " + Quote(dir / "v.exr")),
                 {"scene.json"});
}

// 100,000 '[' once took minutes (the reader's work grew with the square of the depth); now
// they are refused at the 65th level, whichever JSON file they are in.
TEST(Cli, DeeplyNestedJsonIsRefusedAtTheNestingLimit) {
  TempDir dir;
  const std::string deep(100000, '[');
  test::WriteText(dir / "scene.json", deep);
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(dir / "scene.json") + " -o " + Quote(dir / "v.exr")),
                 {"scene.json", "nesting deeper than 64 levels at byte 65"});
  test::WriteText(dir / "cams/scene.json", R"({"version": 1, "cameras": "cameras.json", "nodes": [{"name": "b", "primitive": "box"}]})");
  test::WriteText(dir / "cams/cameras.json", "{\"cameras\": " + deep);
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(dir / "cams/scene.json") + " -o " + Quote(dir / "v.exr")),
                 {"cameras.json", "nesting deeper than 64 levels at byte 76"});
  test::WriteText(dir / "at.json", deep);
  ExpectBadInput(RunCommand(kVkrecon + " synth " + Quote(kAssets / "box/scene.json") + " --at " +
                            Quote(dir / "at.json") + " -o " + Quote(dir / "o")),
                 {"at.json", "nesting deeper than 64 levels"});
}

TEST(Cli, SceneWithNothingToDrawIsBadInput) {
  TempDir dir;
  test::WriteText(dir / "scene.json", R"({"version": 1, "nodes": [{"name": "pivot"}]})");
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(dir / "scene.json") + " -o " + Quote(dir / "v.exr")),
                 {"scene.json", "nodes", "nothing to draw"});
}

TEST(Cli, AtFileMissingAParameterNamesIt) {
  TempDir dir;
  test::WriteText(dir / "at.json", R"({"x": 0.1, "y": 0, "w": 1, "d": 1, "h": 0.5})");
  ExpectBadInput(RunCommand(kVkrecon + " synth " + Quote(kAssets / "box/scene.json") + " --at " +
                            Quote(dir / "at.json") + " -o " + Quote(dir / "o")),
                 {"at.json", "yaw"});
}

TEST(Cli, BadOverrideIsNamed) {
  TempDir dir;
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(kAssets / "box/scene.json") +
                            " --set likelihood.sigmaa=3 -o " + Quote(dir / "v.exr")),
                 {"sigmaa"});
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(kAssets / "box/scene.json") +
                            " --set nonsense -o " + Quote(dir / "v.exr")),
                 {"--set"});
}

TEST(Cli, NonSquareTextureIsRejected) {
  TempDir dir;
  WritePng(dir / "t.png", Image(8, 4, 0.5f));
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(kAssets / "box/scene.json") + " --texture " +
                            Quote(dir / "t.png") + " -o " + Quote(dir / "v.exr")),
                 {"t.png", "square"});
}

TEST(Cli, UnknownCameraIsNamed) {
  TempDir dir;
  ExpectBadInput(RunCommand(kVkrecon + " render " + Quote(kAssets / "box/scene.json") +
                            " --camera nope -o " + Quote(dir / "v.exr")),
                 {"nope"});
}

class AssetTest : public ::testing::TestWithParam<std::string> {};

// synth at quarter size, then the object's centre must be covered in every image whose
// camera sees it, and render must write EXRs with surface (alpha 1) and background (alpha 0).
TEST_P(AssetTest, SynthAndRenderPlaceTheObjectWhereTheCamerasSay) {
  const fs::path scene_file = kAssets / GetParam() / "scene.json";
  const fs::path truth = kAssets / GetParam() / "truth.json";
  TempDir dir;
  const auto synth = RunCommand(kVkrecon + " synth -q " + Quote(scene_file) + " --at " + Quote(truth) +
                                " --scale 0.25 --noise 4 -o " + Quote(dir / "images"));
  ASSERT_EQ(synth.exit_status, 0) << synth.err;

  // The images and the cameras written beside them load as a scene of their own.
  const Scene scene = LoadScene(scene_file, {{"cameras", (dir / "images/cameras.json").string()},
                                             {"images", (dir / "images").string()}});
  const std::vector<double> psi = scene.ValuesFromFile(truth);
  const auto cameras = scene.Cameras(psi);
  ASSERT_EQ(cameras.size(), scene.cameras.size());
  // The object: the last node with a primitive; its centre in its own frame is (0,0,0.5).
  int object = -1;
  for (int n = 0; n < int(scene.nodes.size()); ++n)
    if (scene.nodes[n].primitive != PrimitiveKind::None && scene.nodes[n].primitive != PrimitiveKind::Plane) object = n;
  ASSERT_GE(object, 0);
  const Eigen::Vector3d centre = (scene.WorldFromNode(psi)[object] * Eigen::Vector4d(0, 0, 0.5, 1)).head<3>();
  int seen = 0;
  for (const Camera& c : cameras) {
    const Image image = LoadImage(c.image);
    EXPECT_EQ(image.width, c.width);
    const Eigen::Vector2d uv = c.Project(centre);
    if (uv.x() < 1 || uv.y() < 1 || uv.x() > c.width - 1 || uv.y() > c.height - 1) continue;
    ++seen;
    const float* px = image.At(int(uv.x()), int(uv.y()));
    // Background is black; every object texture is far from black.
    EXPECT_GT(px[0] + px[1] + px[2], 0.25f) << c.name << " does not show the object at " << uv.transpose();
  }
  EXPECT_GE(seen, 3);

  const auto render = RunCommand(kVkrecon + " render -q " + Quote(scene_file) + " --at " + Quote(truth) +
                                 " --orbit 3 --scale 0.25 --atlas 512 --png -o " + Quote(dir / "views/orbit.exr"));
  ASSERT_EQ(render.exit_status, 0) << render.err;
  for (int k = 0; k < 3; ++k) {
    const Image view = LoadImage(dir / ("views/orbit_00" + std::to_string(k) + ".exr"));
    EXPECT_EQ(view.width, 160);
    int surface = 0, background = 0;
    for (size_t i = 3; i < view.rgba.size(); i += 4) (view.rgba[i] > 0.5f ? surface : background)++;
    EXPECT_GT(surface, 1000);
    EXPECT_GT(background, 100);
    EXPECT_TRUE(fs::exists(dir / ("views/orbit_00" + std::to_string(k) + ".png")));
  }
}

INSTANTIATE_TEST_SUITE_P(Assets, AssetTest, ::testing::Values("box", "house", "stairs", "poster"));

}  // namespace
}  // namespace vkr
