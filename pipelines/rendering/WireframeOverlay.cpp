#include "pipelines/rendering/WireframeOverlay.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "engine/scene/Photographs.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

// Blends `colour` into pixel (x, y) with weight `w`; off the image: nothing.
void Blend(Image& image, int x, int y, double w, const std::array<float, 3>& colour, float opacity) {
  if (x < 0 || y < 0 || x >= image.width || y >= image.height || w <= 0.0) return;
  float* p = image.At(x, y);
  const float a = float(std::min(w, 1.0)) * opacity;
  for (int c = 0; c < 3; ++c) p[c] = p[c] * (1.0f - a) + colour[size_t(c)] * a;
}

double Fraction(double x) { return x - std::floor(x); }

// Xiaolin Wu's anti-aliased line between continuous pixel coordinates (pixel (i, j) spans
// [i, i+1) × [j, j+1), so its centre is at i + 0.5).
void DrawLine(Image& image, Eigen::Vector2d p0, Eigen::Vector2d p1, const std::array<float, 3>& colour,
              float opacity) {
  p0 -= Eigen::Vector2d(0.5, 0.5);  // to centre-at-integer coordinates
  p1 -= Eigen::Vector2d(0.5, 0.5);
  const bool steep = std::abs(p1.y() - p0.y()) > std::abs(p1.x() - p0.x());
  if (steep) {
    std::swap(p0.x(), p0.y());
    std::swap(p1.x(), p1.y());
  }
  if (p0.x() > p1.x()) std::swap(p0, p1);
  // Lines far off the image: clamp the sweep to where it could land.
  const double limit = double(steep ? image.height : image.width) + 1.0;
  const double y_limit = double(steep ? image.width : image.height) + 1.0;
  const double dx = p1.x() - p0.x(), dy = p1.y() - p0.y();
  const double gradient = dx == 0.0 ? 1.0 : dy / dx;
  auto plot = [&](int x, int y, double w) { steep ? Blend(image, y, x, w, colour, opacity) : Blend(image, x, y, w, colour, opacity); };
  const double x_start = std::max(std::round(p0.x()), -1.0), x_end = std::min(std::round(p1.x()), limit);
  for (double x = x_start; x <= x_end; x += 1.0) {
    // End pixels get the share of the pixel the line covers.
    double cover = 1.0;
    if (x == std::round(p0.x())) cover = 1.0 - Fraction(p0.x() + 0.5);
    if (x == std::round(p1.x())) cover = std::min(cover, Fraction(p1.x() + 0.5));
    if (x_start == x_end) cover = std::max(dx, 0.5);
    const double y = p0.y() + gradient * (x - p0.x());
    if (!(y > -2.0 && y < y_limit)) continue;  // off the image (and no int overflow far away)
    const int yi = int(std::floor(y));
    plot(int(x), yi, (1.0 - Fraction(y)) * cover);
    plot(int(x), yi + 1, Fraction(y) * cover);
  }
}

}  // namespace

Eigen::Vector2d LensPixel(const Camera& camera, const Eigen::Vector3d& x_cam) {
  Eigen::Vector2d n = x_cam.head<2>() / x_cam.z();
  if (!camera.distortion.IsNone()) n = camera.distortion.Distort(n);
  const Eigen::Vector3d p = camera.K * Eigen::Vector3d(n.x(), n.y(), 1.0);
  return p.head<2>() / p.z();
}

NodeWire WeldWire(const Mesh& mesh) {
  NodeWire wire;
  if (mesh.indices.empty()) return wire;
  // Positions equal to ~1e-6 of the mesh's size are one.
  Eigen::Vector3f lo = mesh.positions[0], hi = lo;
  for (const auto& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double quantum = std::max(1e-6 * double((hi - lo).norm()), 1e-9);
  std::map<std::tuple<long long, long long, long long>, int> welded;
  std::vector<int> weld(mesh.positions.size());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3f& p = mesh.positions[i];
    const auto key = std::make_tuple(std::llround(p.x() / quantum), std::llround(p.y() / quantum),
                                     std::llround(p.z() / quantum));
    const auto [it, inserted] = welded.emplace(key, int(wire.vertices.size()));
    if (inserted) wire.vertices.push_back(p.cast<double>());
    weld[i] = it->second;
  }
  std::map<std::pair<int, int>, size_t> index;  // welded vertex pair → edge
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const std::array<int, 3> v = {weld[mesh.indices[t]], weld[mesh.indices[t + 1]], weld[mesh.indices[t + 2]]};
    const int triangle = int(wire.triangles.size());
    wire.triangles.push_back(v);
    for (int k = 0; k < 3; ++k) {
      const int a = v[size_t(k)], b = v[size_t(k + 1) % 3];
      if (a == b) continue;
      const auto [it, inserted] = index.emplace(std::minmax(a, b), wire.edges.size());
      if (inserted) wire.edges.push_back({std::min(a, b), std::max(a, b), {}});
      wire.edges[it->second].triangles.push_back(triangle);
    }
  }
  return wire;
}

std::vector<WireEdge> SceneEdges(const Scene& scene, const SceneGeometry& geometry, const std::vector<double>& psi) {
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  std::vector<WireEdge> edges;
  for (size_t node = 0; node < geometry.meshes.size() && node < world_from_node.size(); ++node) {
    const NodeWire wire = WeldWire(geometry.meshes[node]);
    std::vector<Eigen::Vector3d> world;
    for (const Eigen::Vector3d& p : wire.vertices) world.push_back((world_from_node[node] * p.homogeneous()).head<3>());
    std::vector<Eigen::Vector3d> normals;  // zero for a triangle the transform collapses
    for (const auto& v : wire.triangles) {
      const Eigen::Vector3d n = (world[size_t(v[1])] - world[size_t(v[0])]).cross(world[size_t(v[2])] - world[size_t(v[0])]);
      normals.push_back(n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::Zero());
    }
    for (const NodeWire::Edge& e : wire.edges) {
      WireEdge edge{world[size_t(e.a)], world[size_t(e.b)], {}};
      for (int t : e.triangles)
        if (!normals[size_t(t)].isZero()) edge.normals.push_back(normals[size_t(t)]);
      if (!edge.normals.empty()) edges.push_back(std::move(edge));
    }
  }
  return edges;
}

std::vector<WorldTriangle> SceneTriangles(const Scene& scene, const SceneGeometry& geometry,
                                          const std::vector<double>& psi) {
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  std::vector<WorldTriangle> triangles;
  for (size_t node = 0; node < geometry.meshes.size() && node < world_from_node.size(); ++node) {
    const Mesh& mesh = geometry.meshes[node];
    const auto world = [&](uint32_t i) {
      return (world_from_node[node] * mesh.positions[i].cast<double>().homogeneous()).head<3>().eval();
    };
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
      triangles.push_back({world(mesh.indices[t]), world(mesh.indices[t + 1]), world(mesh.indices[t + 2])});
  }
  return triangles;
}

bool IsDrawnEdge(const WireEdge& edge, const Eigen::Vector3d& centre, const WireframeOptions& options) {
  if (edge.normals.size() != 2) return true;  // a boundary (or a non-manifold edge)
  const Eigen::Vector3d& n0 = edge.normals[0];
  const Eigen::Vector3d& n1 = edge.normals[1];
  if (n0.dot(n1) < std::cos(options.crease_degrees * M_PI / 180.0)) return true;
  const Eigen::Vector3d view = centre - 0.5 * (edge.a + edge.b);
  return (n0.dot(view) > 0.0) != (n1.dot(view) > 0.0);  // silhouette
}

Image DrawWireframe(const Image& photo, const Camera& camera, const std::vector<WireEdge>& edges,
                    const WireframeOptions& options, const DepthBuffer* hidden) {
  Image out = photo;
  const Eigen::Vector3d centre = camera.Centre();
  constexpr double kNear = 1e-3;  // metres in front of the camera
  const int pieces = camera.distortion.IsNone() ? 1 : 32;
  for (const WireEdge& edge : edges) {
    if (!IsDrawnEdge(edge, centre, options)) continue;
    Eigen::Vector3d a = (camera.cam_from_world * edge.a.homogeneous()).head<3>();
    Eigen::Vector3d b = (camera.cam_from_world * edge.b.homogeneous()).head<3>();
    if (a.z() < kNear && b.z() < kNear) continue;
    if (a.z() < kNear) a = b + (a - b) * ((b.z() - kNear) / (b.z() - a.z()));
    if (b.z() < kNear) b = a + (b - a) * ((a.z() - kNear) / (a.z() - b.z()));
    Eigen::Vector2d from = LensPixel(camera, a);
    int steps = pieces;
    if (hidden) {  // a piece per pixel, so that visibility changes where the occluder's edge is
      const double length = (LensPixel(camera, b) - from).norm();
      steps = std::max(pieces, int(std::min(std::ceil(std::isfinite(length) ? length : 0.0), 4096.0)));
    }
    for (int k = 1; k <= steps; ++k) {
      const Eigen::Vector2d to = LensPixel(camera, a + (b - a) * (double(k) / steps));
      const bool seen = !hidden || hidden->Visible(a + (b - a) * ((k - 0.5) / steps));
      if (seen && from.allFinite() && to.allFinite()) DrawLine(out, from, to, options.colour, options.opacity);
      from = to;
    }
  }
  return out;
}

std::vector<fs::path> WriteWireframeOverlays(const fs::path& dir, const Scene& scene, const SceneGeometry& geometry,
                                             const std::vector<double>& psi, const WireframeOptions& options) {
  fs::create_directories(dir);
  const std::vector<WireEdge> edges = SceneEdges(scene, geometry, psi);
  const std::vector<WorldTriangle> triangles = SceneTriangles(scene, geometry, psi);
  std::vector<fs::path> written;
  for (const Camera& camera : scene.Cameras(psi)) {
    const fs::path file = dir / (camera.name + ".png");
    const DepthBuffer hidden(camera, triangles);
    WritePng(file, DrawWireframe(LoadPhotograph(camera.image, camera.shrink), camera, edges, options, &hidden));
    written.push_back(file);
  }
  return written;
}

}  // namespace vkr
