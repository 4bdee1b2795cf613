// Flattens a scene's geometry for the GPU (DESIGN.md, "Data flows one way"): the vertices
// of every node are uploaded once per run in their node's frame, each tagged with its node
// (to pick the node matrix of a hypothesis) and its atlas position (the chart of its face,
// fixed for the run). A hypothesis then changes only the small buffer of node matrices.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "engine/common/InputError.h"
#include "engine/geometry/SceneGeometry.h"

namespace vkr {
namespace {

// A triangle is drawn as a grid of smaller ones when its atlas extent exceeds this share of
// the atlas side (at most kMostCells per edge): the ground, usually two triangles, then
// becomes patches the view pass can skip where a camera does not see them
// (pipelines/passes/ViewCulling.h). Every attribute is affine over a triangle, so the small
// triangles reproduce the large one's interpolation: the same texels, the same values (to
// float rounding).
constexpr float kCellShare = 1.0f / 8.0f;
constexpr int kMostCells = 8;

// Appends triangle `corners` (vertex indices, counter-clockwise) to the index list, as
// n × n smaller triangles of the same winding when it is large in the atlas.
void AppendSubdivided(SceneGeometry& g, const uint32_t (&corners)[3]) {
  const GpuVertex a = g.vertices[corners[0]], b = g.vertices[corners[1]], c = g.vertices[corners[2]];
  auto length = [&](const GpuVertex& p, const GpuVertex& q) {  // in atlas sides
    return std::hypot(p.atlas_uv[0] - q.atlas_uv[0], p.atlas_uv[1] - q.atlas_uv[1]);
  };
  const float longest = std::max({length(a, b), length(b, c), length(c, a)});
  const int n = std::clamp(int(std::ceil(longest / kCellShare - 1e-4f)), 1, kMostCells);
  if (n == 1) {
    g.indices.insert(g.indices.end(), std::begin(corners), std::end(corners));
    return;
  }
  // Grid point (i, j) = a + (i/n)(b − a) + (j/n)(c − a): in this form equal corners give
  // equal values exactly (a flat face's normals stay identical), and the points along an
  // edge from a are the same for both triangles of a quad (they share a and the diagonal).
  std::vector<uint32_t> grid;  // (i, j), j-major, i + j ≤ n
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i + j <= n; ++i) {
      const float u = float(i) / float(n), v = float(j) / float(n);
      auto lerp = [&](float pa, float pb, float pc) { return pa + u * (pb - pa) + v * (pc - pa); };
      GpuVertex p = a;
      for (int d = 0; d < 3; ++d) {
        p.position[d] = lerp(a.position[d], b.position[d], c.position[d]);
        p.normal[d] = lerp(a.normal[d], b.normal[d], c.normal[d]);
      }
      for (int d = 0; d < 2; ++d) p.atlas_uv[d] = lerp(a.atlas_uv[d], b.atlas_uv[d], c.atlas_uv[d]);
      const bool corner = (i == 0 && j == 0) || i == n || j == n;
      const uint32_t existing = i == 0 && j == 0 ? corners[0] : i == n ? corners[1] : corners[2];
      grid.push_back(corner ? existing : uint32_t(g.vertices.size()));
      if (!corner) g.vertices.push_back(p);
    }
  auto at = [&](int i, int j) { return grid[size_t(j * (n + 1) - j * (j - 1) / 2 + i)]; };
  // Row by row, so that consecutive triangles are neighbours (ViewCulling clusters runs).
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      g.indices.insert(g.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
      if (i + j + 1 < n) g.indices.insert(g.indices.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    }
}

}  // namespace

std::vector<Mesh> BuildMeshes(const Scene& scene) {
  std::vector<Mesh> meshes;
  meshes.reserve(scene.nodes.size());
  for (const Node& node : scene.nodes) {
    switch (node.primitive) {
      case PrimitiveKind::None: meshes.emplace_back(); break;
      case PrimitiveKind::Mesh: meshes.push_back(LoadGltfMesh(node.mesh)); break;
      default: meshes.push_back(MakePrimitive(node.primitive)); break;
    }
  }
  return meshes;
}

SceneGeometry BuildSceneGeometry(const Scene& scene, const std::vector<double>& psi_layout,
                                 int atlas_size) {
  if (atlas_size <= 0)  // "auto" must be resolved first (AtlasFootprint.h)
    throw std::logic_error("BuildSceneGeometry: atlas size " + std::to_string(atlas_size));
  SceneGeometry g;
  g.meshes = BuildMeshes(scene);
  const bool drawable = std::any_of(g.meshes.begin(), g.meshes.end(),
                                    [](const Mesh& m) { return m.TriangleCount() > 0; });
  if (!drawable)
    throw InputError(scene.file.string(), "nodes", "no node has a primitive: there is nothing to draw");
  // The layout is decided once, at psi_layout (usually the initial values): chart sizes
  // follow the world extents there, and stay fixed while the sampler moves the geometry.
  g.atlas = PackAtlas(g.meshes, scene.WorldFromNode(psi_layout), atlas_size);

  // PackAtlas lists charts in (node, face) order, so a node's faces start at first_chart.
  size_t chart = 0;
  std::vector<int> remap;  // mesh vertex → flattened vertex, for the current face
  for (size_t n = 0; n < g.meshes.size(); ++n) {
    const Mesh& mesh = g.meshes[n];
    for (size_t f = 0; f < mesh.faces.size(); ++f, ++chart) {
      const Chart& c = g.atlas.charts.at(chart);
      if (c.node != int(n) || c.face != int(f))
        throw std::logic_error("BuildSceneGeometry: atlas charts out of (node, face) order");
      // Vertices are emitted per face: one shared by two faces (none of ours is) would
      // need two atlas positions, so it is duplicated rather than given the wrong one.
      remap.assign(mesh.positions.size(), -1);
      const Face& face = mesh.faces[f];
      for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
        uint32_t corners[3];
        for (int k = 0; k < 3; ++k) {
          const uint32_t i = mesh.indices[3 * t + k];
          if (remap[i] < 0) {
            remap[i] = int(g.vertices.size());
            GpuVertex v;
            const Eigen::Vector2f uv = g.atlas.AtlasUv(c, mesh.face_uv[i]);
            for (int d = 0; d < 3; ++d) {
              v.position[d] = mesh.positions[i][d];
              v.normal[d] = mesh.normals[i][d];
            }
            v.atlas_uv[0] = uv.x();
            v.atlas_uv[1] = uv.y();
            v.node = uint32_t(n);
            v.face = uint32_t(chart);
            g.vertices.push_back(v);
          }
          corners[k] = uint32_t(remap[i]);
        }
        AppendSubdivided(g, corners);
      }
    }
  }
  return g;
}

std::vector<Image> LoadAlbedos(const Scene& scene) {
  std::vector<Image> albedos(scene.nodes.size());
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const auto& path = scene.nodes[n].albedo;
    if (path.empty()) continue;
    try {
      albedos[n] = LoadImage(path);
    } catch (const InputError& e) {
      // Blame the scene entry that named the texture; keep the image's own reason.
      throw InputError(scene.file.string(), "nodes[" + std::to_string(n) + "].albedo",
                       e.problem() + " (" + path.string() + ")");
    }
  }
  return albedos;
}

}  // namespace vkr
