#pragma once
// `vkrecon run` as a library call, shaped after Ceres's Solve: photographs and a loaded scene
// in, a ReconstructSummary out (the parametric model's MAP, its honest uncertainty, whether to
// trust it), the outputs written to a folder (docs/internals/SAMPLER.md). This is the one
// place where the sampler (optimiser/, no Vulkan) meets the likelihood (pipelines/).

#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "recon/ReconstructSummary.h"

namespace vkr::recon {

class Ranks;

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
  // The scene, as LoadSearchScene (SearchSetup.h) returns it; read while the run lasts. Its
  // file and overrides go into map.json's settings, and the polish at the finer atlas loads
  // that file again with them.
  std::shared_ptr<const Scene> scene;
  std::filesystem::path output_dir;  // the checkpoint and every output
  bool resume = false;               // continue from output_dir/checkpoint.json
  double checkpoint_seconds = 5.0;   // how often the state is saved
  int temperatures = 0;              // replicas per chain; 0: sampler.batch / sampler.chains
  double time_limit = -1.0;          // seconds of sampling (0: none); below 0: sampler.time_limit
  // The processes that share each batch (Ranks.h): &Ranks::World() under mpirun; null, this
  // process alone. Every rank runs the same sampler; rank 0 alone writes.
  const Ranks* ranks = nullptr;
  // Polled after every sampler frame: true checkpoints and stops the run (the command line's
  // SIGINT sets the flag its callback reads). Under MPI rank 0's answer counts.
  std::function<bool()> should_stop;
  // Where the progress line and the run's messages go (null: nowhere). `quiet` keeps only
  // the warnings; a progress line on a terminal's stderr is redrawn in place.
  std::ostream* log = &std::cerr;
  bool quiet = false;
  RunObserver observer;

  // A scene and an output folder, and numbers in range; else false and why.
  bool IsValid(std::string* why) const;
};

// Runs (or resumes) the reconstruction into `summary`. When it completes, rank 0 writes
// OUT/map.json (summary->ToJson()), at_map.json (the MAP as an `--at` file), chain.csv,
// chains/, composite.exr (+ .png), model.glb, reprojections/ and report.html; stopped, the
// checkpoint. Throws InputError for bad input, including a scene whose cameras see nothing of
// it at the initial parameters, and std::invalid_argument for options that are not IsValid.
void Reconstruct(const ReconstructOptions& options, vk::Device& device, ReconstructSummary* summary);

}  // namespace vkr::recon
