#pragma once
// The writer over a reconstruction's summary (ReconstructSummary.h): the files that describe
// the result rather than show the model. Reconstruct calls it on rank 0 when a run completes;
// a caller that changed nothing gets the same bytes again.

#include <filesystem>
#include <vector>

#include "engine/scene/Scene.h"
#include "recon/ReconstructSummary.h"

namespace vkr::recon {

// Into summary.output_dir: at_map.json (the MAP as an `--at` file, for `render --at`),
// chain.csv, chains/stan-<k>.csv (CmdStan's format, for ArviZ) and map.json (ToJson()) last,
// so that a map.json marks a finished run. `scene`: the run's. Returns the paths written.
std::vector<std::filesystem::path> WriteRunFiles(const ReconstructSummary& summary, const Scene& scene);

}  // namespace vkr::recon
