// Triangles of a glTF 2.0 file (.glb or .gltf) for `{"primitive": "mesh"}` nodes
// (docs/guide/SCENE_FORMAT.md, "nodes"), read with tinygltf (its implementation lives in the Debian
// libtinygltf.so; this file only includes the header).
//
// What is read: every primitive of mode TRIANGLES (strips and fans are unrolled; points and
// lines have no surface and are skipped) of every mesh instanced by the default scene's
// node tree, with the nodes' matrices or TRS applied, then glTF's Y-up turned into
// vkrecon's Z-up by (x, y, z) → (x, −z, y). Zero-area triangles are dropped.
//
// Faces: when every primitive has TEXCOORD_0, the whole mesh is ONE face and face_uv is the
// file's texture coordinate (glTF, like Image, puts v = 0 at the image's top row).
// Limitation: coordinates outside [0,1] are wrapped into it by their fractional part, so a
// texture that tiles, or a triangle that straddles an integer u or v, is painted and
// measured wrongly — the atlas has one chart per face and cannot represent tiling. Without
// TEXCOORD_0 (on any primitive) every triangle is its own face with face_uv (0,0), (1,0),
// (0,1). Vertices are duplicated per triangle whenever they cannot be shared (no normals,
// per-triangle faces).

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

#include "engine/common/InputError.h"
#include "engine/geometry/Mesh.h"

namespace vkr {
namespace {

using Eigen::Matrix3d;
using Eigen::Matrix4d;
using Eigen::Vector2f;
using Eigen::Vector3d;
using Eigen::Vector3f;

// Texture images are irrelevant to geometry: skip decoding them (faster, fewer failures).
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;
}

// More elements than any mesh we draw has; only accessors without data are held to it.
constexpr size_t kMaxZeroElements = size_t(1) << 20;

// glTF Y-up → vkrecon Z-up, a proper rotation (det +1) so windings are kept.
Vector3d ZUp(const Vector3d& v) { return {v.x(), -v.z(), v.y()}; }

class Reader {
 public:
  Reader(const tinygltf::Model& model, std::string file) : m_(model), file_(std::move(file)) {}

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw InputError(file_, field, problem);
  }

  // Accessor `index` as `components` floats per element. FLOAT, or normalised integer
  // components (allowed for TEXCOORD_0).
  std::vector<float> Floats(int index, int components, const std::string& field) const {
    const auto [acc, base, stride] = Locate(index, field);
    if (tinygltf::GetNumComponentsInType(uint32_t(acc.type)) != components)
      Fail(field, "expected " + std::to_string(components) + " components per element");
    std::vector<float> out(acc.count * components);
    for (size_t i = 0; i < acc.count; ++i) {
      const unsigned char* e = base ? base + i * stride : nullptr;
      for (int c = 0; c < components; ++c) out[i * components + c] = Component(acc, e, c, field);
    }
    return out;
  }

  // An index accessor: SCALAR of unsigned byte, short or int.
  std::vector<uint32_t> Indices(int index, const std::string& field) const {
    const auto [acc, base, stride] = Locate(index, field);
    std::vector<uint32_t> out(acc.count, 0);
    for (size_t i = 0; base && i < acc.count; ++i) {
      const unsigned char* e = base + i * stride;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[i] = e[0]; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, e, 2); out[i] = v; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, e, 4); out[i] = v; break; }
        default: Fail(field, "indices must be unsigned byte, short or int");
      }
    }
    return out;
  }

 private:
  struct Located {
    const tinygltf::Accessor& acc;
    const unsigned char* base;  // first element; null for an accessor without bufferView (zeros)
    size_t stride;
  };

  // Checks that every element of the accessor lies inside its buffer view and buffer.
  Located Locate(int index, const std::string& field) const {
    if (index < 0 || size_t(index) >= m_.accessors.size()) Fail(field, "accessor index out of range");
    const tinygltf::Accessor& acc = m_.accessors[index];
    if (acc.sparse.isSparse) Fail(field, "sparse accessors are not supported");
    if (acc.bufferView < 0) {  // glTF: all zeros
      // Nothing in the file backs the count: a few bytes could otherwise ask for terabytes.
      if (acc.count > kMaxZeroElements)
        Fail(field, "accessor without a bufferView claims " + std::to_string(acc.count) + " elements");
      return {acc, nullptr, 0};
    }
    if (size_t(acc.bufferView) >= m_.bufferViews.size()) Fail(field, "bufferView out of range");
    const tinygltf::BufferView& view = m_.bufferViews[acc.bufferView];
    if (view.buffer < 0 || size_t(view.buffer) >= m_.buffers.size()) Fail(field, "buffer out of range");
    const int stride = acc.ByteStride(view);
    const int elem = tinygltf::GetComponentSizeInBytes(uint32_t(acc.componentType)) *
                     tinygltf::GetNumComponentsInType(uint32_t(acc.type));
    if (stride <= 0 || elem <= 0) Fail(field, "invalid component type, type or byteStride");
    // Compared by division and subtraction only: the counts and offsets come from the file,
    // and a product or sum of them can wrap around past the check (tests/fuzz/regressions/gltf).
    const size_t buffer_size = m_.buffers[view.buffer].data.size();
    const size_t length = view.byteLength, offset = acc.byteOffset, element = size_t(elem);
    const bool inside = acc.count == 0 || (offset <= length && element <= length - offset &&
                                           acc.count - 1 <= (length - offset - element) / size_t(stride));
    if (!inside || view.byteOffset > buffer_size || length > buffer_size - view.byteOffset)
      Fail(field, "accessor reads past the end of its buffer");
    return {acc, m_.buffers[view.buffer].data.data() + view.byteOffset + acc.byteOffset, size_t(stride)};
  }

  float Component(const tinygltf::Accessor& acc, const unsigned char* e, int c,
                  const std::string& field) const {
    if (!e) return 0.0f;
    switch (acc.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, e + 4 * c, 4); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: if (acc.normalized) return e[c] / 255.0f; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        if (acc.normalized) { uint16_t v; std::memcpy(&v, e + 2 * c, 2); return v / 65535.0f; }
        break;
      default: break;
    }
    Fail(field, "expected float (or normalised unsigned) components");
  }

  const tinygltf::Model& m_;
  std::string file_;
};

// One primitive, in vkrecon's world-of-the-file frame, as a triangle list.
struct Primitive {
  std::vector<Vector3f> positions, normals;
  std::vector<Vector2f> uv;
  std::vector<uint32_t> triangles;
};

Matrix4d LocalMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return Eigen::Map<const Matrix4d>(node.matrix.data());  // column-major
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3) t.translate(Vector3d(node.translation.data()));
  if (node.rotation.size() == 4)  // glTF quaternions are (x, y, z, w)
    t.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized());
  if (node.scale.size() == 3) t.scale(Vector3d(node.scale.data()));
  return t.matrix();
}

// Unrolls strips and fans; returns false for modes without a surface.
bool ToTriangleList(int mode, std::vector<uint32_t>& idx) {
  if (mode == TINYGLTF_MODE_TRIANGLES || mode == -1) {
    idx.resize(idx.size() / 3 * 3);
    return true;
  }
  std::vector<uint32_t> out;
  for (size_t i = 2; i < idx.size(); ++i) {
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      // Every other strip triangle flips its order to stay counter-clockwise.
      if (i % 2 == 0) out.insert(out.end(), {idx[i - 2], idx[i - 1], idx[i]});
      else out.insert(out.end(), {idx[i - 1], idx[i - 2], idx[i]});
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
      out.insert(out.end(), {idx[0], idx[i - 1], idx[i]});
    } else {
      return false;
    }
  }
  idx.swap(out);
  return true;
}

}  // namespace

Mesh LoadGltfMesh(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".glb" && ext != ".gltf") throw InputError(name, "", "a mesh must be a .glb or .gltf file");
  if (!std::filesystem::is_regular_file(file)) throw InputError(name, "", "file not found");

  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&SkipImage, nullptr);
  std::string err, warn;
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, name)
                                : loader.LoadASCIIFromFile(&model, &err, &warn, name);
  if (!ok || !err.empty()) throw InputError(name, "", "cannot read glTF: " + (err.empty() ? warn : err));
  // A warning means tinygltf lost something (usually a missing external file): refuse
  // rather than build a silently different mesh.
  if (!warn.empty()) throw InputError(name, "", "glTF warning: " + warn);
  // Compressed geometry would read as empty accessors; say why instead.
  for (const std::string& e : model.extensionsRequired)
    if (e == "KHR_draco_mesh_compression" || e == "EXT_meshopt_compression")
      throw InputError(name, "extensionsRequired", "compressed meshes (" + e + ") are not supported");
  const Reader reader(model, name);

  // Mesh instances of the node tree: (mesh index, file_from_mesh).
  // glTF node hierarchies are disjoint trees, so each node is visited once: a node reached
  // twice (a shared child, a cycle) is refused, which also bounds the walk by the node
  // count. A file of 40 nodes each listing the next twice once took 2^40 steps. The walk
  // keeps its own stack, so a deep chain cannot overflow the thread's.
  std::vector<std::pair<int, Matrix4d>> instances;
  std::vector<bool> visited(model.nodes.size(), false);
  auto visit = [&](int root) {
    std::vector<std::pair<int, Matrix4d>> stack = {{root, Matrix4d::Identity()}};
    while (!stack.empty()) {
      const auto [n, parent] = stack.back();
      stack.pop_back();
      if (n < 0 || size_t(n) >= model.nodes.size()) reader.Fail("nodes", "node index out of range");
      if (visited[size_t(n)])
        reader.Fail("nodes[" + std::to_string(n) + "]",
                    "node reached twice (a child of two nodes, or a cycle); glTF node hierarchies are trees");
      visited[size_t(n)] = true;
      const Matrix4d world = parent * LocalMatrix(model.nodes[n]);
      if (model.nodes[n].mesh >= 0) instances.emplace_back(model.nodes[n].mesh, world);
      const std::vector<int>& children = model.nodes[n].children;
      for (auto c = children.rbegin(); c != children.rend(); ++c) stack.emplace_back(*c, world);  // in file order
    }
  };
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size() ? model.defaultScene : 0;
    for (int n : model.scenes[s].nodes) visit(n);
  } else if (!model.nodes.empty()) {  // no scene: every node that is nobody's child is a root
    std::vector<bool> child(model.nodes.size(), false);
    for (const auto& node : model.nodes)
      for (int c : node.children) if (c >= 0 && size_t(c) < child.size()) child[c] = true;
    for (size_t n = 0; n < model.nodes.size(); ++n) if (!child[n]) visit(int(n));
  } else {  // bare meshes
    for (size_t i = 0; i < model.meshes.size(); ++i) instances.emplace_back(int(i), Matrix4d::Identity());
  }

  // Read every triangle primitive, transformed into the file's frame (Z-up).
  std::vector<Primitive> prims;
  bool all_uv = true;
  for (const auto& [mesh_index, file_from_mesh] : instances) {
    if (size_t(mesh_index) >= model.meshes.size()) reader.Fail("nodes", "mesh index out of range");
    const Matrix3d linear = file_from_mesh.topLeftCorner<3, 3>();
    const Matrix3d normal_matrix = linear.inverse().transpose();
    const bool mirrored = linear.determinant() < 0;  // glTF: mirroring flips the winding
    const auto& gprims = model.meshes[mesh_index].primitives;
    for (size_t p = 0; p < gprims.size(); ++p) {
      const tinygltf::Primitive& gp = gprims[p];
      const std::string field = "meshes[" + std::to_string(mesh_index) + "].primitives[" + std::to_string(p) + "]";
      const auto pos_it = gp.attributes.find("POSITION");
      if (pos_it == gp.attributes.end()) reader.Fail(field, "no POSITION attribute");
      const std::vector<float> pos = reader.Floats(pos_it->second, 3, field + ".attributes.POSITION");
      const size_t count = pos.size() / 3;
      std::vector<uint32_t> idx;
      if (gp.indices >= 0) {
        idx = reader.Indices(gp.indices, field + ".indices");
      } else {
        idx.resize(count);
        for (size_t i = 0; i < count; ++i) idx[i] = uint32_t(i);
      }
      if (!ToTriangleList(gp.mode, idx)) continue;
      for (uint32_t i : idx) if (i >= count) reader.Fail(field + ".indices", "index beyond the vertex count");

      Primitive out;
      for (size_t i = 0; i < count; ++i) {
        const Eigen::Vector4d h(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], 1.0);
        out.positions.push_back(ZUp((file_from_mesh * h).head<3>()).cast<float>());
      }
      if (auto it = gp.attributes.find("NORMAL"); it != gp.attributes.end()) {
        const std::vector<float> n = reader.Floats(it->second, 3, field + ".attributes.NORMAL");
        if (n.size() != pos.size()) reader.Fail(field + ".attributes.NORMAL", "count differs from POSITION");
        for (size_t i = 0; i < count; ++i)
          out.normals.push_back(ZUp(normal_matrix * Vector3d(n[3 * i], n[3 * i + 1], n[3 * i + 2])).normalized().cast<float>());
      }
      if (auto it = gp.attributes.find("TEXCOORD_0"); it != gp.attributes.end()) {
        const std::vector<float> t = reader.Floats(it->second, 2, field + ".attributes.TEXCOORD_0");
        if (t.size() != 2 * count) reader.Fail(field + ".attributes.TEXCOORD_0", "count differs from POSITION");
        auto wrap = [](float x) { return x >= 0.0f && x <= 1.0f ? x : x - std::floor(x); };
        for (size_t i = 0; i < count; ++i) out.uv.emplace_back(wrap(t[2 * i]), wrap(t[2 * i + 1]));
      } else {
        all_uv = false;
      }
      // Drop zero-area triangles: no surface, and no usable flat normal or chart.
      for (size_t t = 0; t + 2 < idx.size(); t += 3) {
        uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
        if (mirrored) std::swap(b, c);
        const Vector3f& pa = out.positions[a];
        if ((out.positions[b] - pa).cross(out.positions[c] - pa).squaredNorm() > 0.0f)
          out.triangles.insert(out.triangles.end(), {a, b, c});
      }
      prims.push_back(std::move(out));
    }
  }

  // Flatten into one Mesh, sharing vertices only where normals and face_uv allow it.
  Mesh mesh;
  for (const Primitive& p : prims) {
    const bool share = all_uv && !p.normals.empty();
    const uint32_t base = uint32_t(mesh.positions.size());
    if (share) {
      mesh.positions.insert(mesh.positions.end(), p.positions.begin(), p.positions.end());
      mesh.normals.insert(mesh.normals.end(), p.normals.begin(), p.normals.end());
      mesh.face_uv.insert(mesh.face_uv.end(), p.uv.begin(), p.uv.end());
      for (uint32_t i : p.triangles) mesh.indices.push_back(base + i);
      continue;
    }
    static const Vector2f kTriangleUv[3] = {{0, 0}, {1, 0}, {0, 1}};
    for (size_t t = 0; t < p.triangles.size(); t += 3) {
      const uint32_t* v = &p.triangles[t];
      const Vector3f flat =
          (p.positions[v[1]] - p.positions[v[0]]).cross(p.positions[v[2]] - p.positions[v[0]]).normalized();
      for (int k = 0; k < 3; ++k) {
        mesh.indices.push_back(uint32_t(mesh.positions.size()));
        mesh.positions.push_back(p.positions[v[k]]);
        mesh.normals.push_back(p.normals.empty() ? flat : p.normals[v[k]]);
        mesh.face_uv.push_back(all_uv ? p.uv[v[k]] : kTriangleUv[k]);
      }
    }
  }
  if (mesh.indices.empty()) throw InputError(name, "", "the file has no triangles");
  if (all_uv) {
    mesh.faces.push_back({0, mesh.TriangleCount()});
  } else {
    for (int t = 0; t < mesh.TriangleCount(); ++t) mesh.faces.push_back({t, 1});
  }
  return mesh;
}

}  // namespace vkr
