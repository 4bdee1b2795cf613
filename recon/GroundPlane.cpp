#include "recon/GroundPlane.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>

namespace vkr::recon {
namespace {

// Counts of `plane` over `points`: inliers within the tolerance, points below 3 of them.
void CountSupport(const std::vector<Eigen::Vector3d>& points, double tolerance, GroundPlane& plane) {
  plane.inliers = plane.below = 0;
  for (const Eigen::Vector3d& x : points) {
    const double h = plane.Height(x);
    plane.inliers += std::abs(h) <= tolerance;
    plane.below += h < -3.0 * tolerance;
  }
}

// The plane with normal `n` (any sign) through `at`, facing `up`; nothing past the tilt.
std::optional<GroundPlane> Facing(Eigen::Vector3d n, const Eigen::Vector3d& at, const GroundPlaneOptions& o) {
  if (!(n.norm() > 0.0)) return std::nullopt;
  n.normalize();
  if (n.dot(o.up) < 0.0) n = -n;
  if (n.dot(o.up) < std::cos(o.max_tilt_deg * M_PI / 180.0)) return std::nullopt;
  GroundPlane plane;
  plane.normal = n;
  plane.offset = n.dot(at);
  return plane;
}

bool Acceptable(const GroundPlane& p, size_t count, const GroundPlaneOptions& o) {
  return p.below <= o.max_below * double(count);
}

// The least-squares plane of `plane`'s inliers (the smallest principal axis of their
// scatter), refitted twice as its inliers settle.
GroundPlane Refit(const std::vector<Eigen::Vector3d>& points, GroundPlane plane, const GroundPlaneOptions& o) {
  for (int round = 0; round < 3; ++round) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::vector<const Eigen::Vector3d*> in;
    for (const Eigen::Vector3d& x : points)
      if (std::abs(plane.Height(x)) <= o.tolerance) in.push_back(&x), mean += x;
    if (in.size() < 3) break;
    mean /= double(in.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d* x : in) scatter += (*x - mean) * (*x - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    Eigen::Vector3d n = eig.eigenvectors().col(0);
    if (n.dot(plane.normal) < 0.0) n = -n;
    plane.normal = n;
    plane.offset = n.dot(mean);
    CountSupport(points, o.tolerance, plane);
  }
  return plane;
}

}  // namespace

std::optional<GroundPlane> FitGroundPlane(const std::vector<Eigen::Vector3d>& points,
                                          const GroundPlaneOptions& options) {
  if (points.size() < 3) return std::nullopt;
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  std::vector<Eigen::Vector3d> sample;
  const size_t stride = (points.size() + size_t(options.support_sample) - 1) / size_t(std::max(options.support_sample, 1));
  for (size_t i = 0; i < points.size(); i += std::max<size_t>(stride, 1)) sample.push_back(points[i]);
  const auto score = [&](const GroundPlane& p) { return double(p.inliers) * p.normal.dot(options.up) - double(p.below); };
  std::optional<GroundPlane> best;
  for (int i = 0; i < options.iterations; ++i) {
    const Eigen::Vector3d &a = points[pick(rng)], &b = points[pick(rng)], &c = points[pick(rng)];
    std::optional<GroundPlane> plane = Facing((b - a).cross(c - a), a, options);
    if (!plane) continue;
    CountSupport(sample, options.tolerance, *plane);
    if (Acceptable(*plane, sample.size(), options) && (!best || score(*plane) > score(*best))) best = plane;
  }
  if (!best) return std::nullopt;
  CountSupport(points, options.tolerance, *best);
  GroundPlane refit = Refit(points, *best, options);
  // The refit may lean past the tilt or drop support; then the RANSAC plane stands.
  if (refit.normal.dot(options.up) < std::cos(options.max_tilt_deg * M_PI / 180.0) ||
      !Acceptable(refit, points.size(), options) || refit.inliers < best->inliers / 2)
    refit = *best;
  const double needed = std::max(double(options.min_inliers), options.min_inlier_share * double(points.size()));
  if (refit.inliers < needed) return std::nullopt;
  return refit;
}

}  // namespace vkr::recon
