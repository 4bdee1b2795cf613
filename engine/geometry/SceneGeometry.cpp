// Flattens a scene's geometry for the GPU (docs/internals/OVERVIEW.md, "How a hypothesis flows"):
// the vertices of every node are uploaded once per run in their node's frame, each tagged with its
// node (to pick the node matrix of a hypothesis) and its atlas position (the chart of its face,
// fixed for the run). A hypothesis then changes only the small buffer of node matrices.

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/common/InputError.h"
#include "engine/geometry/AtlasFootprint.h"
#include "engine/geometry/SceneGeometry.h"

namespace vkr {

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

const char* ToString(ChartSizing charts) { return charts == ChartSizing::Pixels ? "pixels" : "area"; }

bool FromString(const std::string& text, ChartSizing* charts) {
  if (text == "area") *charts = ChartSizing::Area;
  else if (text == "pixels") *charts = ChartSizing::Pixels;
  else return false;
  return true;
}

SceneGeometry BuildSceneGeometry(const Scene& scene, const std::vector<double>& psi_layout,
                                 int atlas_size, ChartSizing charts) {
  if (atlas_size <= 0)  // "auto" must be resolved first (AtlasFootprint.h)
    throw std::logic_error("BuildSceneGeometry: atlas size " + std::to_string(atlas_size));
  SceneGeometry g;
  g.meshes = BuildMeshes(scene);
  const bool drawable = std::any_of(g.meshes.begin(), g.meshes.end(),
                                    [](const Mesh& m) { return m.TriangleCount() > 0; });
  if (!drawable)
    throw InputError(scene.file.string(), "nodes", "no node has a primitive: there is nothing to draw");
  // The layout is decided once, at psi_layout (usually the initial values): chart sizes
  // follow the world extents there (times the faces' pixel densities under charts
  // "pixels"), and stay fixed while the sampler moves the geometry.
  g.atlas = PackAtlas(g.meshes, scene.WorldFromNode(psi_layout), atlas_size, 2,
                      charts == ChartSizing::Pixels ? ChartDensities(scene, g.meshes, psi_layout)
                                                    : std::vector<double>{});

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
      const double texel = 1.0 / c.texels_per_metre;
      remap.assign(mesh.positions.size(), -1);
      const Face& face = mesh.faces[f];
      for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
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
            v.texel_area = float(texel * texel);
            g.vertices.push_back(v);
          }
          g.indices.push_back(uint32_t(remap[i]));
        }
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
