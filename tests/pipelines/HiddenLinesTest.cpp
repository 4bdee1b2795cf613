// The host depth buffer behind the overlays' hidden-line test (pipelines/rendering/HiddenLines.h):
// what lies behind a surface is hidden, what lies on or before it is seen, and a surface that
// reaches behind the camera is clipped at the near plane rather than projected to infinity.

#include <gtest/gtest.h>

#include "pipelines/rendering/HiddenLines.h"

namespace vkr {
namespace {

// A 200×100 pinhole at the origin looking down +z (OpenCV convention: y down).
Camera Pinhole() {
  Camera c;
  c.width = 200, c.height = 100;
  c.K << 100, 0, 100, 0, 100, 50, 0, 0, 1;
  return c;
}

// A square wall at depth z, 2 m wide, facing the camera.
std::vector<WorldTriangle> Wall(double z) {
  const Eigen::Vector3d a(-1, -1, z), b(1, -1, z), c(1, 1, z), d(-1, 1, z);
  return {{a, b, c}, {a, c, d}};
}

TEST(HiddenLines, WhatLiesBehindAWallIsHidden) {
  const DepthBuffer depth(Pinhole(), Wall(4.0));
  EXPECT_TRUE(depth.Visible({0.1, 0.2, 3.0})) << "in front of the wall";
  EXPECT_TRUE(depth.Visible({0.1, 0.2, 4.0})) << "on it";
  EXPECT_FALSE(depth.Visible({0.1, 0.2, 5.0})) << "behind it";
  EXPECT_TRUE(depth.Visible({3.0, 0.2, 5.0})) << "behind, but beside it";
  EXPECT_TRUE(depth.Visible({1.25, 0.0, 5.0})) << "behind it at its outline, where the background shows beside it";
}

// A ground plane under the camera from 10 m behind it to 10 m ahead: its corners behind the
// camera are clipped, and a point under the ground ahead is hidden, one above it seen.
TEST(HiddenLines, SurfaceBehindTheCameraIsClippedNotProjected) {
  const Eigen::Vector3d a(-50, 1, -10), b(50, 1, -10), c(50, 1, 10), d(-50, 1, 10);
  const DepthBuffer depth(Pinhole(), {{a, b, c}, {a, c, d}});
  EXPECT_FALSE(depth.Visible({0.0, 1.5, 5.0})) << "under the ground";
  EXPECT_TRUE(depth.Visible({0.0, 0.5, 5.0})) << "above it";
}

}  // namespace
}  // namespace vkr
