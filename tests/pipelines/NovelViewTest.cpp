// The novel-view pass draws where K[R|t] says: every covered pixel's interpolated world
// position projects back onto that pixel's centre, and the silhouette of a box matches the
// convex hull of its projected corners to within half a pixel.

#include <gtest/gtest.h>

#include <cmath>

#include "engine/geometry/SceneGeometry.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/NovelViewPass.h"
#include "tests/common/GpuTest.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

using test::GpuTest;

// A rotated, off-centre box seen by a camera with skew and an off-centre principal point.
constexpr const char* kBoxScene = R"({
  "version": 1,
  "parameters": {"yaw": {"prior": {"uniform": [-45, 45]}, "init": 23}},
  "nodes": [{"name": "box", "primitive": "box",
             "transforms": [{"translate": [0.2, -0.1, 0]}, {"rotate": [0, 0, "yaw"]},
                            {"scale": [0.8, 0.5, 0.6]}]}],
  "cameras": [{"name": "c", "image": "c.png", "width": 160, "height": 120,
               "K": [[150, 3.5, 71.3], [0, 155, 66.8], [0, 0, 1]],
               "R": [[0.8660254037844387, 0.5, 0], [0.1710100716628344, -0.2961981327260238, -0.9396926207859084], [-0.4698463103929542, 0.8137976813493737, -0.3420201433256687]],
               "t": [0.05, 0.2, 2.4]}]
})";

struct Drawn {
  Scene scene;
  std::vector<double> psi;
  Camera camera;
  Image position;
};

Drawn DrawBox(vk::Device& device) {
  test::TempDir dir;
  test::WriteText(dir / "scene.json", kBoxScene);
  LoadOptions load;
  load.require_images = false;
  Drawn d{LoadScene(dir / "scene.json", {}, load), {}, {}, {}};
  d.psi = d.scene.InitialValues();
  d.camera = d.scene.Cameras(d.psi)[0];
  const SceneGeometry geometry = BuildSceneGeometry(d.scene, d.psi, 256, ChartSizing::Area);
  vk::Transfer transfer(device);
  vk::CommandContext context(device);
  GpuScene gpu(device, transfer, geometry);
  gpu.SetNodeMatrices(0, d.scene.WorldFromNode(d.psi));
  vk::GpuImage atlas(device, {4, 4, 1, VK_FORMAT_R32G32B32A32_SFLOAT,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
  std::vector<float> grey(4 * 4 * 4, 0.5f);
  transfer.UploadImage(atlas, 0, grey.data(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  NovelViewPass pass(device, gpu, atlas);
  d.position = pass.Render(transfer, context, d.camera, 0, NovelViewPass::Output::WorldPosition);
  return d;
}

TEST_F(GpuTest, EveryPixelShowsThePointThatProjectsOntoItsCentre) {
  const Drawn d = DrawBox(device());
  int covered = 0;
  double worst = 0.0;
  for (int j = 0; j < d.position.height; ++j)
    for (int i = 0; i < d.position.width; ++i) {
      const float* p = d.position.At(i, j);
      if (p[3] == 0.0f) continue;
      ++covered;
      const Eigen::Vector2d uv = d.camera.Project(Eigen::Vector3d(p[0], p[1], p[2]));
      worst = std::max(worst, (uv - Eigen::Vector2d(i + 0.5, j + 0.5)).norm());
    }
  EXPECT_GT(covered, 500);
  // Float interpolation of world positions a couple of metres away: hundredths of a pixel.
  // A half-pixel convention error would show as 0.5 or more.
  EXPECT_LT(worst, 0.05);
}

// Signed distance of p to the convex polygon (positive inside).
double InsideDistance(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p) {
  double d = 1e30;
  for (size_t k = 0; k < hull.size(); ++k) {
    const Eigen::Vector2d a = hull[k], b = hull[(k + 1) % hull.size()];
    const Eigen::Vector2d e = (b - a).normalized();
    d = std::min(d, e.x() * (p.y() - a.y()) - e.y() * (p.x() - a.x()));
  }
  return d;
}

std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;  // counter-clockwise in a y-up frame = clockwise in image coordinates
}

TEST_F(GpuTest, BoxSilhouetteMatchesProjectedCornersWithinHalfAPixel) {
  const Drawn d = DrawBox(device());
  const Eigen::Matrix4d world_from_box = d.scene.WorldFromNode(d.psi)[0];
  std::vector<Eigen::Vector2d> corners;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector4d local((c & 1) ? 0.5 : -0.5, (c & 2) ? 0.5 : -0.5, (c & 4) ? 1.0 : 0.0, 1.0);
    corners.push_back(d.camera.Project((world_from_box * local).head<3>()));
  }
  std::vector<Eigen::Vector2d> hull = ConvexHull(corners);
  // Orient so that InsideDistance is positive inside, whatever the hull's winding.
  if (InsideDistance(hull, (corners[0] + corners[7]) / 2) < 0) std::reverse(hull.begin(), hull.end());
  int checked = 0, wrong = 0;
  for (int j = 0; j < d.position.height; ++j)
    for (int i = 0; i < d.position.width; ++i) {
      const double inside = InsideDistance(hull, {i + 0.5, j + 0.5});
      if (std::abs(inside) < 0.5) continue;  // the rasteriser may go either way this close
      ++checked;
      if ((d.position.At(i, j)[3] > 0.0f) != (inside > 0)) ++wrong;
    }
  EXPECT_GT(checked, 15000);
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace vkr
