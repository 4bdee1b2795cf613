// The unit primitives (docs/guide/SCENE_FORMAT.md, "nodes"): extent, faces, orientation,
// closedness, areas and volumes, and the upright face_uv convention documented in Primitives.cpp.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <tuple>

#include "engine/geometry/Mesh.h"

namespace vkr {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

Vector3d P(const Mesh& m, int t, int k) { return m.positions[m.indices[3 * t + k]].cast<double>(); }

double Area(const Mesh& m) {
  double a = 0;
  for (int t = 0; t < m.TriangleCount(); ++t) a += 0.5 * (P(m, t, 1) - P(m, t, 0)).cross(P(m, t, 2) - P(m, t, 0)).norm();
  return a;
}

// Divergence theorem: V = Σ p0·(p1×p2)/6 over a closed, outward-wound surface.
double Volume(const Mesh& m) {
  double v = 0;
  for (int t = 0; t < m.TriangleCount(); ++t) v += P(m, t, 0).dot(P(m, t, 1).cross(P(m, t, 2))) / 6.0;
  return v;
}

// Faces cover all triangles in order; data arrays agree; everything inside the unit box.
void CheckStructure(const Mesh& m, size_t faces) {
  ASSERT_EQ(m.faces.size(), faces);
  int next = 0;
  for (const Face& f : m.faces) {
    EXPECT_EQ(f.first_triangle, next);
    EXPECT_GT(f.triangle_count, 0);
    next += f.triangle_count;
  }
  EXPECT_EQ(next, m.TriangleCount());
  ASSERT_EQ(m.indices.size() % 3, 0u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  ASSERT_EQ(m.face_uv.size(), m.positions.size());
  for (uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const Vector3f& p = m.positions[i];
    EXPECT_TRUE(p.x() >= -0.5f && p.x() <= 0.5f && p.y() >= -0.5f && p.y() <= 0.5f && p.z() >= 0.0f && p.z() <= 1.0f) << p.transpose();
    EXPECT_NEAR(m.normals[i].norm(), 1.0f, 1e-5f);
    const Vector2f& uv = m.face_uv[i];
    EXPECT_TRUE(uv.x() >= 0.0f && uv.x() <= 1.0f && uv.y() >= 0.0f && uv.y() <= 1.0f) << uv.transpose();
  }
}

// Each triangle is counter-clockwise from outside: its right-hand normal agrees with the
// vertex normals and points away from `inside`, a point inside the (convex) solid.
void CheckOutward(const Mesh& m, const Vector3d& inside) {
  for (int t = 0; t < m.TriangleCount(); ++t) {
    const Vector3d n = (P(m, t, 1) - P(m, t, 0)).cross(P(m, t, 2) - P(m, t, 0));
    ASSERT_GT(n.norm(), 1e-9) << "degenerate triangle " << t;
    EXPECT_GT(n.dot(P(m, t, 0) - inside), 0.0) << "triangle " << t << " faces inwards";
    for (int k = 0; k < 3; ++k)
      EXPECT_GT(n.normalized().dot(m.normals[m.indices[3 * t + k]].cast<double>()), 0.5) << "triangle " << t;
  }
}

// Watertight and consistently wound: every directed edge (by position) appears once, and
// its reverse once.
void CheckClosed(const Mesh& m) {
  auto key = [](const Vector3d& p) {
    return std::make_tuple(std::lround(p.x() * 1e5), std::lround(p.y() * 1e5), std::lround(p.z() * 1e5));
  };
  using Key = decltype(key(Vector3d()));
  std::map<std::pair<Key, Key>, int> edges;
  for (int t = 0; t < m.TriangleCount(); ++t)
    for (int k = 0; k < 3; ++k) ++edges[{key(P(m, t, k)), key(P(m, t, (k + 1) % 3))}];
  for (const auto& [e, count] : edges) {
    EXPECT_EQ(count, 1);
    const auto it = edges.find({e.second, e.first});
    EXPECT_TRUE(it != edges.end() && it->second == 1) << "open or inconsistently wound edge";
  }
}

// ∂P/∂u and ∂P/∂v of triangle t (P in the node frame).
std::pair<Vector3d, Vector3d> Jacobian(const Mesh& m, int t) {
  Eigen::Matrix2d duv;
  Eigen::Matrix<double, 3, 2> dp;
  const auto uv = [&](int k) { return m.face_uv[m.indices[3 * t + k]].cast<double>(); };
  duv << uv(1) - uv(0), uv(2) - uv(0);
  dp << P(m, t, 1) - P(m, t, 0), P(m, t, 2) - P(m, t, 0);
  const Eigen::Matrix<double, 3, 2> J = dp * duv.inverse();
  return {J.col(0), J.col(1)};
}

// The albedo stands upright and unmirrored seen from outside: u runs to the viewer's right,
// v downwards (z down on non-horizontal faces, -y on horizontal ones).
void CheckUpright(const Mesh& m) {
  for (int t = 0; t < m.TriangleCount(); ++t) {
    const auto [du, dv] = Jacobian(m, t);
    const Vector3d n = (P(m, t, 1) - P(m, t, 0)).cross(P(m, t, 2) - P(m, t, 0)).normalized();
    const Vector3d right = du.normalized(), up = -dv.normalized();
    EXPECT_GT(right.cross(up).dot(n), 0.0) << "mirrored image on triangle " << t;
    const bool horizontal = std::abs(n.z()) > 0.999;
    if (horizontal) EXPECT_GT(up.y(), 0.99) << "triangle " << t;
    else EXPECT_GT(up.z(), 0.0) << "upside-down image on triangle " << t;
  }
}

TEST(Primitives, PlaneIsOneUpwardSquare) {
  const Mesh m = MakePrimitive(PrimitiveKind::Plane);
  CheckStructure(m, 1);
  EXPECT_NEAR(Area(m), 1.0, 1e-6);
  for (int t = 0; t < m.TriangleCount(); ++t)
    EXPECT_GT((P(m, t, 1) - P(m, t, 0)).cross(P(m, t, 2) - P(m, t, 0)).z(), 0.0);
  for (const Vector3f& n : m.normals) EXPECT_EQ(n, Vector3f(0, 0, 1));
  for (const Vector3f& p : m.positions) EXPECT_EQ(p.z(), 0.0f);
  CheckUpright(m);
  // The image's top-left corner lies at (-0.5, +0.5): north up, seen from above.
  for (size_t i = 0; i < m.positions.size(); ++i)
    EXPECT_EQ(m.face_uv[i], Vector2f(m.positions[i].x() + 0.5f, 0.5f - m.positions[i].y()));
}

TEST(Primitives, BoxIsTheClosedUnitCube) {
  const Mesh m = MakePrimitive(PrimitiveKind::Box);
  CheckStructure(m, 6);
  EXPECT_EQ(m.positions.size(), 24u);
  EXPECT_EQ(m.TriangleCount(), 12);
  CheckOutward(m, {0, 0, 0.5});
  CheckClosed(m);
  CheckUpright(m);
  EXPECT_NEAR(Area(m), 6.0, 1e-6);
  EXPECT_NEAR(Volume(m), 1.0, 1e-6);
  // Flat normals: each face's vertices share one axis-aligned normal.
  for (const Face& f : m.faces) {
    const Vector3f n = m.normals[m.indices[3 * f.first_triangle]];
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0f, 1e-6f);
    for (int t = f.first_triangle; t < f.first_triangle + f.triangle_count; ++t)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[m.indices[3 * t + k]], n);
  }
  // Vertical faces: v = 0 at the top edge.
  for (size_t i = 0; i < m.positions.size(); ++i)
    if (std::abs(m.normals[i].z()) < 0.5f) EXPECT_FLOAT_EQ(m.face_uv[i].y(), 1.0f - m.positions[i].z());
}

TEST(Primitives, PrismIsARoof) {
  const Mesh m = MakePrimitive(PrimitiveKind::Prism);
  CheckStructure(m, 5);
  CheckOutward(m, {0, 0, 0.5});
  CheckClosed(m);
  CheckUpright(m);
  EXPECT_NEAR(Area(m), 2 * std::sqrt(1.25) + 2 * 0.5 + 1.0, 1e-6);
  EXPECT_NEAR(Volume(m), 0.5, 1e-6);
  // Two quads, two triangles, one quad; the ridge is y = 0, z = 1.
  const int triangles[5] = {2, 2, 1, 1, 2};
  for (int f = 0; f < 5; ++f) EXPECT_EQ(m.faces[f].triangle_count, triangles[f]);
  for (const Vector3f& p : m.positions)
    if (p.z() == 1.0f) EXPECT_EQ(p.y(), 0.0f);
  for (int f = 2; f < 4; ++f) {
    const Face& g = m.faces[f];
    EXPECT_EQ(m.face_uv[m.indices[3 * g.first_triangle + 0]], Vector2f(0, 1));
    EXPECT_EQ(m.face_uv[m.indices[3 * g.first_triangle + 1]], Vector2f(1, 1));
    EXPECT_EQ(m.face_uv[m.indices[3 * g.first_triangle + 2]], Vector2f(0.5f, 0));
    EXPECT_EQ(m.positions[m.indices[3 * g.first_triangle + 2]].z(), 1.0f);
  }
}

TEST(Primitives, CylinderIsClosedWithASmoothSide) {
  const int segments = 256;
  const Mesh m = MakePrimitive(PrimitiveKind::Cylinder, segments);
  CheckStructure(m, 3);
  CheckOutward(m, {0, 0, 0.5});
  CheckClosed(m);
  CheckUpright(m);
  EXPECT_NEAR(Area(m), M_PI + 2 * M_PI / 4, 1e-3);
  EXPECT_NEAR(Volume(m), M_PI / 4, 1e-3);
  EXPECT_EQ(m.faces[0].triangle_count, 2 * segments);
  // Side: radial normals, u = angle / 360°, v = 1 − z, and a duplicated seam.
  const Face& side = m.faces[0];
  int seam = 0;
  for (int t = side.first_triangle; t < side.first_triangle + side.triangle_count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = m.indices[3 * t + k];
      const Vector3f& p = m.positions[i];
      EXPECT_NEAR((m.normals[i] - Vector3f(2 * p.x(), 2 * p.y(), 0)).norm(), 0.0f, 1e-5f);
      EXPECT_FLOAT_EQ(m.face_uv[i].y(), 1.0f - p.z());
      double angle = std::atan2(p.y(), p.x());
      if (angle < 0) angle += 2 * M_PI;
      const float u = m.face_uv[i].x();
      if (u == 1.0f) ++seam;
      else EXPECT_NEAR(u, angle / (2 * M_PI), 1e-5);
    }
  }
  EXPECT_GT(seam, 0);
}

TEST(Primitives, CylinderAreaConvergesWithSegments) {
  double previous = 0;
  for (int s : {3, 8, 32, 128}) {
    const double a = Area(MakePrimitive(PrimitiveKind::Cylinder, s));
    EXPECT_GT(a, previous);
    EXPECT_LT(a, 1.5 * M_PI);
    previous = a;
  }
  EXPECT_THROW(MakePrimitive(PrimitiveKind::Cylinder, 2), std::invalid_argument);
}

TEST(Primitives, NoneIsEmptyAndMeshIsNotAPrimitive) {
  EXPECT_TRUE(MakePrimitive(PrimitiveKind::None).positions.empty());
  EXPECT_THROW(MakePrimitive(PrimitiveKind::Mesh), std::invalid_argument);
}

}  // namespace
}  // namespace vkr
