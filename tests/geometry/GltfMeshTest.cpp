// glTF meshes (docs/guide/SCENE_FORMAT.md, "nodes": `{"mesh": "file.glb"}`): models built in code,
// written with tinygltf, read back by LoadGltfMesh, and bad files.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <cstring>

#include "engine/common/InputError.h"
#include "engine/geometry/Mesh.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

// Builds a one-buffer glTF model, one buffer view per accessor.
struct GltfBuilder {
  tinygltf::Model model;

  GltfBuilder() {
    model.buffers.emplace_back();
    model.asset.version = "2.0";
  }

  int Accessor(const void* data, size_t bytes, int component, int type, size_t count) {
    auto& buf = model.buffers[0].data;
    while (buf.size() % 4) buf.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buf.size();
    view.byteLength = bytes;
    buf.insert(buf.end(), static_cast<const unsigned char*>(data), static_cast<const unsigned char*>(data) + bytes);
    model.bufferViews.push_back(view);
    tinygltf::Accessor acc;
    acc.bufferView = int(model.bufferViews.size() - 1);
    acc.componentType = component;
    acc.type = type;
    acc.count = count;
    model.accessors.push_back(acc);
    return int(model.accessors.size() - 1);
  }
  int Floats(const std::vector<float>& v, int type, int per) {
    return Accessor(v.data(), v.size() * 4, TINYGLTF_COMPONENT_TYPE_FLOAT, type, v.size() / per);
  }
  template <typename T>
  int Indices(const std::vector<T>& v, int component) {
    return Accessor(v.data(), v.size() * sizeof(T), component, TINYGLTF_TYPE_SCALAR, v.size());
  }

  // A mesh of one primitive; returns the mesh index.
  int AddMesh(const std::vector<float>& positions, int indices = -1, int mode = TINYGLTF_MODE_TRIANGLES,
              const std::vector<float>& normals = {}, const std::vector<float>& uv = {}) {
    tinygltf::Primitive p;
    p.mode = mode;
    p.indices = indices;
    p.attributes["POSITION"] = Floats(positions, TINYGLTF_TYPE_VEC3, 3);
    if (!normals.empty()) p.attributes["NORMAL"] = Floats(normals, TINYGLTF_TYPE_VEC3, 3);
    if (!uv.empty()) p.attributes["TEXCOORD_0"] = Floats(uv, TINYGLTF_TYPE_VEC2, 2);
    tinygltf::Mesh mesh;
    mesh.primitives.push_back(p);
    model.meshes.push_back(mesh);
    return int(model.meshes.size() - 1);
  }

  int AddNode(int mesh, const std::vector<int>& children = {}) {
    tinygltf::Node n;
    n.mesh = mesh;
    n.children = children;
    model.nodes.push_back(n);
    return int(model.nodes.size() - 1);
  }

  void Write(const std::filesystem::path& file, const std::vector<int>& roots) {
    tinygltf::Scene scene;
    scene.nodes = roots;
    model.scenes = {scene};
    model.defaultScene = 0;
    tinygltf::TinyGLTF writer;
    const bool binary = file.extension() == ".glb";
    ASSERT_TRUE(writer.WriteGltfSceneToFile(&model, file.string(), true, true, !binary, binary));
  }
};

// glTF's Y-up to vkrecon's Z-up.
Vector3f ZUp(const Vector3d& v) { return Vector3d(v.x(), -v.z(), v.y()).cast<float>(); }

// A tetrahedron in the glTF frame, wound counter-clockwise from outside.
const std::vector<float> kTetra = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
const std::vector<uint16_t> kTetraIndices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

Vector3d Corner(const Mesh& m, int t, int k) { return m.positions[m.indices[3 * t + k]].cast<double>(); }

// Divergence-theorem volume: positive iff the closed mesh is wound outward.
double Volume(const Mesh& m) {
  double v = 0;
  for (int t = 0; t < m.TriangleCount(); ++t) v += Corner(m, t, 0).dot(Corner(m, t, 1).cross(Corner(m, t, 2))) / 6;
  return v;
}

TEST(GltfMesh, IndexedTetrahedronWithoutTexcoordsRoundTrips) {
  test::TempDir dir;
  GltfBuilder b;
  const int mesh = b.AddMesh(kTetra, b.Indices(kTetraIndices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
  const int node = b.AddNode(mesh);
  b.model.nodes[node].translation = {1, 2, 3};
  b.Write(dir / "tetra.glb", {node});

  const Mesh m = LoadGltfMesh(dir / "tetra.glb");
  ASSERT_EQ(m.TriangleCount(), 4);
  ASSERT_EQ(m.faces.size(), 4u);  // no TEXCOORD_0: one face per triangle
  for (int t = 0; t < 4; ++t) {
    EXPECT_EQ(m.faces[t].first_triangle, t);
    EXPECT_EQ(m.faces[t].triangle_count, 1);
    const Vector3f n = (Corner(m, t, 1) - Corner(m, t, 0)).cross(Corner(m, t, 2) - Corner(m, t, 0)).normalized().cast<float>();
    const Vector2f uv[3] = {{0, 0}, {1, 0}, {0, 1}};
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = m.indices[3 * t + k];
      const int j = kTetraIndices[3 * t + k];
      const Vector3d gltf(kTetra[3 * j] + 1.0, kTetra[3 * j + 1] + 2.0, kTetra[3 * j + 2] + 3.0);
      EXPECT_TRUE(m.positions[i].isApprox(ZUp(gltf), 1e-6f)) << m.positions[i].transpose();
      EXPECT_TRUE(m.normals[i].isApprox(n, 1e-5f)) << "flat normal";
      EXPECT_EQ(m.face_uv[i], uv[k]);
    }
  }
  EXPECT_NEAR(Volume(m), 1.0 / 6.0, 1e-6);
}

TEST(GltfMesh, TexcoordsMakeOneWrappedFace) {
  test::TempDir dir;
  GltfBuilder b;
  // A unit quad in the glTF x–z plane facing +y (up), texture coordinates partly outside [0,1].
  const std::vector<float> pos = {0, 0, 0, 0, 0, -1, 1, 0, -1, 1, 0, 0};
  const std::vector<float> normals = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  const std::vector<float> uv = {0, 1, 0, 0, 1.25f, 0, 1, -0.25f};
  const std::vector<uint32_t> idx = {0, 3, 2, 0, 2, 1};
  const int mesh = b.AddMesh(pos, b.Indices(idx, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT), TINYGLTF_MODE_TRIANGLES, normals, uv);
  b.Write(dir / "quad.gltf", {b.AddNode(mesh)});  // ASCII, buffer as a data URI

  const Mesh m = LoadGltfMesh(dir / "quad.gltf");
  ASSERT_EQ(m.faces.size(), 1u);
  EXPECT_EQ(m.faces[0].triangle_count, 2);
  ASSERT_EQ(m.positions.size(), 4u);  // normals and one face: vertices are shared
  const Vector2f expected_uv[4] = {{0, 1}, {0, 0}, {0.25f, 0}, {1, 0.75f}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(m.positions[i].isApprox(ZUp(Vector3d(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2])))) << i;
    EXPECT_TRUE(m.normals[i].isApprox(Vector3f(0, 0, 1))) << m.normals[i].transpose();
    EXPECT_TRUE(m.face_uv[i].isApprox(expected_uv[i])) << m.face_uv[i].transpose();
  }
  EXPECT_EQ(m.indices, idx);
  // Facing up in Z-up, counter-clockwise seen from above.
  EXPECT_GT((Corner(m, 0, 1) - Corner(m, 0, 0)).cross(Corner(m, 0, 2) - Corner(m, 0, 0)).z(), 0);
}

TEST(GltfMesh, NodeHierarchyAndMirroringKeepTrianglesOutward) {
  test::TempDir dir;
  GltfBuilder b;
  // Non-indexed tetrahedron (12 vertices), and one indexed with unsigned bytes.
  std::vector<float> flat;
  for (uint16_t i : kTetraIndices) flat.insert(flat.end(), {kTetra[3 * i], kTetra[3 * i + 1], kTetra[3 * i + 2]});
  const int plain = b.AddMesh(flat);
  const std::vector<uint8_t> idx8(kTetraIndices.begin(), kTetraIndices.end());
  const int bytes = b.AddMesh(kTetra, b.Indices(idx8, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE));
  // child: a matrix (rotate 90° about y, move +x 5); mirror: scale x by -1; parent: scale 2.
  const int child = b.AddNode(plain);
  Eigen::Matrix4d mat = Eigen::Matrix4d::Identity();
  mat.topLeftCorner<3, 3>() = Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()).toRotationMatrix();
  mat(0, 3) = 5;
  b.model.nodes[child].matrix.assign(mat.data(), mat.data() + 16);  // column-major, as glTF
  const int mirror = b.AddNode(bytes);
  b.model.nodes[mirror].scale = {-1, 1, 1};
  const int parent = b.AddNode(-1, {child, mirror});
  b.model.nodes[parent].scale = {2, 2, 2};
  b.Write(dir / "tree.glb", {parent});

  const Mesh m = LoadGltfMesh(dir / "tree.glb");
  ASSERT_EQ(m.TriangleCount(), 8);
  // Both tetrahedra are scaled by 2 (volume 8/6) and stay outward-wound: the volume sum
  // would cancel if the mirrored one were inside out.
  EXPECT_NEAR(Volume(m), 2 * 8.0 / 6.0, 1e-5);
  // The child's corner (1,0,0) goes to R·(1,0,0) + (5,0,0) = (5,0,-1), then ×2.
  bool found = false;
  for (const Vector3f& p : m.positions) found |= p.isApprox(ZUp(Vector3d(10, 0, -2)), 1e-5f);
  EXPECT_TRUE(found);
  // The mirrored corner (1,0,0) goes to (-2,0,0).
  found = false;
  for (const Vector3f& p : m.positions) found |= p.isApprox(ZUp(Vector3d(-2, 0, 0)), 1e-5f);
  EXPECT_TRUE(found);
}

// Expects LoadGltfMesh to refuse `file` with an InputError naming it and whose problem
// mentions `why`.
void ExpectInputError(const std::filesystem::path& file, const std::string& why = "") {
  try {
    LoadGltfMesh(file);
    ADD_FAILURE() << "expected InputError for " << file;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_FALSE(e.problem().empty());
    EXPECT_NE(e.problem().find(why), std::string::npos) << e.what();
  }
}

TEST(GltfMesh, BadFilesAreInputErrors) {
  test::TempDir dir;
  test::WriteText(dir / "garbage.glb", "this is not a glTF binary, just text of some length");
  ExpectInputError(dir / "garbage.glb");
  test::WriteText(dir / "garbage.gltf", "{ not json");
  ExpectInputError(dir / "garbage.gltf");
  ExpectInputError(dir / "missing.glb", "not found");
  test::WriteText(dir / "mesh.obj", "v 0 0 0");
  ExpectInputError(dir / "mesh.obj", ".glb or .gltf");
  // A hand-written .gltf with an external buffer loads; the same with a texture image that
  // is missing makes tinygltf warn, which is refused.
  std::string bin(reinterpret_cast<const char*>(kTetra.data()), kTetra.size() * 4);
  test::WriteText(dir / "tetra.bin", bin);
  const std::string head =
      R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "tetra.bin", "byteLength": 48}],
          "bufferViews": [{"buffer": 0, "byteLength": 48}],
          "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 4}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 6}]}],
          "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}])";
  test::WriteText(dir / "fan.gltf", head + "}");
  EXPECT_EQ(LoadGltfMesh(dir / "fan.gltf").TriangleCount(), 2);  // a fan of 4 vertices
  test::WriteText(dir / "textured.gltf", head + R"(, "images": [{"uri": "nowhere.png"}]})");
  ExpectInputError(dir / "textured.gltf", "warning");
  // Only points: no surface.
  GltfBuilder b;
  b.Write(dir / "points.glb", {b.AddNode(b.AddMesh(kTetra, -1, TINYGLTF_MODE_POINTS))});
  ExpectInputError(dir / "points.glb", "no triangles");
  // An index past the vertices.
  GltfBuilder c;
  const std::vector<uint16_t> bad = {0, 1, 7};
  c.Write(dir / "bad_index.glb", {c.AddNode(c.AddMesh(kTetra, c.Indices(bad, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)))});
  ExpectInputError(dir / "bad_index.glb", "index");
}

}  // namespace
}  // namespace vkr
