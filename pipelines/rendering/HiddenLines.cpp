#include "pipelines/rendering/HiddenLines.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace vkr {
namespace {

constexpr double kNearPlane = 1e-3;  // metres in front of the camera, as the overlays clip

// The part of a camera-frame triangle in front of the near plane: 0, 3 or 4 corners.
std::vector<Eigen::Vector3d> ClipAtNear(const std::array<Eigen::Vector3d, 3>& t) {
  std::vector<Eigen::Vector3d> out;
  for (size_t i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = t[i];
    const Eigen::Vector3d& b = t[(i + 1) % 3];
    const bool a_in = a.z() >= kNearPlane, b_in = b.z() >= kNearPlane;
    if (a_in) out.push_back(a);
    if (a_in != b_in) out.push_back(a + (b - a) * ((kNearPlane - a.z()) / (b.z() - a.z())));
  }
  return out;
}

}  // namespace

DepthBuffer::DepthBuffer(const Camera& camera, const std::vector<WorldTriangle>& triangles)
    : K_(camera.K), margin_x_(camera.width / 4), margin_y_(camera.height / 4),
      width_(camera.width + 2 * margin_x_), height_(camera.height + 2 * margin_y_),
      depth_(size_t(std::max(width_, 0)) * size_t(std::max(height_, 0)), std::numeric_limits<float>::infinity()) {
  for (const WorldTriangle& world : triangles) {
    std::array<Eigen::Vector3d, 3> cam;
    for (size_t i = 0; i < 3; ++i) cam[i] = (camera.cam_from_world * world[i].homogeneous()).head<3>();
    const std::vector<Eigen::Vector3d> polygon = ClipAtNear(cam);
    for (size_t i = 2; i < polygon.size(); ++i) Rasterise({polygon[0], polygon[i - 1], polygon[i]});
  }
}

// Depth interpolated as 1/z, which is linear in the image; pixel centres at (i + ½, j + ½).
void DepthBuffer::Rasterise(const std::array<Eigen::Vector3d, 3>& cam) {
  std::array<Eigen::Vector2d, 3> s;
  std::array<double, 3> inverse_z;
  for (size_t i = 0; i < 3; ++i) {
    const Eigen::Vector3d p = K_ * (cam[i] / cam[i].z());
    s[i] = Eigen::Vector2d(p.x() + margin_x_, p.y() + margin_y_);
    inverse_z[i] = 1.0 / cam[i].z();
  }
  const auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
    return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
  };
  const double area = edge(s[0], s[1], s[2]);
  if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) return;
  // Clamped before conversion: a corner just past the near plane projects far outside.
  const auto column = [&](double x) { return int(std::clamp(x, -1.0, double(width_))); };
  const auto row = [&](double y) { return int(std::clamp(y, -1.0, double(height_))); };
  const int x0 = std::max(0, column(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
  const int x1 = std::min(width_ - 1, column(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
  const int y0 = std::max(0, row(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
  const int y1 = std::min(height_ - 1, row(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      const double b0 = edge(s[1], s[2], p) / area, b1 = edge(s[2], s[0], p) / area, b2 = 1.0 - b0 - b1;
      if (b0 < 0.0 || b1 < 0.0 || b2 < 0.0) continue;
      const float z = float(1.0 / (b0 * inverse_z[0] + b1 * inverse_z[1] + b2 * inverse_z[2]));
      float& d = depth_[size_t(y) * size_t(width_) + size_t(x)];
      d = std::min(d, z);
    }
}

bool DepthBuffer::Visible(const Eigen::Vector3d& x_cam) const {
  if (x_cam.z() < kNearPlane) return false;
  const Eigen::Vector3d p = K_ * (x_cam / x_cam.z());
  const double bx = std::floor(p.x()) + margin_x_, by = std::floor(p.y()) + margin_y_;
  if (!(bx >= 1.0 && by >= 1.0 && bx < width_ - 1.0 && by < height_ - 1.0)) return true;  // NaN too
  const int px = int(bx), py = int(by);
  float nearest = std::numeric_limits<float>::infinity(), furthest = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const float d = At(px + dx, py + dy);
      if (!std::isfinite(d)) return true;  // open background beside it: an outline
      nearest = std::min(nearest, d), furthest = std::max(furthest, d);
    }
  return x_cam.z() - furthest <= (furthest - nearest) + 1e-3 * x_cam.z();
}

}  // namespace vkr
