// The texture atlas (docs/internals/LIKELIHOOD.md, "Charts"): layout (no overlaps, common scale,
// aspect ratios from world extents) and the CPU bake of albedo images into it.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "engine/geometry/Atlas.h"

namespace vkr {
namespace {

using Eigen::Matrix4d;

Matrix4d Scale(double x, double y, double z) { return Eigen::Vector4d(x, y, z, 1).asDiagonal(); }

// A chart side is its world size at the common scale rounded up to whole texels (the
// small slack allows for float vertices).
void ExpectSide(float texels, double metres, double texels_per_metre) {
  EXPECT_GE(texels, metres * texels_per_metre - 1e-3);
  EXPECT_LT(texels, metres * texels_per_metre + 1.0);
}

// Charts with their gutters lie inside the atlas and are pairwise disjoint.
void CheckDisjoint(const AtlasLayout& a) {
  const int g = a.gutter;
  for (size_t i = 0; i < a.charts.size(); ++i) {
    const Chart& c = a.charts[i];
    EXPECT_EQ(c.x, std::floor(c.x));  // whole texels
    EXPECT_GE(c.x - g, 0);
    EXPECT_GE(c.y - g, 0);
    EXPECT_LE(c.x + c.w + g, a.size);
    EXPECT_LE(c.y + c.h + g, a.size);
    EXPECT_GE(c.w, 4);
    EXPECT_GE(c.h, 4);
    for (size_t j = 0; j < i; ++j) {
      const Chart& d = a.charts[j];
      const bool apart = c.x + c.w + g <= d.x - g || d.x + d.w + g <= c.x - g ||
                         c.y + c.h + g <= d.y - g || d.y + d.h + g <= c.y - g;
      EXPECT_TRUE(apart) << "charts " << i << " and " << j << " overlap";
    }
  }
}

TEST(Atlas, ChartsFollowWorldExtentsAtOneScale) {
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Box)};
  const AtlasLayout a = PackAtlas(meshes, {Scale(2, 1, 1)}, 256, 2);
  ASSERT_EQ(a.charts.size(), 6u);
  CheckDisjoint(a);
  EXPECT_GT(a.texels_per_metre, 0);
  // World sizes (u, v) in metres of the faces -y, +x, +y, -x, top, bottom.
  const double world[6][2] = {{2, 1}, {1, 1}, {2, 1}, {1, 1}, {2, 1}, {2, 1}};
  for (int f = 0; f < 6; ++f) {
    const Chart& c = a.charts[f];
    EXPECT_EQ(c.node, 0);
    EXPECT_EQ(c.face, f);
    // Every chart is its world size at the common scale, rounded up to whole texels.
    SCOPED_TRACE("face " + std::to_string(f));
    ExpectSide(c.w, world[f][0], a.texels_per_metre);
    ExpectSide(c.h, world[f][1], a.texels_per_metre);
  }
  // The ±y faces (2 m along x, 1 m high) are twice as wide as tall.
  EXPECT_NEAR(a.charts[0].w / a.charts[0].h, 2.0, 0.05);
  EXPECT_NEAR(a.charts[2].w / a.charts[2].h, 2.0, 0.05);
  EXPECT_NEAR(a.charts[1].w / a.charts[1].h, 1.0, 0.05);
  // The scale is about as large as fits: the charts use a fair share of the atlas.
  double used = 0;
  for (const Chart& c : a.charts) used += (c.w + 4) * (c.h + 4);
  EXPECT_GT(used, 0.5 * 256 * 256);
}

// likelihood.charts "pixels" hands PackAtlas a density per face: a chart is its world size
// at the common scale times its face's density, and records the scale it got.
TEST(Atlas, ADensityPerFaceScalesItsChart) {
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Box)};
  const std::vector<double> density = {1.0, 0.5, 2.0, 0.25, 1.0, 1.0};
  const AtlasLayout a = PackAtlas(meshes, {Scale(2, 1, 1)}, 256, 2, density);
  ASSERT_EQ(a.charts.size(), 6u);
  CheckDisjoint(a);
  const double world[6][2] = {{2, 1}, {1, 1}, {2, 1}, {1, 1}, {2, 1}, {2, 1}};
  for (int f = 0; f < 6; ++f) {
    SCOPED_TRACE("face " + std::to_string(f));
    const Chart& c = a.charts[f];
    EXPECT_DOUBLE_EQ(c.texels_per_metre, a.texels_per_metre * density[f]);
    ExpectSide(c.w, world[f][0], c.texels_per_metre);
    ExpectSide(c.h, world[f][1], c.texels_per_metre);
  }
  // Face 2 (+y) is as large as face 0 (-y) in the world and gets twice the texels per side.
  EXPECT_NEAR(a.charts[2].w / a.charts[0].w, 2.0, 0.1);
  // Without densities every chart has the common scale.
  const AtlasLayout uniform = PackAtlas(meshes, {Scale(2, 1, 1)}, 256, 2);
  EXPECT_GT(uniform.texels_per_metre, 0.0);
  for (const Chart& c : uniform.charts) EXPECT_DOUBLE_EQ(c.texels_per_metre, uniform.texels_per_metre);
  EXPECT_THROW(PackAtlas(meshes, {Scale(2, 1, 1)}, 256, 2, {1.0, 1.0}), std::invalid_argument);
  EXPECT_THROW(PackAtlas(meshes, {Scale(2, 1, 1)}, 256, 2, {1.0, 1.0, 0.0, 1.0, 1.0, 1.0}), std::invalid_argument);
}

TEST(Atlas, ManyNodesPackWithoutOverlap) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> s(0.2, 3.0);
  std::vector<Mesh> meshes;
  std::vector<Matrix4d> world;
  const PrimitiveKind kinds[] = {PrimitiveKind::Box, PrimitiveKind::Prism, PrimitiveKind::Cylinder,
                                 PrimitiveKind::Plane, PrimitiveKind::None};
  for (int i = 0; i < 40; ++i) {
    meshes.push_back(MakePrimitive(kinds[i % 5], 16));
    Matrix4d m = Scale(s(rng), s(rng), s(rng));
    m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(s(rng), Eigen::Vector3d(1, 2, 3).normalized()) * m.topLeftCorner<3, 3>();
    m.topRightCorner<3, 1>() = Eigen::Vector3d(s(rng), -s(rng), 1);
    world.push_back(m);
  }
  const AtlasLayout a = PackAtlas(meshes, world, 1024, 3);
  size_t faces = 0;
  for (const Mesh& m : meshes) faces += m.faces.size();
  ASSERT_EQ(a.charts.size(), faces);
  CheckDisjoint(a);
  // In (node, face) order, as SceneGeometry relies on.
  for (size_t i = 1; i < a.charts.size(); ++i)
    EXPECT_TRUE(std::make_pair(a.charts[i - 1].node, a.charts[i - 1].face) <
                std::make_pair(a.charts[i].node, a.charts[i].face));
}

TEST(Atlas, CylinderSideIsAsWideAsItsCircumference) {
  const int n = 16;
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Cylinder, n)};
  // Rotation and translation do not change chart sizes; a uniform scale 2 does.
  Matrix4d m = Scale(2, 2, 2);
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()) * m.topLeftCorner<3, 3>();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(5, -3, 2);
  const AtlasLayout a = PackAtlas(meshes, {m}, 512, 2);
  ASSERT_EQ(a.charts.size(), 3u);
  CheckDisjoint(a);
  const double s = a.texels_per_metre;
  const double perimeter = 2.0 * n * std::sin(M_PI / n);  // of the 16-gon, 2 m across
  ExpectSide(a.charts[0].w, perimeter, s);
  ExpectSide(a.charts[0].h, 2.0, s);
  for (int cap = 1; cap < 3; ++cap) {
    ExpectSide(a.charts[cap].w, 2.0, s);
    ExpectSide(a.charts[cap].h, 2.0, s);
  }
}

TEST(Atlas, TooSmallAnAtlasIsAProgrammerError) {
  std::vector<Mesh> meshes(100, MakePrimitive(PrimitiveKind::Box));
  std::vector<Matrix4d> world(100, Matrix4d::Identity());
  try {
    PackAtlas(meshes, world, 32, 2);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("600 charts"), std::string::npos) << e.what();
  }
}

TEST(Atlas, AtlasUvMapsFaceUvOntoTheChart) {
  AtlasLayout a;
  a.size = 100;
  const Chart c{0, 0, 10, 20, 30, 40};
  EXPECT_TRUE(a.AtlasUv(c, {0, 0}).isApprox(Eigen::Vector2f(0.1f, 0.2f)));
  EXPECT_TRUE(a.AtlasUv(c, {1, 1}).isApprox(Eigen::Vector2f(0.4f, 0.6f)));
  EXPECT_TRUE(a.AtlasUv(c, {0.5f, 0.25f}).isApprox(Eigen::Vector2f(0.25f, 0.3f)));
}

// A 64×64 albedo of four 32×32 quadrants: red, green (top row), blue, white (bottom row).
Image Quadrants() {
  Image img(64, 64, 1.0f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      float* p = img.At(x, y);
      const int q = (y >= 32) * 2 + (x >= 32);
      const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
      for (int k = 0; k < 3; ++k) p[k] = colours[q][k];
    }
  return img;
}

void ExpectColour(const Image& img, int x, int y, float r, float g, float b, float a) {
  const float* p = img.At(x, y);
  EXPECT_NEAR(p[0], r, 1e-4) << "texel " << x << "," << y;
  EXPECT_NEAR(p[1], g, 1e-4) << "texel " << x << "," << y;
  EXPECT_NEAR(p[2], b, 1e-4) << "texel " << x << "," << y;
  EXPECT_EQ(p[3], a) << "texel " << x << "," << y;
}

TEST(Atlas, BakePaintsAnUprightAlbedoAndFillsGutters) {
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Plane)};
  const AtlasLayout a = PackAtlas(meshes, {Scale(2, 2, 1)}, 80, 2);
  ASSERT_EQ(a.charts.size(), 1u);
  const Chart& c = a.charts[0];
  ASSERT_EQ(c.w, 76);
  ASSERT_EQ(c.h, 76);
  const Image atlas = BakeAlbedoAtlas(a, meshes, {Quadrants()});
  ASSERT_EQ(atlas.width, 80);
  // The plane's corner (-0.5, +0.5) (north-west seen from above) is the chart's corner
  // (c.x, c.y) and shows the image's top-left quadrant.
  for (size_t i = 0; i < meshes[0].positions.size(); ++i) {
    const auto& p = meshes[0].positions[i];
    if (p.x() < 0 && p.y() > 0) EXPECT_TRUE(a.AtlasUv(c, meshes[0].face_uv[i]).isApprox(Eigen::Vector2f(c.x / 80, c.y / 80)));
  }
  const int x0 = int(c.x), y0 = int(c.y);
  ExpectColour(atlas, x0 + 10, y0 + 10, 1, 0, 0, 1);  // top-left: red
  ExpectColour(atlas, x0 + 60, y0 + 10, 0, 1, 0, 1);  // top-right: green
  ExpectColour(atlas, x0 + 10, y0 + 60, 0, 0, 1, 1);  // bottom-left: blue
  ExpectColour(atlas, x0 + 60, y0 + 60, 1, 1, 1, 1);  // bottom-right: white
  // Every texel of the chart is covered (the quad's diagonal leaves no hole) ...
  for (int y = y0; y < y0 + 76; ++y)
    for (int x = x0; x < x0 + 76; ++x) ASSERT_EQ(atlas.At(x, y)[3], 1.0f) << x << "," << y;
  // ... the gutter carries the border colour with alpha 0.5 ...
  // (a texel beside a straight border copies it exactly).
  auto gutter_copies = [&](int gx, int gy, int bx, int by) {
    const float* e = atlas.At(bx, by);
    ExpectColour(atlas, gx, gy, e[0], e[1], e[2], 0.5f);
  };
  gutter_copies(x0 - 1, y0 + 10, x0, y0 + 10);
  gutter_copies(x0 - 2, y0 + 10, x0, y0 + 10);
  gutter_copies(x0 + 60, y0 + 77, x0 + 60, y0 + 75);
  gutter_copies(x0 - 1, y0 - 1, x0, y0);  // diagonal corner, reached in the 2nd round
  EXPECT_GT(atlas.At(x0, y0 + 10)[0], 0.8f);  // the border itself is (mostly) red
  // ... and in an atlas with room to spare, texels beyond the gutter stay empty.
  AtlasLayout small = PackAtlas(meshes, {Scale(1, 1, 1)}, 80, 2);
  small.charts[0].w = 20;  // shrink the chart by hand: empty space around it
  small.charts[0].h = 20;
  const Image sparse = BakeAlbedoAtlas(small, meshes, {});
  ExpectColour(sparse, 2 + 10, 2 + 10, 0.5f, 0.5f, 0.5f, 1);  // no albedo: mid grey
  ExpectColour(sparse, 2 + 21, 2 + 10, 0.5f, 0.5f, 0.5f, 0.5f);
  ExpectColour(sparse, 2 + 22, 2 + 10, 0, 0, 0, 0);
  ExpectColour(sparse, 70, 70, 0, 0, 0, 0);
}

TEST(Atlas, BakeCoversTriangularAndCurvedFaces) {
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Prism), MakePrimitive(PrimitiveKind::Cylinder, 24)};
  const AtlasLayout a = PackAtlas(meshes, {Matrix4d::Identity(), Matrix4d::Identity()}, 256, 2);
  const Image atlas = BakeAlbedoAtlas(a, meshes, {Image(), Image()});
  for (const Chart& c : a.charts) {
    const Mesh& m = meshes[c.node];
    const Face& f = m.faces[c.face];
    // The texel at each triangle's centroid is covered.
    for (int t = f.first_triangle; t < f.first_triangle + f.triangle_count; ++t) {
      Eigen::Vector2f uv = Eigen::Vector2f::Zero();
      for (int k = 0; k < 3; ++k) uv += m.face_uv[m.indices[3 * t + k]] / 3.0f;
      const Eigen::Vector2f p = a.AtlasUv(c, uv) * float(a.size);
      EXPECT_EQ(atlas.At(int(p.x()), int(p.y()))[3], 1.0f);
    }
    // The cylinder side and caps fill their charts' centres; a gable leaves its chart's
    // top corners (beyond the gutter reach) empty.
    if (c.node == 0 && (c.face == 2 || c.face == 3)) {
      EXPECT_EQ(atlas.At(int(c.x), int(c.y))[3], 0.0f);
      EXPECT_EQ(atlas.At(int(c.x + c.w / 2), int(c.y + c.h - 1))[3], 1.0f);
    }
  }
}

// Speed is a benchmark's business, not a unit test's: this only checks a large atlas is
// mostly covered by charts (the packer uses the space it is given).
TEST(Atlas, LargeAtlasIsMostlyCovered) {
  const std::vector<Mesh> meshes = {MakePrimitive(PrimitiveKind::Plane), MakePrimitive(PrimitiveKind::Box),
                                    MakePrimitive(PrimitiveKind::Cylinder, 64)};
  const AtlasLayout a = PackAtlas(meshes, {Scale(4, 4, 1), Matrix4d::Identity(), Matrix4d::Identity()}, 2048);
  const Image atlas = BakeAlbedoAtlas(a, meshes, {Quadrants(), Quadrants(), Image()});
  double covered = 0;
  for (int y = 0; y < 2048; ++y)
    for (int x = 0; x < 2048; ++x) covered += atlas.At(x, y)[3] == 1.0f;
  EXPECT_GT(covered, 0.5 * 2048 * 2048);
}

}  // namespace
}  // namespace vkr
