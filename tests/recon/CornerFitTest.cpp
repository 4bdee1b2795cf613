// The corner template's walls (recon/CornerFit.h) from a footprint of noisy points on two walls,
// with stray points: where they meet, how they run and how long they are; and the footprints
// and cameras that are not an inside corner, refused with a reason.

#include "recon/CornerFit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vkr::test {
namespace {

using Vec2 = Eigen::Vector2d;

Vec2 Direction(double degrees) { return {std::cos(degrees * M_PI / 180.0), std::sin(degrees * M_PI / 180.0)}; }

struct Corner {
  Vec2 at{2.0, 3.0};
  double yaw = 20.0, angle = 100.0, length_a = 8.0, length_b = 6.0;
};

// 600 points on the walls (noise 0.03), 60 strays within 10 of the corner, cameras 12 away
// along the bisector, spread over ±20°.
void Footprint(const Corner& c, std::vector<Vec2>& points, std::vector<Vec2>& cameras, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.03);
  for (int i = 0; i < 600; ++i) {
    const bool on_a = i % 5 < 3;  // wall a holds more points than b
    const Vec2 d = Direction(on_a ? c.yaw : c.yaw + c.angle);
    points.push_back(c.at + unit(rng) * (on_a ? c.length_a : c.length_b) * d + Vec2(noise(rng), noise(rng)));
  }
  for (int i = 0; i < 60; ++i) points.push_back(c.at + Vec2(20.0 * unit(rng) - 10.0, 20.0 * unit(rng) - 10.0));
  for (int i = 0; i < 5; ++i) cameras.push_back(c.at + 12.0 * Direction(c.yaw + c.angle / 2 - 20.0 + 10.0 * i));
}

TEST(CornerFit, FindsWhereTwoWallsMeetAndHowTheyRun) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const Corner truth;
    std::vector<Vec2> points, cameras;
    Footprint(truth, points, cameras, seed);
    const recon::CornerResult r = recon::FitCorner(points, cameras, 0.1, seed);
    ASSERT_TRUE(r.fit) << r.why_not;
    EXPECT_LT((r.fit->corner - truth.at).norm(), 0.05) << seed;
    EXPECT_NEAR(r.fit->yaw_deg, truth.yaw, 0.5) << seed;
    EXPECT_NEAR(r.fit->angle_deg, truth.angle, 0.5) << seed;
    // The 98th percentile of points spread evenly along each wall.
    EXPECT_NEAR(r.fit->length_a, 0.98 * truth.length_a, 0.15) << seed;
    EXPECT_NEAR(r.fit->length_b, 0.98 * truth.length_b, 0.15) << seed;
    EXPECT_GT(r.fit->inliers_a, r.fit->inliers_b);
  }
}

TEST(CornerFit, LabelsTheWallsCounterClockwise) {
  // Wall b's points more numerous: RANSAC finds it first, and the labels still follow the turn.
  Corner truth;
  truth.yaw = -60.0, truth.angle = 75.0;
  std::vector<Vec2> points, cameras;
  Footprint(truth, points, cameras, 4);
  std::vector<Vec2> more_b = points;
  for (const Vec2& p : points)
    if (std::abs((p - truth.at).normalized().dot(Direction(truth.yaw + truth.angle))) > 0.999) more_b.push_back(p);
  const recon::CornerResult r = recon::FitCorner(more_b, cameras, 0.1, 4);
  ASSERT_TRUE(r.fit) << r.why_not;
  EXPECT_NEAR(r.fit->yaw_deg, truth.yaw, 0.5);
  EXPECT_NEAR(r.fit->angle_deg, truth.angle, 0.5);
  EXPECT_LT(r.fit->inliers_a, r.fit->inliers_b);
}

TEST(CornerFit, RefusesWhatIsNoInsideCorner) {
  const Corner truth;
  std::vector<Vec2> points, cameras;
  Footprint(truth, points, cameras, 5);

  std::vector<Vec2> behind;  // the same walls seen from outside: a building's corner
  for (const Vec2& c : cameras) behind.push_back(truth.at - (c - truth.at));
  recon::CornerResult r = recon::FitCorner(points, behind, 0.1, 5);
  EXPECT_FALSE(r.fit);
  EXPECT_NE(r.why_not.find("0 of 5 cameras stand between"), std::string::npos) << r.why_not;
  EXPECT_NE(r.why_not.find("box or house"), std::string::npos) << r.why_not;

  std::vector<Vec2> one_wall;
  for (const Vec2& p : points)
    if (std::abs((p - truth.at).normalized().dot(Direction(truth.yaw))) > 0.999) one_wall.push_back(p);
  r = recon::FitCorner(one_wall, cameras, 0.1, 5);
  EXPECT_FALSE(r.fit);
  EXPECT_NE(r.why_not.find("lie on one wall"), std::string::npos) << r.why_not;

  std::vector<Vec2> parallel, narrow_cameras;  // two walls 10° apart
  Corner narrow = truth;
  narrow.angle = 10.0;
  Footprint(narrow, parallel, narrow_cameras, 6);
  r = recon::FitCorner(parallel, narrow_cameras, 0.1, 6);
  EXPECT_FALSE(r.fit);
  EXPECT_NE(r.why_not.find("at least 30° from the first"), std::string::npos) << r.why_not;
}

}  // namespace
}  // namespace vkr::test
