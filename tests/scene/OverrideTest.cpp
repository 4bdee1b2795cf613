// `--set PATH=VALUE` overrides (docs/guide/SCENE_FORMAT.md, "Overrides").

#include <gtest/gtest.h>

#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

TEST(Override, UnknownKeyIsAnError) {
  TempDir dir;
  const auto file = WriteScene(dir, BaseScene());
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"samplr.seed", "4"}}); },
                        {"samplr: unknown key"}));
}

TEST(Override, NodesCamerasAndImages) {
  TempDir dir;
  WritePgm(dir / "other/c1.pgm", 4, 3);
  WriteText(dir / "cams.json", Json{{"cameras", Json::array({BaseCamera("c1", "c1.pgm")})}}.dump());
  const auto file = WriteScene(dir, BaseScene());
  const Scene s = LoadScene(file, {{"nodes[1].primitive", "cylinder"},
                                   {"cameras", "cams.json"},
                                   {"images", "other"}});
  EXPECT_EQ(s.nodes[1].primitive, PrimitiveKind::Cylinder);
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].image, (dir.path() / "other/c1.pgm").lexically_normal());
  // A JSON value: a mesh object.
  WriteText(dir / "m.glb", "glTF");
  EXPECT_EQ(LoadScene(file, {{"nodes[0].primitive", R"({"mesh": "m.glb"})"}}).nodes[0].primitive,
            PrimitiveKind::Mesh);
}

TEST(Override, BadPaths) {
  TempDir dir;
  const auto file = WriteScene(dir, BaseScene());
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"nodes[5].primitive", "box"}}); },
                        {"scene.json: nodes[5].primitive", "has no element [5]"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"version.x", "1"}}); },
                        {"version.x", "version is not an object"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"likelihood..sigma", "1"}}); },
                        {"likelihood..sigma", "bad --set path"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"", "1"}}); }, {"bad --set path"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"nodes[x]", "1"}}); }, {"bad --set path"}));
  // An index too large for a long: std::stol threw std::out_of_range, not an InputError, and
  // the command line said only "error: stol" (fuzz_scene_json found it).
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"nodes[18888888888888888888888].primitive", "box"}}); },
                        {"bad --set path", "index [18888888888888888888888] is out of range"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"nodes[9223372036854775807].primitive", "box"}}); },
                        {"has no element [9223372036854775807]"}));
}

}  // namespace
}  // namespace vkr::test
