// `--set PATH=VALUE` overrides (docs/guide/SCENE_FORMAT.md, "Overrides").

#include <gtest/gtest.h>

#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

TEST(Override, SettingsByDottedPath) {
  TempDir dir;
  const auto file = WriteScene(dir, BaseScene());
  const Scene plain = LoadScene(file);
  EXPECT_EQ(plain.likelihood.sigma, 8.0);
  EXPECT_EQ(plain.likelihood.kind, "surface");
  EXPECT_EQ(plain.sampler.seed, 1u);

  // likelihood and sampler are absent from the file: overriding creates them.
  const Scene s = LoadScene(file, {{"likelihood.sigma", "4"},
                                   {"sampler.seed", "7"},
                                   {"likelihood.kind", "image"},
                                   {"sampler.batch", "32"}});
  EXPECT_EQ(s.likelihood.sigma, 4.0);
  EXPECT_FALSE(s.likelihood.sigma_auto);  // a number replaces the default "auto"
  EXPECT_EQ(s.sampler.seed, 7u);
  EXPECT_EQ(s.likelihood.kind, "image");
  EXPECT_EQ(s.sampler.batch, 32);
  EXPECT_TRUE(s.sampler.iterations_auto);  // untouched defaults stay
  EXPECT_EQ(s.likelihood.atlas, 0);

  // "auto" and numbers for the length and the time limit.
  const Scene fixed = LoadScene(file, {{"sampler.iterations", "300"}, {"sampler.time_limit", "90"}});
  EXPECT_FALSE(fixed.sampler.iterations_auto);
  EXPECT_EQ(fixed.sampler.iterations, 300);
  EXPECT_EQ(fixed.sampler.TimeLimit(), 90.0);
  const Scene fixed_unlimited = LoadScene(file, {{"sampler.iterations", "300"}});
  EXPECT_EQ(fixed_unlimited.sampler.TimeLimit(), 0.0);  // a fixed count runs to its end
  const Scene unlimited = LoadScene(file, {{"sampler.iterations", "auto"}, {"sampler.time_limit", "none"}});
  EXPECT_TRUE(unlimited.sampler.iterations_auto);
  EXPECT_EQ(unlimited.sampler.TimeLimit(), 0.0);
}

TEST(Override, LaterOverridesWinAndValuesAreValidated) {
  TempDir dir;
  Json scene = BaseScene();
  scene["likelihood"] = Json{{"sigma", 2}};
  const auto file = WriteScene(dir, scene);
  EXPECT_EQ(LoadScene(file, {{"likelihood.sigma", "5"}, {"likelihood.sigma", "6"}}).likelihood.sigma,
            6.0);
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"likelihood.sigma", "-1"}}); },
                        {"scene.json: likelihood.sigma", "must be > 0"}));
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"likelihood.kind", "volume"}}); },
                        {"likelihood.kind", "unknown kind"}));
  EXPECT_TRUE(LoadScene(file, {{"likelihood.sigma", "auto"}}).likelihood.sigma_auto);
}

TEST(Override, UnknownKeyIsAnError) {
  TempDir dir;
  const auto file = WriteScene(dir, BaseScene());
  EXPECT_TRUE(FailsWith([&] { LoadScene(file, {{"likelihood.sigmaa", "4"}}); },
                        {"scene.json: likelihood.sigmaa: unknown key", "set by --set"}));
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
