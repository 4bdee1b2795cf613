#pragma once
// `vkrecon run`: photographs and a scene description in; a reconstructed, textured,
// parametric model with honest uncertainty out (docs/internals/SAMPLER.md). This is the one
// place where the sampler (optimiser/, no Vulkan) meets the likelihood (pipelines/).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"

namespace vkr::recon {

// What a caller (the peers benchmark, bench/peers/PeersBench.h) may watch of a run as it goes,
// rather than parsing its output. Called on rank 0 and every other rank alike.
struct RunObserver {
  // After every scoring call of the likelihood: its level and how many hypotheses it scored.
  // Level −1: the polish at twice the atlas's side (rank 0 only), each about four of level 0's.
  std::function<void(int level, size_t hypotheses)> evaluated;
  // The running MAP: after every sampler frame, the sampler's best hypothesis at its current
  // level (opt::Progress::best_psi); during the polish, the polish's best when it beats it.
  std::function<void(const std::vector<double>& psi)> best;
};

struct ReconstructOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::filesystem::path output_dir;
  bool resume = false;             // continue from output_dir/checkpoint.json
  bool quiet = false;              // no progress bar
  double checkpoint_seconds = 5.0; // how often the state is saved
  int temperatures = 0;            // replicas per chain; 0: sampler.batch / sampler.chains
  double time_limit = -1.0;        // seconds of sampling (0: none); below 0: sampler.time_limit
  bool one_process = false;        // this process alone, even under MPI (a scene of a list)
  RunObserver observer;
};

struct ReconstructResult {
  bool completed = false;          // false: stopped (interrupted); resume to finish
  bool diagnosis_ok = false;       // true only when the residuals look like noise and the chains agree
  bool failed = false;             // the model does not explain the images (exit 1)
  std::vector<std::string> notes;  // the diagnosis, one sentence each
  std::vector<double> map;         // the MAP hypothesis
  std::filesystem::path map_json;
};

// Runs (or resumes) the reconstruction and writes OUT/map.json, at_map.json (the MAP as an
// `--at` file), chain.csv, composite.exr (+ .png), model.glb and reprojections/. Throws InputError for bad input, including a scene
// whose cameras see nothing of it at the initial parameters.
ReconstructResult Reconstruct(const ReconstructOptions& options, vk::Device& device);

// Asks a running Reconstruct to checkpoint and stop after the current frame (SIGINT).
void RequestStop();

}  // namespace vkr::recon
