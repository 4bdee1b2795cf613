#pragma once
// Everything a scene draws, flattened for the GPU: one vertex and one index array for all
// nodes (uploaded once per run), and the atlas layout. A vertex carries its node's index,
// so a whole hypothesis is one draw reading node matrices from a small buffer.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/geometry/Atlas.h"
#include "engine/geometry/Mesh.h"
#include "engine/scene/Scene.h"

namespace vkr {

// std430/vertex-input friendly: 40 bytes.
struct GpuVertex {
  float position[3];  // node frame
  float normal[3];    // node frame
  float atlas_uv[2];  // [0,1]², atlas texel centre convention: texel (i,j) at ((i+.5)/N, (j+.5)/N)
  uint32_t node;      // index into Scene::nodes
  uint32_t face;      // global face (= chart) index, for per-face lookups
  float texel_area;   // world area of one full-resolution texel of the vertex's chart (m²)
};
static_assert(sizeof(GpuVertex) == 44);

struct SceneGeometry {
  std::vector<Mesh> meshes;  // per node; empty for transform-only nodes
  AtlasLayout atlas;
  std::vector<GpuVertex> vertices;
  std::vector<uint32_t> indices;
};

// Every node's mesh in its own frame (empty for transform-only nodes). Throws InputError for
// unreadable meshes.
std::vector<Mesh> BuildMeshes(const Scene& scene);

// How the atlas shares its texels among the faces (likelihood.charts): Area, the same texels
// per metre everywhere; Pixels, in proportion to the pixels each face covers in the camera
// that sees it largest (ChartDensities, AtlasFootprint.h).
enum class ChartSizing { Area, Pixels };
const char* ToString(ChartSizing charts);
bool FromString(const std::string& text, ChartSizing* charts);

// Builds meshes (primitives, glTF files), packs the atlas at Ψ = `psi_layout` (usually the
// initial values; charts sized as `charts` says) and flattens. Throws InputError for
// unreadable meshes.
SceneGeometry BuildSceneGeometry(const Scene& scene, const std::vector<double>& psi_layout,
                                 int atlas_size, ChartSizing charts);

// Each node's albedo image (empty Image for nodes without one). Throws InputError naming
// the scene file and nodes[i].albedo when a texture cannot be read.
std::vector<Image> LoadAlbedos(const Scene& scene);

}  // namespace vkr
