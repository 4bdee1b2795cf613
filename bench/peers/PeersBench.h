#pragma once
// `vkrecon bench --only peers` (bench/RESULTS.md, "Peers"): how fast and how well
// `vkrecon run` finds the MAP against NLopt's methods (`vkrecon fit`) on the same likelihood.
// Per bundled asset and noise seed it synthesises reference images at σ = 16 as
// scripts/noise_study.py does (the asset's own settings, its synth.json if it has one), then
// records for `run` and for each method: the evaluations, full-resolution equivalents (a
// level-l evaluation counts 4^-l) and wall time until the running MAP has every parameter
// within `tolerance` of its prior width of the truth, and the final MAP's errors.
// A room of its own beside bench/harness/: it drives `run` and `fit` (recon/), which the
// harness, below them, may not include (docs/internals/OVERVIEW.md).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "optimiser/MapSearch.h"

namespace vkr {

struct PeersOptions {
  std::filesystem::path assets_dir;
  // Images, run outputs and peers.json with the rows so far (empty: a temporary folder, removed).
  std::filesystem::path work_dir;
  std::vector<std::string> assets = {"box", "house", "stairs", "poster"};
  std::vector<int> seeds = {1, 2, 3, 4, 5};  // noise seed = sampler seed = NLopt seed
  double sigma = 16.0;   // image noise sd, 0–255
  // Image size factor for synth: ¼ (160×120). On the shared 2-core machine a default run of
  // an asset takes ~5 min whatever the image size (the 256² atlas's texels dominate; 80 % of
  // its evaluations are at level 0), so the 20 runs fit in ~50 min only with `run` at 150
  // iterations (the assets say 600; the schedule shrinks in proportion) and small images:
  // `overrides` below. Every method sees the same likelihood.
  double scale = 0.25;
  double budget = 300.0; // full-resolution equivalents per NLopt method
  double tolerance = 0.01;  // "reached": every |MAP − truth| ≤ tolerance · prior width
  std::vector<opt::SearchMethod> methods = {opt::SearchMethod::Bobyqa, opt::SearchMethod::NelderMead,
                                            opt::SearchMethod::Sbplx, opt::SearchMethod::Crs2Lm,
                                            opt::SearchMethod::Isres};
  // Extra --set for every search (`run` and the methods alike, so they share the likelihood).
  // `run` at its defaults otherwise, its local search before sampling included
  // (SamplerOptions::start_search, 100 equivalents).
  std::vector<SceneOverride> overrides = {{"sampler.iterations", "150"}};
  bool quick = false;
  // Keep the (asset, seed) groups already in work_dir/peers.json, written with the same
  // settings, and run only the rest: a 45-minute bench cut short (lavapipe's rare crash,
  // docs/internals/HARDENING.md; a closed laptop) goes on where it stopped.
  bool resume = false;

  // One seed, box and poster, ¼-size images, a 128² atlas, 60 iterations of `run`, a budget
  // of 60: the test's (< 2 min).
  static PeersOptions Quick();
};

// One search of one (asset, seed): `run` or an NLopt method.
struct PeersRow {
  std::string asset, method;  // method: "run" or an NLopt method's name
  int seed = 0;
  bool reached = false;  // within tolerance before the end
  // Spent when first within tolerance (NaN when never): evaluations, full-resolution
  // equivalents, wall seconds from the call's start (photographs loaded, pipelines built).
  double evaluations_to = 0, equivalents_to = 0, seconds_to = 0;
  // Spent in all, up to the final MAP (run: sampling, refinement and polish; not its outputs).
  double evaluations = 0, equivalents = 0, seconds = 0;
  // The final MAP: median and largest |MAP − truth| / prior width over the parameters.
  double median_error = 0, max_error = 0;
};

struct PeersReport {
  std::string device;
  PeersOptions options;
  std::vector<PeersRow> rows;
  double wall_s = 0.0;
};

using PeersProgress = std::function<void(const std::string& line)>;

// InputError for an unknown asset (no assets_dir/NAME/scene.json or truth.json), or for
// --resume without a work folder or with a peers.json written with other settings; RunPeers
// calls it too, the command before the device opens.
void CheckPeersOptions(const PeersOptions& options);

PeersReport RunPeers(const PeersOptions& options, vk::Device& device, const PeersProgress& progress);

// {"device", "sigma", "overrides", "scale", "budget", "tolerance", "seeds", "assets", "wall_s",
//  "rows": [PeersRow as an object]}; NaN as null.
nlohmann::json PeersJson(const PeersReport& report);
// Per asset and method, over the seeds: how many reached the tolerance, medians of what it
// took them, median final error. Markdown.
std::string PeersTable(const PeersReport& report);

}  // namespace vkr
