#include "recon/StairsFit.h"

#include <Eigen/Dense>
#include <cmath>

#include "optimiser/Statistics.h"

namespace vkr::recon {

// The share of the heights' variance the plane must explain. Synthesised from the bundled
// assets: stairs 0.23 (their back and sides climb less than their treads), a box 0.014.
constexpr double kMinExplained = 0.1;

std::optional<StairsFit> FitStairs(const std::vector<Eigen::Vector3d>& above) {
  if (above.size() < 3) return std::nullopt;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  std::vector<double> heights;
  for (const Eigen::Vector3d& p : above) {
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    normal += row * row.transpose();
    right += row * p.z();
    heights.push_back(p.z());
  }
  const Eigen::Vector3d plane = normal.ldlt().solve(right);  // z = a·x + b·y + c
  const Eigen::Vector2d slope = plane.head<2>();
  if (!(slope.norm() > 0.0) || !slope.allFinite()) return std::nullopt;
  const Eigen::Vector2d up = slope.normalized(), across(up.y(), -up.x());
  std::vector<double> along, side;
  for (const Eigen::Vector3d& p : above) along.push_back(up.dot(p.head<2>())), side.push_back(across.dot(p.head<2>()));
  StairsFit fit;
  const double first = opt::Quantile(along, 0.02), last = opt::Quantile(along, 0.98);
  const double left = opt::Quantile(side, 0.02), right_edge = opt::Quantile(side, 0.98);
  fit.depth = last - first;
  fit.width = right_edge - left;
  // How much of the heights' spread the plane explains: stairs climb, a box's faces do not.
  double residual = 0.0, spread = 0.0;
  const double mean = opt::Mean(heights);
  for (const Eigen::Vector3d& p : above) {
    residual += std::pow(p.z() - plane.dot(Eigen::Vector3d(p.x(), p.y(), 1.0)), 2);
    spread += std::pow(p.z() - mean, 2);
  }
  const double explained = spread > 0.0 ? 1.0 - residual / spread : 0.0;
  if (explained < kMinExplained) return std::nullopt;
  fit.front = first * up + 0.5 * (left + right_edge) * across;
  fit.yaw_deg = std::atan2(up.y(), up.x()) * 180.0 / M_PI - 90.0;
  if (fit.yaw_deg <= -180.0) fit.yaw_deg += 360.0;
  return fit;
}

}  // namespace vkr::recon
