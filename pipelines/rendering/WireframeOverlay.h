#pragma once
// The fitted model drawn as a wireframe over each photograph (the run's report,
// docs/guide/REPORT.md): the quickest way to
// see whether a reconstruction lines up with what the cameras saw. Host only: the scene's
// meshes at Ψ, projected through each camera (its lens included) onto the photograph as
// stored, with anti-aliased lines (Wu's algorithm). No occlusion test: hidden edges are
// drawn too (docs/guide/REPORT.md).

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"

namespace vkr {

// An edge of a node's mesh in world space. `normals` holds the unit normals of the one or
// two triangles that share it (one: a boundary edge).
struct WireEdge {
  Eigen::Vector3d a, b;
  std::vector<Eigen::Vector3d> normals;
};

// Every edge of the scene's meshes at Ψ, vertices welded by position (a mesh repeats the
// corners of each face for its atlas chart), with the normals of the triangles beside it.
std::vector<WireEdge> SceneEdges(const Scene& scene, const SceneGeometry& geometry, const std::vector<double>& psi);

struct WireframeOptions {
  // An edge is drawn where the faces beside it turn by more than this (degrees), so the
  // diagonals of flat faces and the facets of a smooth cylinder stay out.
  double crease_degrees = 20.0;
  std::array<float, 3> colour = {1.0f, 0.85f, 0.1f};  // encoded RGB
};

// Whether `edge` is drawn for a camera at `centre`: a boundary, a crease, or on the
// silhouette seen from there (one face turned to the camera, the other away).
bool IsDrawnEdge(const WireEdge& edge, const Eigen::Vector3d& centre, const WireframeOptions& options = {});

// `photo` (the camera's photograph as stored) with the drawn edges projected through
// `camera`, clipped at the near plane; through a lens the lines are drawn in short pieces so
// that they bend as the photograph's straight edges do.
Image DrawWireframe(const Image& photo, const Camera& camera, const std::vector<WireEdge>& edges,
                    const WireframeOptions& options = {});

// DIR/<camera>.png for every camera of the scene at Ψ; the files written.
std::vector<std::filesystem::path> WriteWireframeOverlays(const std::filesystem::path& dir, const Scene& scene,
                                                          const SceneGeometry& geometry,
                                                          const std::vector<double>& psi,
                                                          const WireframeOptions& options = {});

}  // namespace vkr
