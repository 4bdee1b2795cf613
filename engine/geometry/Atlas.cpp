// The texture atlas (docs/internals/LIKELIHOOD.md, "Charts"): one chart per face, laid out once
// from the initial parameters so the surface-space likelihood (§5.2–5.5) compares views
// texel by texel in a fixed parametrisation of the surface.
//
// Chart sizes follow the faces' world extents so every face gets (about) the same number
// of texels per metre: a texel then stands for the same patch of surface everywhere, and
// the likelihood weighs surface area, not face count. A density per face scales that
// (likelihood.charts "pixels", AtlasFootprint.h): texels then follow what the photographs
// show of each face, and the view pass reads each chart's own texel area.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "engine/geometry/Atlas.h"

namespace vkr {
namespace {

constexpr int kMinChartTexels = 4;  // a chart never shrinks below 4×4 texels

// A face's world extent along face_uv's u and v, in metres.
struct Extent {
  int node = 0, face = 0;
  double u = 0.0, v = 0.0;
  double density = 1.0;  // multiplies the layout's scale for this face
};

// The largest ‖∂P/∂u‖ and ‖∂P/∂v‖ over the face's triangles, P the world position: for a
// planar face with an affine face_uv (all unit primitives) this is exactly the side
// lengths of the face's uv rectangle in metres; for curved faces (the cylinder side) it
// takes the most stretched triangle, so no part of the face is under-sampled.
Extent MeasureFace(const Mesh& mesh, const Face& face, const Eigen::Matrix4d& world_from_node) {
  Extent e;
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
    Eigen::Vector3d p[3];
    Eigen::Vector2d uv[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = mesh.indices[3 * t + k];
      p[k] = (world_from_node * mesh.positions[i].cast<double>().homogeneous()).head<3>();
      uv[k] = mesh.face_uv[i].cast<double>();
    }
    // [p1-p0, p2-p0] = J · [uv1-uv0, uv2-uv0], J = [∂P/∂u, ∂P/∂v].
    Eigen::Matrix2d duv;
    duv << uv[1] - uv[0], uv[2] - uv[0];
    const double det = duv.determinant();
    if (!(std::abs(det) > 1e-12)) continue;  // degenerate in uv: says nothing about scale
    Eigen::Matrix<double, 3, 2> dp;
    dp << p[1] - p[0], p[2] - p[0];
    const Eigen::Matrix<double, 3, 2> J = dp * duv.inverse();
    e.u = std::max(e.u, J.col(0).norm());
    e.v = std::max(e.v, J.col(1).norm());
  }
  return e;
}

int ChartSide(double metres, double texels_per_metre) {
  return std::max(kMinChartTexels, int(std::ceil(metres * texels_per_metre)));
}

// Shelf packing of the charts in `order` (tallest first) at `scale`: left to right along a
// shelf, a new shelf above when the row is full. Footprints are the charts plus `gutter`
// texels on every side. Returns false when they do not fit into size².
bool Shelve(const std::vector<Extent>& extents, const std::vector<int>& order, double scale,
            int size, int gutter, std::vector<Chart>* charts) {
  int x = 0, y = 0, shelf = 0;
  for (int i : order) {
    const double s = scale * extents[i].density;
    const int w = ChartSide(extents[i].u, s), h = ChartSide(extents[i].v, s);
    const int fw = w + 2 * gutter, fh = h + 2 * gutter;
    if (fw > size) return false;
    if (x + fw > size) {
      y += shelf;
      x = shelf = 0;
    }
    if (y + fh > size) return false;
    if (charts) {
      (*charts)[i] = {extents[i].node, extents[i].face, float(x + gutter), float(y + gutter),
                      float(w), float(h), s};
    }
    x += fw;
    shelf = std::max(shelf, fh);
  }
  return true;
}

}  // namespace

Eigen::Vector2f AtlasLayout::AtlasUv(const Chart& c, const Eigen::Vector2f& face_uv) const {
  return {(c.x + face_uv.x() * c.w) / float(size), (c.y + face_uv.y() * c.h) / float(size)};
}

AtlasLayout PackAtlas(const std::vector<Mesh>& meshes,
                      const std::vector<Eigen::Matrix4d>& world_from_node, int size, int gutter,
                      const std::vector<double>& density) {
  if (meshes.size() != world_from_node.size())
    throw std::invalid_argument("PackAtlas: one world_from_node per mesh expected");
  if (size <= 0 || gutter < 0) throw std::invalid_argument("PackAtlas: bad size or gutter");

  std::vector<Extent> extents;
  for (size_t n = 0; n < meshes.size(); ++n) {
    for (size_t f = 0; f < meshes[n].faces.size(); ++f) {
      Extent e = MeasureFace(meshes[n], meshes[n].faces[f], world_from_node[n]);
      e.node = int(n);
      e.face = int(f);
      extents.push_back(e);
    }
  }
  if (!density.empty()) {
    if (density.size() != extents.size())
      throw std::invalid_argument("PackAtlas: " + std::to_string(density.size()) + " densities for " +
                                  std::to_string(extents.size()) + " faces");
    for (size_t i = 0; i < extents.size(); ++i) {
      if (!(density[i] > 0.0 && std::isfinite(density[i])))
        throw std::invalid_argument("PackAtlas: face density " + std::to_string(density[i]) + " must be > 0");
      extents[i].density = density[i];
    }
  }

  // Chart heights grow monotonically with the scaled extent along v, so one sort serves
  // every scale; wider first among equals packs shelves a little tighter.
  std::vector<int> order(extents.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const double va = extents[a].v * extents[a].density, vb = extents[b].v * extents[b].density;
    const double ua = extents[a].u * extents[a].density, ub = extents[b].u * extents[b].density;
    return va != vb ? va > vb : ua > ub;
  });

  AtlasLayout layout;
  layout.size = size;
  layout.gutter = gutter;
  layout.charts.resize(extents.size());
  if (!Shelve(extents, order, 0.0, size, gutter, nullptr)) {
    throw std::invalid_argument("PackAtlas: " + std::to_string(extents.size()) +
                                " charts do not fit into a " + std::to_string(size) + "² atlas even at " +
                                std::to_string(kMinChartTexels) + " texels + " +
                                std::to_string(gutter) + " gutter per side");
  }
  // Bisect on the scale: 0 fits, and (size+1)/largest extent cannot (that chart alone
  // would be wider than the atlas). Shelf packing is not strictly monotone in the scale,
  // but `lo` always fits, which is all the layout needs.
  double largest = 0.0;
  for (const Extent& e : extents) largest = std::max({largest, e.u * e.density, e.v * e.density});
  double lo = 0.0;
  if (largest > 0.0) {
    double hi = (size + 1.0) / largest;
    for (int it = 0; it < 60 && hi - lo > 1e-9 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (Shelve(extents, order, mid, size, gutter, nullptr) ? lo : hi) = mid;
    }
  }
  Shelve(extents, order, lo, size, gutter, &layout.charts);
  layout.texels_per_metre = lo;
  return layout;
}

Image BakeAlbedoAtlas(const AtlasLayout& layout, const std::vector<Mesh>& meshes,
                      const std::vector<Image>& albedo) {
  const int n = layout.size;
  Image atlas(n, n, 0.0f);
  for (const Chart& c : layout.charts) {
    const Mesh& mesh = meshes.at(c.node);
    const Face& face = mesh.faces.at(c.face);
    const Image* image = size_t(c.node) < albedo.size() && !albedo[c.node].Empty() ? &albedo[c.node] : nullptr;
    for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
      Eigen::Vector2d a[3], uv[3];  // atlas position in texels, face_uv
      for (int k = 0; k < 3; ++k) {
        uv[k] = mesh.face_uv[mesh.indices[3 * t + k]].cast<double>();
        a[k] = {c.x + uv[k].x() * c.w, c.y + uv[k].y() * c.h};
      }
      auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, double x, double y) {
        return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
      };
      const double area = edge(a[0], a[1], a[2].x(), a[2].y());
      if (!(std::abs(area) > 1e-12)) continue;
      // Texels whose centres (i+0.5, j+0.5) can lie inside the triangle.
      const int x0 = std::max(0, int(std::floor(std::min({a[0].x(), a[1].x(), a[2].x()}) - 0.5)));
      const int x1 = std::min(n - 1, int(std::ceil(std::max({a[0].x(), a[1].x(), a[2].x()}) - 0.5)));
      const int y0 = std::max(0, int(std::floor(std::min({a[0].y(), a[1].y(), a[2].y()}) - 0.5)));
      const int y1 = std::min(n - 1, int(std::ceil(std::max({a[0].y(), a[1].y(), a[2].y()}) - 0.5)));
      for (int j = y0; j <= y1; ++j) {
        for (int i = x0; i <= x1; ++i) {
          const double px = i + 0.5, py = j + 0.5;
          // Barycentrics; the test is inclusive (with a hair of slack for rounding) so a
          // texel centre on an edge shared by two triangles of a face is never lost.
          const double b0 = edge(a[1], a[2], px, py) / area;
          const double b1 = edge(a[2], a[0], px, py) / area;
          const double b2 = 1.0 - b0 - b1;
          constexpr double kSlack = -1e-7;
          if (b0 < kSlack || b1 < kSlack || b2 < kSlack) continue;
          const Eigen::Vector2d f = b0 * uv[0] + b1 * uv[1] + b2 * uv[2];
          float* out = atlas.At(i, j);
          if (image) {
            SampleRepeat(*image, f.x(), f.y(), out);
          } else {
            out[0] = out[1] = out[2] = 0.5f;
          }
          out[3] = 1.0f;
        }
      }
    }
  }

  // Bleed into the gutters: each round gives every empty texel the mean of its already
  // painted 4-neighbours, so bilinear lookups at a chart's border read its own colour. Charts
  // lie ≥ 2·gutter apart, so `gutter` rounds never let two charts meet in one texel.
  // Filled texels get alpha 0.5: distinguishable from covered (1) and empty (0).
  std::vector<std::pair<size_t, Eigen::Vector3f>> fill;
  for (int round = 0; round < layout.gutter; ++round) {
    fill.clear();
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        if (atlas.At(i, j)[3] > 0.0f) continue;
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        int count = 0;
        const int nb[4][2] = {{i - 1, j}, {i + 1, j}, {i, j - 1}, {i, j + 1}};
        for (const auto& q : nb) {
          if (q[0] < 0 || q[1] < 0 || q[0] >= n || q[1] >= n) continue;
          const float* p = atlas.At(q[0], q[1]);
          if (p[3] > 0.0f) {
            sum += Eigen::Vector3f(p[0], p[1], p[2]);
            ++count;
          }
        }
        if (count) fill.emplace_back(size_t(j) * n + i, sum / float(count));
      }
    }
    for (const auto& [index, colour] : fill) {
      float* p = &atlas.rgba[index * 4];
      p[0] = colour.x();
      p[1] = colour.y();
      p[2] = colour.z();
      p[3] = 0.5f;
    }
  }
  return atlas;
}

}  // namespace vkr
