// Node matrices and cameras at a hypothesis, against matrices computed by hand.

#include <gtest/gtest.h>

#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

Scene LoadNodes(const TempDir& dir, const char* parameters, const char* nodes) {
  Json scene = {{"version", 1}};
  scene["parameters"] = Json::parse(parameters);
  scene["nodes"] = Json::parse(nodes);
  return LoadScene(WriteScene(dir, scene));
}

void ExpectNear(const Eigen::Matrix4d& actual, const Eigen::Matrix4d& expected) {
  EXPECT_TRUE(actual.isApprox(expected, 1e-12) || (actual - expected).norm() < 1e-12)
      << "actual\n" << actual << "\nexpected\n" << expected;
}

TEST(Transform, TranslateThenScaleFirstOutermost) {
  TempDir dir;
  const Scene s = LoadNodes(dir, "{}",
                            R"([{"name": "a", "transforms": [{"translate": [1, 2, 3]},
                                                             {"scale": [2, 3, 4]}]}])");
  Eigen::Matrix4d expected;
  expected << 2, 0, 0, 1,  //
      0, 3, 0, 2,          //
      0, 0, 4, 3,          //
      0, 0, 0, 1;
  ExpectNear(s.WorldFromNode({})[0], expected);
}

TEST(Transform, RotationIsZThenYThenXMatrixProduct) {
  // rotate [90, 0, 90] = Rz(90)·Rx(90): x ↦ y, y ↦ z, z ↦ x. The other order, Rx·Rz,
  // would send x to z, so this example tells them apart.
  TempDir dir;
  const Scene s =
      LoadNodes(dir, "{}", R"([{"name": "a", "transforms": [{"rotate": [90, 0, 90]}]}])");
  Eigen::Matrix4d expected;
  expected << 0, 0, 1, 0,  //
      1, 0, 0, 0,          //
      0, 1, 0, 0,          //
      0, 0, 0, 1;
  ExpectNear(s.WorldFromNode({})[0], expected);

  // All three angles, Rz(90)·Ry(90)·Rx(90), column by column (x first):
  //   x: Rx → x, Ry → −z, Rz → −z.   y: Rx → z, Ry → x, Rz → y.   z: Rx → −y, Ry → −y, Rz → x.
  const Scene t =
      LoadNodes(dir, "{}", R"([{"name": "a", "transforms": [{"rotate": [90, 90, 90]}]}])");
  Eigen::Matrix4d expected3;
  expected3 << 0, 0, 1, 0,  //
      0, 1, 0, 0,           //
      -1, 0, 0, 0,          //
      0, 0, 0, 1;
  ExpectNear(t.WorldFromNode({})[0], expected3);
}

TEST(Transform, ChildOfTranslatedRotatedScaledParent) {
  TempDir dir;
  const Scene s = LoadNodes(dir, R"({"w": {"prior": {"uniform": [1, 3]}}})", R"([
    {"name": "parent", "transforms": [{"translate": [1, 0, 0]}, {"rotate": [0, 0, 90]},
                                      {"scale": ["w", 1, 1]}]},
    {"name": "child", "parent": "parent", "primitive": "box",
     "transforms": [{"translate": [0.5, 0, 1]}]}])");
  const auto world = s.WorldFromNode({2.0});
  // parent = T(1,0,0)·Rz(90)·S(2,1,1); child = parent·T(0.5,0,1).
  Eigen::Matrix4d parent;
  parent << 0, -1, 0, 1,  //
      2, 0, 0, 0,         //
      0, 0, 1, 0,         //
      0, 0, 0, 1;
  Eigen::Matrix4d child;
  child << 0, -1, 0, 1,  //
      2, 0, 0, 1,        //
      0, 0, 1, 1,        //
      0, 0, 0, 1;
  ExpectNear(world[0], parent);
  ExpectNear(world[1], child);
  EXPECT_EQ(s.nodes[1].parent, 0);
  // ComposeTransforms is the node's own chain, without the parent.
  Eigen::Matrix4d local = Eigen::Matrix4d::Identity();
  local.topRightCorner<3, 1>() << 0.5, 0, 1;
  ExpectNear(ComposeTransforms(s, s.nodes[1].transforms, {2.0}), local);
}

TEST(Transform, RoofInheritsBoxScale) {
  // The house of docs/guide/SCENE_FORMAT.md: the roof's "rh/h" cancels the box's height so its
  // world height is rh.
  TempDir dir;
  const Scene s = LoadNodes(dir, R"({"h": {"prior": {"uniform": [0.2, 1.0]}},
                                     "rh": {"prior": {"uniform": [0.05, 0.6]}}})",
                            R"([
    {"name": "box", "primitive": "box", "transforms": [{"scale": [1, 1, "h"]}]},
    {"name": "roof", "parent": "box", "primitive": "prism",
     "transforms": [{"translate": [0, 0, 1]}, {"scale": [1, 1, "rh/h"]}]}])");
  const auto world = s.WorldFromNode({0.8, 0.3});
  EXPECT_NEAR(world[1](2, 2), 0.3, 1e-15);  // world height of the roof = rh
  EXPECT_NEAR(world[1](2, 3), 0.8, 1e-15);  // it sits on top of the box
}

TEST(Transform, CameraPoseAndProjection) {
  TempDir dir;
  Json scene = {{"version", 1}};
  scene["parameters"] = Json::parse(R"({"dx": {"prior": {"uniform": [-2, 2]}}})");
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["K"] = Json::parse("[[100, 0, 320], [0, 100, 240], [0, 0, 1]]");
  cam["width"] = 640;
  cam["height"] = 480;
  cam["pose"] = Json::parse(R"([{"translate": ["dx", 0, 0]}])");
  scene["cameras"] = Json::array({cam});
  const Scene s = LoadScene(WriteScene(dir, scene), {}, LoadOptions{.require_images = false});

  const Camera at_rest = s.Cameras({0.0})[0];
  // x_cam = X + (0,0,5): (1,2,5) → (1,2,10) → (100·0.1 + 320, 100·0.2 + 240).
  const Eigen::Vector2d p = at_rest.Project({1, 2, 5});
  EXPECT_NEAR(p.x(), 330.0, 1e-12);
  EXPECT_NEAR(p.y(), 260.0, 1e-12);
  EXPECT_TRUE(at_rest.Centre().isApprox(Eigen::Vector3d(0, 0, -5)));

  // The pose moves the camera by +1 in x: its centre moves, the point shifts left.
  const Camera moved = s.Cameras({1.0})[0];
  EXPECT_TRUE(moved.Centre().isApprox(Eigen::Vector3d(1, 0, -5)));
  EXPECT_TRUE(moved.R().isApprox(Eigen::Matrix3d::Identity()));
  EXPECT_NEAR(moved.Project({1, 2, 5}).x(), 320.0, 1e-12);
}

TEST(Transform, CameraPoseRotatesAboutTheWorldOrigin) {
  // A rotating pose turns the camera about the world origin: world_from_cam' = P·world_from_cam.
  TempDir dir;
  Json scene = {{"version", 1}};
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["pose"] = Json::parse(R"([{"rotate": [0, 0, 90]}])");
  scene["cameras"] = Json::array({cam});
  const Scene s = LoadScene(WriteScene(dir, scene), {}, LoadOptions{.require_images = false});
  const Camera c = s.Cameras({})[0];
  // Centre (0,0,-5) on the z axis is unchanged by Rz; the camera's x axis now points along y.
  EXPECT_TRUE(c.Centre().isApprox(Eigen::Vector3d(0, 0, -5)));
  EXPECT_TRUE(c.R().row(0).transpose().isApprox(Eigen::Vector3d(0, 1, 0)));
}

TEST(Transform, WrongSizeOfPsiIsAProgrammerError) {
  TempDir dir;
  const Scene s = LoadNodes(dir, R"({"w": {"prior": {"uniform": [1, 3]}}})",
                            R"([{"name": "a", "transforms": [{"scale": ["w", 1, 1]}]}])");
  EXPECT_THROW(s.WorldFromNode({}), std::invalid_argument);
}

}  // namespace
}  // namespace vkr::test
