#pragma once
// The stages of Reconstruct (Reconstruct.h) that its files share: what every stage of one run
// sees, and the stage at the MAP (RunOutputs.cpp). Callers call Reconstruct, not these.

#include <filesystem>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/geometry/SceneGeometry.h"
#include "optimiser/Sampler.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "recon/Ranks.h"
#include "recon/Reconstruct.h"
#include "recon/SearchSetup.h"

namespace vkr::recon {

// What every stage of one run shares. Under MPI every rank runs the same stages with the same
// sampler; rank 0 alone writes (checkpoints, clutter masks, outputs) and talks
// (docs/guide/SCALE_OUT.md).
struct RunContext {
  RunContext(const ReconstructOptions& options, vk::Device& device)
      : options(options),
        device(device),
        scene(*options.scene),
        ranks(options.ranks ? *options.ranks : Ranks::One()),
        root(ranks.rank() == 0),
        quiet(options.quiet || !root || !options.log),
        checkpoint_file(options.output_dir / "checkpoint.json"),
        start_file(options.output_dir / "start_search.json"),
        // Per invocation: a resumed run gets the whole limit again.
        likelihood(LikelihoodSettingsOf(scene)),
        sampler(SamplerOptionsOf(scene)),
        time_limit(options.time_limit >= 0.0 ? options.time_limit : sampler.TimeLimit()) {}

  // The run's messages (progress, what it did) unless quiet; Warn's whatever quiet says.
  std::ostream* Say() const { return quiet ? nullptr : options.log; }
  std::ostream* Warn() const { return root ? options.log : nullptr; }

  const ReconstructOptions& options;
  vk::Device& device;
  const Scene& scene;
  const Ranks& ranks;
  const bool root, quiet;
  const std::filesystem::path checkpoint_file;
  // The local search before sampling (SamplerOptions::start_search), kept beside the
  // checkpoint: a resumed run compares the same mode at the end.
  const std::filesystem::path start_file;
  // The scene's settings blocks, typed: "auto" atlas and levels resolved (LoadSearchScene).
  const LikelihoodSettings likelihood;
  const opt::SamplerOptions sampler;  // before the run adds the likelihood's levels (SamplerOptionsFor)
  const double time_limit;  // seconds of sampling; 0: none
};

// "12s", "3m05s"; "?" when not a time.
std::string Duration(double seconds);

// Rank 0, after a completed and refined run: the polish at the finer atlas, then the outputs
// that show the model at the MAP (composite, model.glb, reprojections/, clutter/) and the
// diagnosis of what they show, into `summary`; `geometry`: the scene's, for the report.
// `chains_calibration`: the checkpoint's, whose clutter masks stay.
void FinishAtMap(const RunContext& run, const opt::Sampler& sampler, const nlohmann::json& chains_calibration,
                 ReconstructSummary* summary, SceneGeometry* geometry);


}  // namespace vkr::recon
