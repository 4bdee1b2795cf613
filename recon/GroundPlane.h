#pragma once
// The ground of a sparse point cloud: the plane `vkrecon init` puts at z = 0 (SceneInit.h).
// RANSAC over triples of points, then a least-squares refit on the inliers, keeping only
// planes whose normal lies near the expected up direction and that leave few points below.
// A plane's score is its inliers times the cosine of its tilt from up, less the points below
// it: of a ground and a plane through the walls' feet that leans into the wall behind, the
// ground wins, with the scene above it.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace vkr::recon {

struct GroundPlaneOptions {
  // The expected up direction (unit): the cameras' mean up, or the user's --up.
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  // The most the plane's normal may lean from `up`, degrees. Cameras that all look down from
  // one side tilt their mean up by about their elevation; a wall is 90° off.
  double max_tilt_deg = 45.0;
  // A point is on the plane within this distance (the cloud's units).
  double tolerance = 0.01;
  // The most points that may lie more than 3 tolerances below the plane, as a share of all:
  // the ground has the scene on its cameras' side, a table top or box lid does not.
  double max_below = 0.2;
  // The fewest inliers a ground needs, as a share of all points and as a count.
  double min_inlier_share = 0.03;
  int min_inliers = 10;
  // Enough triples to draw three points of a plane that holds 3 % of the cloud with 98 %
  // probability. The path along the walls' feet in Merton's courtyard holds 5–6 % of what
  // COLMAP triangulates: at 5 % and 40,000 triples one of three calibrations had no ground.
  int iterations = 150000;
  // RANSAC counts each plane's support on an even subsample of at most this many points;
  // the refit counts all of them.
  int support_sample = 4000;
  std::uint64_t seed = 1;
};

// n·X = offset on the plane; n is unit and points up (n·up > 0).
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;
  int inliers = 0;
  int below = 0;
  double Height(const Eigen::Vector3d& x) const { return normal.dot(x) - offset; }
};

// The ground, or nothing when no plane passes the options' tests.
std::optional<GroundPlane> FitGroundPlane(const std::vector<Eigen::Vector3d>& points,
                                          const GroundPlaneOptions& options);

}  // namespace vkr::recon
