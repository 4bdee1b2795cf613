// The ground `vkrecon init` finds (recon/GroundPlane.h): of the planes near up, the one with the
// scene above it, not merely the one holding the most points.

#include "recon/GroundPlane.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vkr::recon {
namespace {

// 300 points on the ground z = 0 over x in [0, 6], and 390 on a plane leaning 20° from up that
// rises from the ground at x = 3.5 (a wall's foot and the wall seen askew, as in a courtyard):
// more points than the ground, and 125 of the ground's below it.
std::vector<Eigen::Vector3d> GroundAndALeaningPlane() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 300; ++i) points.emplace_back(6.0 * u(rng), 4.0 * u(rng), 0.0);
  const double slope = std::tan(20.0 * M_PI / 180.0);
  for (int i = 0; i < 390; ++i) {
    const double x = 3.5 + 4.0 * u(rng);
    points.emplace_back(x, 4.0 * u(rng), slope * (x - 3.5));
  }
  return points;
}

TEST(GroundPlane, TheSceneIsAboveTheGroundNotBelowIt) {
  GroundPlaneOptions options;
  options.tolerance = 0.02;
  const std::optional<GroundPlane> ground = FitGroundPlane(GroundAndALeaningPlane(), options);
  ASSERT_TRUE(ground);
  EXPECT_NEAR(std::acos(ground->normal.z()) * 180.0 / M_PI, 0.0, 0.5);
  EXPECT_NEAR(ground->offset, 0.0, 0.01);
  EXPECT_EQ(ground->below, 0);
  EXPECT_GE(ground->inliers, 300);  // and the leaning plane's few at its foot
  EXPECT_LE(ground->inliers, 310);
}

TEST(GroundPlane, APlaneBeyondTheTiltIsNoGround) {
  GroundPlaneOptions options;
  options.tolerance = 0.02;
  options.max_tilt_deg = 10.0;
  options.up = Eigen::Vector3d(std::sin(0.5), 0.0, std::cos(0.5));  // 29° from the ground's normal
  EXPECT_FALSE(FitGroundPlane(GroundAndALeaningPlane(), options));
}

}  // namespace
}  // namespace vkr::recon
