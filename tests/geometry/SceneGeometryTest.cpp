// Flattened scene geometry (docs/internals/OVERVIEW.md, "How a hypothesis flows") and albedo
// loading, on scenes built in code.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "engine/common/InputError.h"
#include "engine/geometry/SceneGeometry.h"
#include "tests/common/TestFiles.h"

namespace vkr {
namespace {

Transform Constant(Transform::Kind kind, double x, double y, double z) {
  Transform t;
  t.kind = kind;
  t.value[0].constant = x;
  t.value[1].constant = y;
  t.value[2].constant = z;
  return t;
}

Node MakeNode(const std::string& name, PrimitiveKind kind, int parent, std::vector<Transform> transforms) {
  Node n;
  n.name = name;
  n.primitive = kind;
  n.parent = parent;
  n.transforms = std::move(transforms);
  return n;
}

// ground plane 4×4; a pure transform node; a 2×1×1 box under it; a cylinder; a prism roof.
Scene HouseScene() {
  Scene s;
  s.file = "/nowhere/scene.json";
  s.nodes.push_back(MakeNode("ground", PrimitiveKind::Plane, -1, {Constant(Transform::Kind::Scale, 4, 4, 1)}));
  s.nodes.push_back(MakeNode("frame", PrimitiveKind::None, -1, {Constant(Transform::Kind::Translate, 1, 0, 0)}));
  s.nodes.push_back(MakeNode("box", PrimitiveKind::Box, 1, {Constant(Transform::Kind::Scale, 2, 1, 1)}));
  s.nodes.push_back(MakeNode("pipe", PrimitiveKind::Cylinder, -1, {}));
  s.nodes.push_back(MakeNode("roof", PrimitiveKind::Prism, 2, {Constant(Transform::Kind::Translate, 0, 0, 1)}));
  return s;
}

TEST(SceneGeometry, FlattensNodesWithChartsAndNodeIndices) {
  const Scene scene = HouseScene();
  const SceneGeometry g = BuildSceneGeometry(scene, {}, 512, ChartSizing::Area);
  ASSERT_EQ(g.meshes.size(), 5u);
  EXPECT_TRUE(g.meshes[1].positions.empty());  // the transform-only node draws nothing
  size_t faces = 0, vertices = 0, indices = 0;
  for (const Mesh& m : g.meshes) {
    faces += m.faces.size();
    vertices += m.positions.size();  // unit primitives share no vertex between faces
    indices += m.indices.size();
  }
  ASSERT_EQ(g.atlas.charts.size(), faces);
  EXPECT_EQ(g.vertices.size(), vertices);
  ASSERT_EQ(g.indices.size(), indices);
  EXPECT_EQ(g.atlas.size, 512);

  // Every triangle's vertices share node and face; positions are the node's own; atlas_uv
  // lies inside its chart; the chart belongs to that node.
  std::vector<int> triangles_per_node(5, 0);
  for (size_t t = 0; t < g.indices.size(); t += 3) {
    const GpuVertex& a = g.vertices.at(g.indices[t]);
    ++triangles_per_node.at(a.node);
    for (int k = 0; k < 3; ++k) {
      const GpuVertex& v = g.vertices.at(g.indices[t + k]);
      EXPECT_EQ(v.node, a.node);
      EXPECT_EQ(v.face, a.face);
      const Chart& c = g.atlas.charts.at(v.face);
      EXPECT_EQ(c.node, int(v.node));
      EXPECT_GE(v.atlas_uv[0] * 512, c.x - 1e-3);
      EXPECT_LE(v.atlas_uv[0] * 512, c.x + c.w + 1e-3);
      EXPECT_GE(v.atlas_uv[1] * 512, c.y - 1e-3);
      EXPECT_LE(v.atlas_uv[1] * 512, c.y + c.h + 1e-3);
    }
  }
  for (int n = 0; n < 5; ++n) EXPECT_EQ(triangles_per_node[n], g.meshes[n].TriangleCount()) << "node " << n;
  // Indices are offset per node: the first box vertex follows the plane's four.
  const GpuVertex& first_box = g.vertices.at(4);
  EXPECT_EQ(first_box.node, 2u);
  EXPECT_EQ(first_box.face, 1u);  // chart 0 is the ground's only face
  EXPECT_FLOAT_EQ(first_box.position[0], g.meshes[2].positions[0].x());
  EXPECT_FLOAT_EQ(first_box.normal[1], g.meshes[2].normals[0].y());

  // Charts are laid out at the given matrices: the ground (4 m) is 4× the pipe's cap (1 m)
  // and the box's ±y faces (2 m × 1 m) twice as wide as tall.
  const Chart& ground = g.atlas.charts[0];
  const Chart& box_front = g.atlas.charts[1];
  EXPECT_NEAR(ground.w / box_front.h, 4.0, 0.2);
  EXPECT_NEAR(box_front.w / box_front.h, 2.0, 0.1);
}

TEST(SceneGeometry, MeshNodesComeFromGltf) {
  test::TempDir dir;
  // A single triangle without texture coordinates: one face.
  tinygltf::Model model;
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  model.buffers.emplace_back();
  model.buffers[0].data.assign(reinterpret_cast<const unsigned char*>(pos), reinterpret_cast<const unsigned char*>(pos) + sizeof pos);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteLength = sizeof pos;
  model.bufferViews.push_back(view);
  tinygltf::Accessor acc;
  acc.bufferView = 0;
  acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  acc.type = TINYGLTF_TYPE_VEC3;
  acc.count = 3;
  model.accessors.push_back(acc);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = 0;
  model.meshes.emplace_back().primitives.push_back(prim);
  model.nodes.emplace_back().mesh = 0;
  model.scenes.emplace_back().nodes = {0};
  model.asset.version = "2.0";
  ASSERT_TRUE(tinygltf::TinyGLTF().WriteGltfSceneToFile(&model, (dir / "tri.glb").string(), true, true, false, true));

  Scene scene;
  scene.nodes.push_back(MakeNode("tri", PrimitiveKind::Mesh, -1, {}));
  scene.nodes[0].mesh = dir / "tri.glb";
  const SceneGeometry g = BuildSceneGeometry(scene, {}, 64, ChartSizing::Area);
  ASSERT_EQ(g.vertices.size(), 3u);
  EXPECT_EQ(g.atlas.charts.size(), 1u);
  EXPECT_FLOAT_EQ(g.vertices[1].position[0], 1.0f);
  EXPECT_FLOAT_EQ(g.vertices[2].position[2], 1.0f);  // glTF +y is vkrecon's +z

  scene.nodes[0].mesh = dir / "absent.glb";
  EXPECT_THROW(BuildSceneGeometry(scene, {}, 64, ChartSizing::Area), InputError);
}

TEST(SceneGeometry, LoadAlbedosNamesTheSceneEntry) {
  test::TempDir dir;
  Scene scene = HouseScene();
  Image red(3, 2, 1.0f);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) red.At(x, y)[1] = red.At(x, y)[2] = 0.0f;
  WritePng(dir / "red.png", red);
  scene.nodes[2].albedo = dir / "red.png";
  const std::vector<Image> albedos = LoadAlbedos(scene);
  ASSERT_EQ(albedos.size(), 5u);
  EXPECT_TRUE(albedos[0].Empty());
  ASSERT_EQ(albedos[2].width, 3);
  EXPECT_NEAR(albedos[2].At(1, 1)[0], 1.0f, 1e-6f);
  EXPECT_NEAR(albedos[2].At(1, 1)[1], 0.0f, 1e-6f);

  scene.nodes[4].albedo = dir / "missing.png";
  try {
    LoadAlbedos(scene);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nowhere/scene.json");
    EXPECT_EQ(e.field(), "nodes[4].albedo");
    EXPECT_NE(e.problem().find("missing.png"), std::string::npos) << e.problem();
  }
}

}  // namespace
}  // namespace vkr
