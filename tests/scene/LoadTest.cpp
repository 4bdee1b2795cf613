// The house of docs/guide/SCENE_FORMAT.md ("Worked example: the house", without its albedos
// and with constant settings) loads as written, and missing sections take the defaults.

#include <gtest/gtest.h>

#include "engine/scene/Expression.h"
#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

constexpr const char* kDesignExample = R"({
  "version": 1,
  "images": "images/",
  "cameras": "cameras.json",
  "parameters": {
    "x":   {"prior": {"uniform": [-0.5, 0.5]}, "init": 0.0},
    "y":   {"prior": {"uniform": [-0.5, 0.5]}},
    "yaw": {"prior": {"normal": [10, 15]}, "bounds": [-45, 45]},
    "w":   {"prior": {"uniform": [0.3, 1.5]}},
    "d":   {"prior": {"uniform": [0.3, 1.5]}},
    "h":   {"prior": {"uniform": [0.2, 1.0]}},
    "rh":  {"prior": {"uniform": [0.05, 0.6]}}
  },
  "nodes": [
    {"name": "ground", "primitive": "plane", "transforms": [{"scale": [4, 4, 1]}]},
    {"name": "box", "primitive": "box",
     "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]}, {"scale": ["w", "d", "h"]}]},
    {"name": "roof", "parent": "box", "primitive": "prism",
     "transforms": [{"translate": [0, 0, 1]}, {"scale": [1, 1, "rh/h"]}]}
  ],
  "likelihood": {"kind": "surface", "sigma": 8.0, "weights": "angle", "atlas": 1024, "levels": 3,
                 "sandwich_blocks": 32, "charts": "pixels", "kappa": 12.5, "position_sd": 0.25,
                 "edges": true},
  "sampler": {"iterations": 4000, "chains": 4, "batch": 16, "seed": 1}
})";

TEST(Load, DesignExample) {
  TempDir dir;
  Json cam = BaseCamera("c1", "c1.pgm");
  WriteText(dir / "house/cameras.json", Json{{"cameras", Json::array({cam})}}.dump());
  WritePgm(dir / "house/images/c1.pgm", 4, 3);
  WriteText(dir / "house/scene.json", kDesignExample);
  const Scene s = LoadScene(dir / "house/scene.json");

  // Ψ follows the file's order of parameters, not alphabetical order.
  std::vector<std::string> names;
  for (const Parameter& p : s.parameters) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"x", "y", "yaw", "w", "d", "h", "rh"}));
  EXPECT_EQ(s.parameters[2].prior.kind, Prior::Kind::Normal);
  EXPECT_EQ(s.parameters[2].bounds, std::make_pair(-45.0, 45.0));
  EXPECT_EQ(s.parameters[0].init, 0.0);
  EXPECT_FALSE(s.parameters[1].init.has_value());

  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[0].primitive, PrimitiveKind::Plane);
  EXPECT_EQ(s.nodes[2].primitive, PrimitiveKind::Prism);
  EXPECT_EQ(s.nodes[2].parent, 1);
  EXPECT_EQ(s.nodes[1].transforms[1].kind, Transform::Kind::Rotate);
  EXPECT_STREQ(ToString(s.nodes[1].primitive), "box");

  EXPECT_EQ(s.file, (dir.path() / "house/scene.json").lexically_normal());
  EXPECT_EQ(s.images_dir, (dir.path() / "house/images").lexically_normal());
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].image, (dir.path() / "house/images/c1.pgm").lexically_normal());
  // The settings blocks are kept for their layers (tests/recon/SceneSettingsTest.cpp).
  EXPECT_EQ(Json::parse(s.settings.at("sampler")), Json::parse(R"({"iterations": 4000, "chains": 4, "batch": 16, "seed": 1})"));
  EXPECT_EQ(s.settings.count("synth"), 0u);

  // At the initial values the box is w × d × h = 0.9 × 0.9 × 0.6, yaw 10°, and the roof
  // stands 0.325 (the centre of rh's prior) tall on top of it.
  const auto world = s.WorldFromNode(s.InitialValues());
  EXPECT_NEAR(world[1].col(2).norm(), 0.6, 1e-12);
  EXPECT_NEAR(world[2](2, 2), 0.325, 1e-12);
  EXPECT_NEAR(world[2](2, 3), 0.6, 1e-12);
  EXPECT_NEAR(std::atan2(world[1](1, 0), world[1](0, 0)) * 180 / M_PI, 10.0, 1e-12);
}

TEST(Load, DefaultsForMissingSections) {
  TempDir dir;
  const Scene s = LoadScene(WriteScene(dir, Json{{"version", 1}}));
  EXPECT_TRUE(s.parameters.empty());
  EXPECT_TRUE(s.nodes.empty());
  EXPECT_TRUE(s.cameras.empty());
  EXPECT_EQ(s.images_dir, dir.path().lexically_normal());
  EXPECT_TRUE(s.settings.empty());
  EXPECT_EQ(s.expressions().size(), 0);
}

TEST(Load, NodeWithoutPrimitiveIsATransformNode) {
  TempDir dir;
  Json scene = BaseScene();
  scene["nodes"].push_back(Json{{"name", "pivot"}, {"parent", "box"}});
  const Scene s = LoadScene(WriteScene(dir, scene));
  EXPECT_EQ(s.nodes[2].primitive, PrimitiveKind::None);
  EXPECT_TRUE(s.nodes[2].transforms.empty());
}

TEST(Load, ScenesMove) {
  TempDir dir;
  Scene a = LoadScene(WriteScene(dir, BaseScene()));
  const auto before = a.WorldFromNode({1.2, 0.4});
  Scene b = std::move(a);
  EXPECT_EQ(b.WorldFromNode({1.2, 0.4}), before);  // expressions moved along
}

}  // namespace
}  // namespace vkr::test
