// ViewCulling (pipelines/passes/ViewCulling.h) on primitives whose answer is plain geometry:
// what faces away from a camera or lies outside its frustum is unseen, what it might see is
// shaded, a large face partly in view is shaded over the patch in view only, and the lists
// always cover the index buffer once.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "engine/geometry/Mesh.h"
#include "pipelines/passes/Projection.h"
#include "pipelines/passes/ViewCulling.h"

namespace vkr::test {
namespace {

// One node of `kind` at the origin (unit size), as the likelihoods draw it.
SceneGeometry OneNode(PrimitiveKind kind) {
  Scene scene;
  scene.file = "/nowhere/scene.json";
  Node node;
  node.name = "node";
  node.primitive = kind;
  scene.nodes.push_back(node);
  return BuildSceneGeometry(scene, {}, 256, ChartSizing::Area);
}

// A 640×480 camera at `centre` looking at `target`, z up.
Camera LookAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  c.cam_from_world = CamFromWorldLookingAt(centre, target);
  return c;
}

ViewDraws Classify(const SceneGeometry& g, const Eigen::Matrix4d& world_from_node, const Camera& camera) {
  return ViewCulling(g).Classify({world_from_node}, ClipFromWorld(camera), camera.Centre(), kDefaultNear);
}

// Faces (by index in the mesh) some of whose indices are drawn unseen.
std::vector<uint32_t> UnseenFaces(const SceneGeometry& g, const ViewDraws& d) {
  std::vector<uint32_t> faces;
  for (const IndexRun& r : d.unseen)
    for (uint32_t i = r.first; i < r.first + r.count; ++i) {
      const uint32_t f = g.vertices[g.indices[i]].face;
      if (faces.empty() || faces.back() != f) faces.push_back(f);
    }
  return faces;
}

uint32_t Total(const std::vector<IndexRun>& runs) {
  uint32_t n = 0;
  for (const IndexRun& r : runs) n += r.count;
  return n;
}

uint32_t Total(const std::vector<PartialRun>& runs) {
  uint32_t n = 0;
  for (const PartialRun& r : runs) n += r.indices.count;
  return n;
}

TEST(ViewCulling, TheFacesOfABoxTurnedAwayAreUnseen) {
  const SceneGeometry g = OneNode(PrimitiveKind::Box);
  // From 5 m out along +x and 3 m up it sees the +x face and the top; from y = 0, between
  // the planes of the ±y faces, those face away like -x and the bottom.
  const Camera camera = LookAt({5, 0, 3}, {0, 0, 0.5});
  const ViewDraws d = Classify(g, Eigen::Matrix4d::Identity(), camera);
  // Box faces: -y, +x, +y, -x, top, bottom (Primitives.cpp).
  EXPECT_EQ(UnseenFaces(g, d), (std::vector<uint32_t>{0, 2, 3, 5}));
  EXPECT_EQ(Total(d.shaded) + Total(d.unseen), uint32_t(g.indices.size()));
  // Four of six equal faces: two thirds of the charts' area (chart sides round to texels).
  EXPECT_NEAR(d.unseen_area, 4.0 / 6.0, 0.02);
}

TEST(ViewCulling, ANodeMatrixTurnsTheFacesWithIt) {
  const SceneGeometry g = OneNode(PrimitiveKind::Box);
  const Camera camera = LookAt({5, 0, 3}, {0, 0, 0.5});
  // Yawed 180°: the -x face now faces the camera and +x turns away.
  Eigen::Matrix4d yaw = Eigen::Matrix4d::Identity();
  yaw.topLeftCorner<3, 3>() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_EQ(UnseenFaces(g, Classify(g, yaw, camera)), (std::vector<uint32_t>{0, 1, 2, 5}));
  // A non-uniform scale: the faces keep their sides.
  const Eigen::Matrix4d stretch = Eigen::Vector4d(3.0, 0.5, 2.0, 1.0).asDiagonal();
  EXPECT_EQ(UnseenFaces(g, Classify(g, stretch, camera)), (std::vector<uint32_t>{0, 2, 3, 5}));
}

TEST(ViewCulling, GroundBehindOrBelowTheCameraIsUnseenAndGroundInViewShaded) {
  const SceneGeometry g = OneNode(PrimitiveKind::Plane);
  const Eigen::Matrix4d ground = Eigen::Vector4d(40.0, 40.0, 1.0, 1.0).asDiagonal();
  const uint32_t all = uint32_t(g.indices.size());
  // Looking down at it from 3 m: drawn in parts, the full shader only over the patch in
  // view, 3.84 × 2.88 m of the 40 × 40 m (the camera's 640 × 480 pixels at f = 500).
  const ViewDraws down = Classify(g, ground, LookAt({0, -0.01, 3}, {0, 0, 0}));
  ASSERT_EQ(down.partial.size(), 1u);
  EXPECT_EQ(Total(down.partial), all);
  EXPECT_EQ(Total(down.shaded) + Total(down.unseen), 0u);
  const PartialRun& patch = down.partial[0];
  Eigen::Vector2d lo = {1, 1}, hi = {0, 0};
  for (const GpuVertex& v : g.vertices) {
    lo = lo.cwiseMin(Eigen::Vector2d(v.atlas_uv[0], v.atlas_uv[1]));
    hi = hi.cwiseMax(Eigen::Vector2d(v.atlas_uv[0], v.atlas_uv[1]));
  }
  const double du = (patch.u1 - patch.u0) / (hi - lo).x(), dv = (patch.v1 - patch.v0) / (hi - lo).y();
  EXPECT_NEAR(std::max(du, dv), 3.84 / 40.0, 0.01);
  EXPECT_NEAR(std::min(du, dv), 2.88 / 40.0, 0.01);
  const Eigen::Vector2d middle = (lo + hi) / 2;  // the point below the camera
  EXPECT_TRUE(patch.u0 < middle.x() && middle.x() < patch.u1 && patch.v0 < middle.y() && middle.y() < patch.v1);
  EXPECT_NEAR(down.unseen_area, 1.0 - du * dv, 1e-9);
  // From below it faces away.
  const ViewDraws below = Classify(g, ground, LookAt({0, -0.01, -3}, {0, 0, 0}));
  EXPECT_EQ(Total(below.unseen), all);
  EXPECT_NEAR(below.unseen_area, 1.0, 1e-9);
  // Wholly behind the camera: unseen though it faces the camera.
  const Eigen::Matrix4d behind = Eigen::Affine3d(Eigen::Translation3d(0, -80, 0)).matrix() * ground;
  EXPECT_EQ(Total(Classify(g, behind, LookAt({0, -30, 1}, {0, 60, 1})).unseen), all);
  // Wholly to the left of the view: unseen; straddling its edge: shaded.
  const Eigen::Matrix4d left = Eigen::Affine3d(Eigen::Translation3d(-60, 0, 0)).matrix() * ground;
  EXPECT_EQ(Total(Classify(g, left, LookAt({0, -30, 1}, {0, 60, 1})).unseen), all);
  const Eigen::Matrix4d edge = Eigen::Affine3d(Eigen::Translation3d(-20, 0, 0)).matrix() * ground;
  const ViewDraws straddling = Classify(g, edge, LookAt({0, -30, 1}, {0, 60, 1}));
  EXPECT_EQ(Total(straddling.shaded) + Total(straddling.partial), all);
  EXPECT_EQ(Total(straddling.unseen), 0u);
  // A degenerate node matrix is shaded whole, as it was before culling.
  Eigen::Matrix4d nan = ground;
  nan(0, 0) = NAN;
  const ViewDraws degenerate = Classify(g, nan, LookAt({0, -0.01, 3}, {0, 0, 0}));
  EXPECT_EQ(Total(degenerate.shaded), all);
  EXPECT_TRUE(degenerate.partial.empty());
}

TEST(ViewCulling, CurvedFacesAreNeverTakenForBackFacing) {
  const SceneGeometry g = OneNode(PrimitiveKind::Cylinder);
  // Seen from the side: the cylinder's far half faces away, but its normals vary over each
  // cluster, so only the frustum test may cull it — and all of it is in view.
  const Camera camera = LookAt({6, 0, 2}, {0, 0, 0.5});
  const ViewDraws d = Classify(g, Eigen::Matrix4d::Identity(), camera);
  // Cylinder faces: side, top, bottom; only the bottom cap (flat, facing down) is unseen.
  EXPECT_EQ(UnseenFaces(g, d), (std::vector<uint32_t>{2}));
}

TEST(ViewCulling, ShadeAllDrawsEverythingOnce) {
  const SceneGeometry g = OneNode(PrimitiveKind::Prism);
  const ViewDraws d = ViewCulling(g).ShadeAll();
  EXPECT_TRUE(d.unseen.empty());
  ASSERT_EQ(d.shaded.size(), 1u);
  EXPECT_EQ(d.shaded[0].count, uint32_t(g.indices.size()));
}

}  // namespace
}  // namespace vkr::test
