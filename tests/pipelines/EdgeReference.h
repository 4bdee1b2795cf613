#pragma once
// A CPU reference of the surface likelihood's edge term (shaders_glsl/edges.comp,
// pipelines/model/EdgeEvidence.h) in double precision, independent of the GPU path: visibility
// by casting the segment sample → camera centre against every triangle of the scene instead of
// a depth map, colours by host bilinear sampling of the level's image.

#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace vkr::test {

struct EdgeSums {
  double log_edges = 0.0;  // Σ w·log-ratio over the cameras
  double length = 0.0;     // Σ w, level pixels
};

// The edge term of hypothesis `psi` at pyramid level `level`: `pyramids` from
// LoadReferencePyramids (every pixel valid), σ and the edge model from `options`, ε per camera
// measured on its pyramid level as SurfaceLikelihood measures it.
EdgeSums ReferenceEdgeSums(const Scene& scene, const SceneGeometry& geometry,
                           const std::vector<std::vector<Image>>& pyramids, const std::vector<double>& psi, int level,
                           const SurfaceLikelihoodOptions& options);

}  // namespace vkr::test
