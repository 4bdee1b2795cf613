#include "recon/CornerFit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include "optimiser/Statistics.h"

namespace vkr::recon {
namespace {

using Vec2 = Eigen::Vector2d;

struct FootprintLine {
  Vec2 point = Vec2::Zero(), direction = Vec2::UnitX();  // direction is unit
  std::vector<size_t> inliers;
};

double LineDistance(const FootprintLine& l, const Vec2& p) {
  const Vec2 d = p - l.point;
  return std::abs(d.x() * l.direction.y() - d.y() * l.direction.x());
}

void CountLineInliers(const std::vector<Vec2>& points, const std::vector<size_t>& candidates, double tolerance,
                      FootprintLine& line) {
  line.inliers.clear();
  for (size_t i : candidates)
    if (LineDistance(line, points[i]) <= tolerance) line.inliers.push_back(i);
}

// The principal axis through the inliers' mean, then their count again.
void RefitLine(const std::vector<Vec2>& points, const std::vector<size_t>& candidates, double tolerance,
               FootprintLine& line) {
  Vec2 mean = Vec2::Zero();
  for (size_t i : line.inliers) mean += points[i];
  mean /= double(line.inliers.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (size_t i : line.inliers) scatter += (points[i] - mean) * (points[i] - mean).transpose();
  line.point = mean;
  line.direction = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(1);
  CountLineInliers(points, candidates, tolerance, line);
}

// The line through most of `candidates`, at least `min_turn` radians from `away` when given.
std::optional<FootprintLine> BestLine(const std::vector<Vec2>& points, const std::vector<size_t>& candidates,
                                      double tolerance, std::mt19937_64& rng, const std::optional<Vec2>& away,
                                      double min_turn) {
  if (candidates.size() < 2) return std::nullopt;
  std::uniform_int_distribution<size_t> pick(0, candidates.size() - 1);
  std::optional<FootprintLine> best;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 a = points[candidates[pick(rng)]], b = points[candidates[pick(rng)]];
    if ((b - a).norm() <= tolerance) continue;
    FootprintLine line{a, (b - a).normalized(), {}};
    if (away && std::abs(line.direction.x() * away->y() - line.direction.y() * away->x()) < std::sin(min_turn)) continue;
    CountLineInliers(points, candidates, tolerance, line);
    if (!best || line.inliers.size() > best->inliers.size()) best = std::move(line);
  }
  if (!best || best->inliers.size() < 2) return std::nullopt;
  RefitLine(points, candidates, tolerance, *best);
  return best;
}

// Points `line`'s direction from `corner` towards most of its inliers; the far end's distance.
double OrientFromCorner(const std::vector<Vec2>& points, const Vec2& corner, FootprintLine& line) {
  std::vector<double> along;
  for (size_t i : line.inliers) along.push_back(line.direction.dot(points[i] - corner));
  if (opt::Quantile(along, 0.5) < 0.0) {
    line.direction = -line.direction;
    for (double& t : along) t = -t;
  }
  return opt::Quantile(along, 0.98);
}

double Degrees(double radians) { return radians * 180.0 / M_PI; }

}  // namespace

CornerResult FitCorner(const std::vector<Vec2>& footprint, const std::vector<Vec2>& cameras, double tolerance,
                       std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<size_t> all(footprint.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  const double min_turn = 30.0 * M_PI / 180.0;
  std::optional<FootprintLine> a = BestLine(footprint, all, tolerance, rng, std::nullopt, 0.0);
  if (!a) return {std::nullopt, "the points above the ground lie on no wall"};
  std::vector<size_t> rest;
  for (size_t i : all)
    if (LineDistance(*a, footprint[i]) > tolerance) rest.push_back(i);
  std::optional<FootprintLine> b = BestLine(footprint, rest, tolerance, rng, a->direction, min_turn);
  const size_t needed = std::max<size_t>(10, footprint.size() / 10);
  if (!b || b->inliers.size() < needed)
    return {std::nullopt, "the points above the ground lie on one wall: " + std::to_string(b ? b->inliers.size() : 0) + " of " +
                              std::to_string(footprint.size()) + " on a second, at least 30° from the first; it needs " +
                              std::to_string(needed)};
  // a.point + s·a.dir = b.point + t·b.dir
  Eigen::Matrix2d m;
  m << a->direction, -b->direction;
  const Vec2 st = m.colPivHouseholderQr().solve(b->point - a->point);
  CornerFit fit;
  fit.corner = a->point + st.x() * a->direction;
  fit.length_a = OrientFromCorner(footprint, fit.corner, *a);
  fit.length_b = OrientFromCorner(footprint, fit.corner, *b);
  if (a->direction.x() * b->direction.y() - a->direction.y() * b->direction.x() < 0.0) {
    std::swap(a, b);
    std::swap(fit.length_a, fit.length_b);
  }
  // Behind either wall a camera would see its back: all but a few stand between them.
  m << a->direction, b->direction;
  const Eigen::Matrix2d to_walls = m.inverse();
  size_t between = 0;
  for (const Vec2& c : cameras) {
    const Vec2 ab = to_walls * (c - fit.corner);
    between += ab.x() > 0.0 && ab.y() > 0.0;
  }
  if (cameras.empty() || double(between) < 0.8 * double(cameras.size()))
    return {std::nullopt, std::to_string(between) + " of " + std::to_string(cameras.size()) +
                              " cameras stand between the two walls the points lie on (an inside corner needs 80 %); "
                              "for a building's outside corner use the box or house template"};
  fit.yaw_deg = Degrees(std::atan2(a->direction.y(), a->direction.x()));
  fit.angle_deg = Degrees(std::acos(std::clamp(a->direction.dot(b->direction), -1.0, 1.0)));
  fit.inliers_a = int(a->inliers.size());
  fit.inliers_b = int(b->inliers.size());
  return {fit, ""};
}

}  // namespace vkr::recon
