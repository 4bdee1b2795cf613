#pragma once
// What preview.html recomputes the scene from (report/preview.js): the parameters with their
// slider ranges, every expression's text, each node's transform chain and welded wireframe in
// its own frame, each camera as the scene writes it (K, R, t, pose, lens). Numbers in a chain
// or a K are a constant or {"expr": id}. With them go the C++ values the page checks its port
// against when it loads: each expression's value and a few vertices' pixels at Ψ.

#include <nlohmann/json.hpp>
#include <vector>

#include "engine/geometry/Mesh.h"
#include "engine/scene/Scene.h"

namespace vkr::report {

// The page's data at Ψ; `meshes` per node (BuildMeshes).
nlohmann::ordered_json PreviewData(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi);

}  // namespace vkr::report
