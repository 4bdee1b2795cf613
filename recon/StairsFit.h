#pragma once
// A flight of stairs from the points above the ground: what `vkrecon init --template stairs`
// sets its priors by. The way up is the direction in which the points rise (a least-squares
// plane z = a·x + b·y + c through them: treads, risers and sides all climb that way); width
// and depth are the footprint's extent across and along it.

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace vkr::recon {

struct StairsFit {
  Eigen::Vector2d front = Eigen::Vector2d::Zero();  // the middle of the bottom step's front edge
  double yaw_deg = 0.0;  // the stairs' local +y, the way up, lies at yaw + 90° from +x
  double width = 1.0;    // across the way up (2nd–98th percentiles of the footprint)
  double depth = 1.0;    // along it
};

// Nothing when the points do not rise one way: the plane explains less than a tenth of the
// variance of their heights.
std::optional<StairsFit> FitStairs(const std::vector<Eigen::Vector3d>& above);

}  // namespace vkr::recon
