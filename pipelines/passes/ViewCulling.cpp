#include "pipelines/passes/ViewCulling.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>

namespace vkr {
namespace {

// At most about this many clusters per scene: the host tests every cluster for every camera
// of every hypothesis (a few µs per hundred), and a mesh of 100 k triangles should not make
// that cost more than the pass it saves.
constexpr int kMaxClusters = 512;
// Relative margins of the tests, far above the shader's float rounding (~1e-6).
constexpr double kFrustumMargin = 1e-4;
constexpr double kFacingMargin = 1e-3;
// A cluster is drawn in parts only when it holds at least this share of the charts' area
// and its shaded rectangle leaves out at least kPartialSaving of its atlas bounds: each part
// is a draw of its own (five per camera), worth it for a ground, not for a window.
constexpr double kPartialMinArea = 0.02;
constexpr double kPartialSaving = 0.1;

void Append(std::vector<IndexRun>& runs, IndexRun run) {
  if (!runs.empty() && runs.back().first + runs.back().count == run.first) runs.back().count += run.count;
  else runs.push_back(run);
}

}  // namespace

ViewCulling::ViewCulling(const SceneGeometry& geometry) : index_count_(uint32_t(geometry.indices.size())) {
  const int triangles = int(geometry.indices.size() / 3);
  const int per_cluster = std::max(2, (triangles + kMaxClusters - 1) / kMaxClusters);
  const auto& v = geometry.vertices;
  const auto& idx = geometry.indices;
  int t = 0;
  while (t < triangles) {
    // A run of triangles of one face (SceneGeometry emits faces contiguously), at most per_cluster.
    const uint32_t face = v[idx[3 * size_t(t)]].face;
    int end = t + 1;
    while (end < triangles && end - t < per_cluster && v[idx[3 * size_t(end)]].face == face) ++end;
    Cluster c;
    c.indices = {uint32_t(3 * t), uint32_t(3 * (end - t))};
    c.node = int(v[idx[3 * size_t(t)]].node);
    std::vector<uint32_t> corners(idx.begin() + 3 * t, idx.begin() + 3 * end);
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    auto position = [&](uint32_t i) { return Eigen::Vector3d(v[i].position[0], v[i].position[1], v[i].position[2]); };
    auto normal = [&](uint32_t i) { return Eigen::Vector3d(v[i].normal[0], v[i].normal[1], v[i].normal[2]); };
    Eigen::Vector3d lo = position(corners[0]), hi = lo;
    for (uint32_t i : corners) lo = lo.cwiseMin(position(i)), hi = hi.cwiseMax(position(i));
    if (corners.size() <= 8) {
      for (uint32_t i : corners) c.hull.push_back(position(i));
    } else {
      for (int k = 0; k < 8; ++k)
        c.hull.emplace_back(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z());
    }
    // Flat: every vertex carries the same normal and lies in one plane with it, so the sign
    // of (centre − p)·n is the same at every point: the back-face test holds for all texels.
    c.normal = normal(corners[0]);
    const double extent = std::max((hi - lo).norm(), 1e-12);
    c.flat = c.normal.norm() > 0.0;
    for (uint32_t i : corners)
      c.flat = c.flat && normal(i) == c.normal &&
               std::abs((position(i) - position(corners[0])).dot(c.normal)) <= 1e-6 * extent * c.normal.norm();
    for (int k = t; k < end; ++k) {
      const float* a = v[idx[3 * size_t(k)]].atlas_uv;
      const float* b = v[idx[3 * size_t(k) + 1]].atlas_uv;
      const float* e = v[idx[3 * size_t(k) + 2]].atlas_uv;
      c.area += 0.5 * std::abs(double((b[0] - a[0]) * (e[1] - a[1]) - (b[1] - a[1]) * (e[0] - a[0])));
      for (int j = 0; j < 3; ++j) {
        const uint32_t i = idx[3 * size_t(k) + size_t(j)];
        c.corners.push_back(position(i));
        c.corner_uvs.emplace_back(v[i].atlas_uv[0], v[i].atlas_uv[1]);
      }
    }
    c.uv_lo = c.uv_hi = c.corner_uvs.front();
    for (const Eigen::Vector2d& uv : c.corner_uvs) c.uv_lo = c.uv_lo.cwiseMin(uv), c.uv_hi = c.uv_hi.cwiseMax(uv);
    clusters_.push_back(std::move(c));
    t = end;
  }
  double total = 0.0;
  for (const Cluster& c : clusters_) total += c.area;
  if (total > 0.0)
    for (Cluster& c : clusters_) c.area /= total;
  for (Cluster& c : clusters_)
    if (!(c.area >= kPartialMinArea)) c.corners.clear(), c.corner_uvs.clear();
}

bool ViewCulling::VisibleRect(const Cluster& cluster, const Eigen::Matrix4d& clip_from_node, double near,
                              PartialRun* rect) const {
  // A point is kept where view_texture.frag might shade it: |x| ≤ w, |y| ≤ w, w > near, each
  // plane moved outwards by the margin Unseen() allows. Points are tracked by barycentric
  // coordinates, in which the planes are linear, so the clipped corners map to the atlas.
  bool any = false;
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (size_t t = 0; t + 2 < cluster.corners.size(); t += 3) {
    Eigen::Vector4d c[3];
    for (int j = 0; j < 3; ++j) c[j] = clip_from_node * cluster.corners[t + size_t(j)].homogeneous();
    if (!(c[0].allFinite() && c[1].allFinite() && c[2].allFinite())) {
      // A degenerate node matrix: what the shader makes of NaN is its own business, so the
      // whole cluster is shaded, as Unseen() leaves it.
      rect->indices = cluster.indices;
      rect->u0 = cluster.uv_lo.x(), rect->v0 = cluster.uv_lo.y(), rect->u1 = cluster.uv_hi.x(), rect->v1 = cluster.uv_hi.y();
      return true;
    }
    double scale = near;
    for (const Eigen::Vector4d& p : c) scale = std::max({scale, std::abs(p.x()), std::abs(p.y()), std::abs(p.w())});
    const double m = 4.0 * kFrustumMargin * scale;
    auto planes = [&](const Eigen::Vector4d& p) {
      return std::array<double, 5>{p.w() - p.x() + m, p.w() + p.x() + m, p.w() - p.y() + m, p.w() + p.y() + m,
                                   p.w() - near + m};
    };
    std::vector<Eigen::Vector3d> polygon = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 5 && !polygon.empty(); ++k) {
      auto value = [&](const Eigen::Vector3d& b) { return planes(b[0] * c[0] + b[1] * c[1] + b[2] * c[2])[size_t(k)]; };
      std::vector<Eigen::Vector3d> kept;
      for (size_t i = 0; i < polygon.size(); ++i) {
        const Eigen::Vector3d& a = polygon[i];
        const Eigen::Vector3d& b = polygon[(i + 1) % polygon.size()];
        const double fa = value(a), fb = value(b);
        if (fa >= 0.0) kept.push_back(a);
        if ((fa >= 0.0) != (fb >= 0.0)) kept.push_back(a + (fa / (fa - fb)) * (b - a));
      }
      polygon = std::move(kept);
    }
    for (const Eigen::Vector3d& b : polygon) {
      const Eigen::Vector2d uv = b[0] * cluster.corner_uvs[t] + b[1] * cluster.corner_uvs[t + 1] +
                                 b[2] * cluster.corner_uvs[t + 2];
      lo = lo.cwiseMin(uv), hi = hi.cwiseMax(uv);
      any = true;
    }
  }
  if (!any) return false;
  lo = lo.cwiseMax(cluster.uv_lo), hi = hi.cwiseMin(cluster.uv_hi);
  rect->indices = cluster.indices;
  rect->u0 = lo.x(), rect->v0 = lo.y(), rect->u1 = hi.x(), rect->v1 = hi.y();
  return true;
}

bool ViewCulling::Unseen(const Cluster& cluster, const Eigen::Matrix4d& world_from_node,
                         const Eigen::Matrix4d& clip_from_world, const Eigen::Vector3d& centre, double near) const {
  // Outside the frustum: every point strictly beyond one of its side planes, or before its
  // near plane (view_texture.frag rejects z ≤ near and |x/z| > 1, |y/z| > 1). Each test is
  // linear in the point, so holding at the hull's points it holds at every texel.
  bool beyond[5] = {true, true, true, true, true};
  double farthest = 0.0;
  const Eigen::Vector3d first = (world_from_node * cluster.hull.front().homogeneous()).head<3>();
  for (const Eigen::Vector3d& p : cluster.hull) {
    const Eigen::Vector4d w = world_from_node * p.homogeneous();
    farthest = std::max(farthest, (centre - w.head<3>()).norm());
    const Eigen::Vector4d c = clip_from_world * w;
    const double m = kFrustumMargin * (std::abs(c.x()) + std::abs(c.y()) + std::abs(c.w()) + near);
    beyond[0] = beyond[0] && c.x() - c.w() > m;
    beyond[1] = beyond[1] && -c.x() - c.w() > m;
    beyond[2] = beyond[2] && c.y() - c.w() > m;
    beyond[3] = beyond[3] && -c.y() - c.w() > m;
    beyond[4] = beyond[4] && c.w() - near < -m;
  }
  if (std::any_of(std::begin(beyond), std::end(beyond), [](bool b) { return b; })) return true;
  if (!cluster.flat) return false;
  // Back-facing: the shader's normal is the inverse transpose of the node matrix times the
  // vertex normal; cos θ at a texel is (centre − p)·n / (|centre − p| |n|), whose numerator
  // is the same over the plane. NaN (a degenerate matrix) fails the test: shaded.
  const Eigen::Vector3d n = world_from_node.topLeftCorner<3, 3>().inverse().transpose() * cluster.normal;
  const double facing = (centre - first).dot(n) / (n.norm() * farthest);
  return facing < -kFacingMargin;
}

ViewDraws ViewCulling::Classify(const std::vector<Eigen::Matrix4d>& world_from_node,
                                const Eigen::Matrix4d& clip_from_world, const Eigen::Vector3d& centre,
                                double near) const {
  ViewDraws draws;
  for (const Cluster& c : clusters_) {
    const Eigen::Matrix4d& world = world_from_node.at(size_t(c.node));
    bool unseen = Unseen(c, world, clip_from_world, centre, near);
    if (!unseen && !c.corners.empty()) {
      PartialRun part;
      unseen = !VisibleRect(c, clip_from_world * world, near, &part);
      const double bounds = (c.uv_hi - c.uv_lo).prod();
      const double left_out = bounds > 0.0 ? 1.0 - (part.u1 - part.u0) * (part.v1 - part.v0) / bounds : 0.0;
      if (!unseen && left_out >= kPartialSaving) {
        draws.partial.push_back(part);
        draws.unseen_area += c.area * left_out;
        continue;
      }
    }
    Append(unseen ? draws.unseen : draws.shaded, c.indices);
    if (unseen) draws.unseen_area += c.area;
  }
  return draws;
}

ViewDraws ViewCulling::ShadeAll() const {
  ViewDraws draws;
  if (index_count_ > 0) draws.shaded.push_back({0, index_count_});
  return draws;
}

}  // namespace vkr
