#pragma once
// `vkrecon fit`: the maximum a posteriori parameters only, found by one of NLopt's
// derivative-free methods on the same likelihood `run` samples, coarse-to-fine over its
// levels (optimiser/MapSearch.h). No intervals: `run` is what says how sure the answer is.
// Faster to a point estimate, and the peers `run` is measured against (PeersBench.h).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "optimiser/MapSearch.h"

namespace vkr::recon {

struct FitOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::filesystem::path output_dir;  // empty: write nothing (the peers benchmark)
  opt::SearchMethod method = opt::SearchMethod::Bobyqa;
  // Budget in full-resolution-equivalent evaluations (a level-l one counts 4^-l).
  double evaluations = 300.0;
  // Pyramid levels to search, coarsest first (0: all the scene's likelihood.levels).
  int levels = 0;
  // Restarts of a local method from its mode at level 0 while the budget lasts
  // (MapSearchOptions::restarts): on the rasterised likelihood BOBYQA often reports
  // convergence short of the mode (the peers bench's stairs, ¼ size, σ 16: median error
  // 0.97 → 0.41 % of the prior width over five seeds with 3). 0 runs the NLopt method as
  // NLopt ends it (the peers benchmark).
  int restarts = 3;
  bool quiet = false;  // no progress on stderr
  // Every evaluation (level, ψ, log posterior, counts), for callers that watch the search.
  opt::SearchCallback on_evaluation;
};

struct FitResult {
  opt::MapSearchSummary summary;
  std::vector<std::string> names;  // the parameters, in the order of summary.map
  double wall_s = 0.0;             // the search, after loading the photographs
  std::filesystem::path map_json;  // empty when nothing was written
};

// InputError naming the option for a budget ≤ 0 or levels < 0 (FitMap calls it too; the
// command calls it before the device opens).
void CheckFitOptions(const FitOptions& options);

// Searches the MAP and, with an output folder, writes OUT/map.json ({"map_only": true,
// "method", "parameters": {NAME: {"map"}}, "log_posterior", "log_prior", "log_likelihood",
// "evaluations", "full_resolution_equivalents", "levels", "restarts", "wall_s", "message", "settings"})
// and OUT/at_map.json (the MAP as an `--at` file). Throws InputError for bad input (the
// scene, a budget ≤ 0) and std::runtime_error when no hypothesis scored.
FitResult FitMap(const FitOptions& options, vk::Device& device);

}  // namespace vkr::recon
