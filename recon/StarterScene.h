#pragma once
// The files `vkrecon init` writes besides cameras.json (SceneInit.h): the starter scene.json of
// a template, with priors that bracket the points above the ground, and points.ply.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "recon/CornerFit.h"
#include "recon/SceneInit.h"
#include "recon/StairsFit.h"

namespace vkr::recon {

// What a template's priors are set by, in the scene frame (ground z = 0).
struct StarterExtents {
  Eigen::Vector3d lo, hi;   // robust box of the points above the ground
  double ground_size = 1.0;  // side of the ground plane node
  std::optional<CornerFit> corner;  // the corner template's walls
  std::optional<StairsFit> stairs;  // the stairs template's flight
};

// scene.json of `kind`: parameters with uniform priors and inits from `extents`, the ground and
// the template's nodes, "images" (and "masks", when given) relative to the scene folder.
nlohmann::ordered_json StarterSceneJson(InitTemplate kind, const StarterExtents& extents,
                                        const std::string& images, const std::optional<std::string>& masks);

// An ASCII PLY of coloured points ("x y z red green blue" per vertex).
std::string PointsPly(const std::vector<Eigen::Vector3d>& xyz, const std::vector<std::array<std::uint8_t, 3>>& rgb);

}  // namespace vkr::recon
