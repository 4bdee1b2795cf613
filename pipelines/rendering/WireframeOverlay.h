#pragma once
// The fitted model drawn as a wireframe over each photograph (the run's report,
// docs/guide/REPORT.md): the quickest way to
// see whether a reconstruction lines up with what the cameras saw. Host only: the scene's
// meshes at Ψ, projected through each camera (its lens included) onto the photograph as
// stored, with anti-aliased lines (Wu's algorithm). Edges that other surfaces hide are left
// out where a depth buffer is given (HiddenLines.h), as the report does.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <vector>

#include "engine/geometry/Mesh.h"
#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "pipelines/rendering/HiddenLines.h"

namespace vkr {

// An edge of a node's mesh in world space. `normals` holds the unit normals of the one or
// two triangles that share it (one: a boundary edge).
struct WireEdge {
  Eigen::Vector3d a, b;
  std::vector<Eigen::Vector3d> normals;
};

// A node's mesh as a wireframe in its own frame: the positions welded (a mesh repeats the
// corners of each face for its atlas chart), the triangles over the welded vertices, and each
// edge with the triangles beside it. Independent of Ψ: SceneEdges moves it into the world at a
// hypothesis, and `vkrecon preview`'s page does the same in JavaScript.
struct NodeWire {
  struct Edge {
    int a = 0, b = 0;            // welded vertices
    std::vector<int> triangles;  // indices into `triangles`
  };
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Edge> edges;
};
NodeWire WeldWire(const Mesh& mesh);

// Every edge of the scene's meshes at Ψ (NodeWire moved into the world), with the normals of
// the triangles beside it; triangles that the transform collapses do not count.
std::vector<WireEdge> SceneEdges(const Scene& scene, const SceneGeometry& geometry, const std::vector<double>& psi);

// Every triangle of the scene's meshes at Ψ, in the world: what hides an edge.
std::vector<WorldTriangle> SceneTriangles(const Scene& scene, const SceneGeometry& geometry,
                                          const std::vector<double>& psi);

struct WireframeOptions {
  // An edge is drawn where the faces beside it turn by more than this (degrees), so the
  // diagonals of flat faces and the facets of a smooth cylinder stay out.
  double crease_degrees = 20.0;
  std::array<float, 3> colour = {1.0f, 0.85f, 0.1f};  // encoded RGB
  // Weight of the colour over the photograph: below 1, faint lines (the preview's prior extremes).
  float opacity = 1.0f;
};

// Whether `edge` is drawn for a camera at `centre`: a boundary, a crease, or on the
// silhouette seen from there (one face turned to the camera, the other away).
bool IsDrawnEdge(const WireEdge& edge, const Eigen::Vector3d& centre, const WireframeOptions& options = {});

// Pixel coordinates of a camera-frame point in front of the camera, through its lens (the
// photograph as stored); the preview page's JavaScript port is checked against it.
Eigen::Vector2d LensPixel(const Camera& camera, const Eigen::Vector3d& x_cam);

// `photo` (the camera's photograph as stored) with the drawn edges projected through
// `camera`, clipped at the near plane; through a lens the lines are drawn in short pieces so
// that they bend as the photograph's straight edges do. With `hidden` (the camera's depth
// buffer of the scene), only the pieces it shows are drawn, a pixel at a time.
Image DrawWireframe(const Image& photo, const Camera& camera, const std::vector<WireEdge>& edges,
                    const WireframeOptions& options = {}, const DepthBuffer* hidden = nullptr);

// DIR/<camera>.png for every camera of the scene at Ψ, hidden edges left out; the files written.
std::vector<std::filesystem::path> WriteWireframeOverlays(const std::filesystem::path& dir, const Scene& scene,
                                                          const SceneGeometry& geometry,
                                                          const std::vector<double>& psi,
                                                          const WireframeOptions& options = {});

}  // namespace vkr
