#pragma once
// Two walls meeting in an inside corner, from the footprint of the points above the ground:
// what `vkrecon init --template corner` sets its priors by (a courtyard, two façades of an
// L-shaped building, a room). Two lines by sequential RANSAC on the points' (x, y), each
// refitted by least squares; the corner is where they cross.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace vkr::recon {

struct CornerFit {
  Eigen::Vector2d corner = Eigen::Vector2d::Zero();
  // Wall a runs from the corner at `yaw_deg` from +x; wall b at `angle_deg` (0–180)
  // counter-clockwise from wall a. The cameras stand between them.
  double yaw_deg = 0.0, angle_deg = 90.0;
  double length_a = 1.0, length_b = 1.0;  // from the corner to the far end of each wall's points
  int inliers_a = 0, inliers_b = 0;
};

// The corner of the points' footprint seen from `cameras` (their centres' x, y), or a
// sentence saying why they do not fit one: fewer than a tenth of the points on a second wall,
// walls closer than 30° to parallel, or fewer than 80 % of the cameras between the walls
// (a building's outside corner is the box template's).
struct CornerResult {
  std::optional<CornerFit> fit;
  std::string why_not;
};
CornerResult FitCorner(const std::vector<Eigen::Vector2d>& footprint, const std::vector<Eigen::Vector2d>& cameras,
                       double tolerance, std::uint64_t seed);

}  // namespace vkr::recon
