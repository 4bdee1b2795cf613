#pragma once
// What a reconstruction found (Reconstruct.h), after Ceres's Solver::Summary: how it ended,
// the sampler's parameter table and draws, the MAP, the searches around it, the diagnosis and
// the files written. ToJson() is OUT/map.json (docs/reference/OUTPUTS.md, "map.json").

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimiser/MapSearch.h"
#include "optimiser/Polish.h"
#include "optimiser/Sampler.h"
#include "recon/Diagnosis.h"
#include "recon/FinerAtlasPolish.h"

namespace vkr::recon {

struct ReconstructSummary {
  // Completed: sampled, refined and written. Stopped: should_stop or the time before the
  // first frame ran out; the checkpoint is the output, and a run with `resume` continues it.
  opt::Termination termination = opt::Termination::Stopped;
  // The chains' summary: the parameter table (map, mean, sd, q025, q975, ess, rhat), the
  // draws (`chain`, burn-in included), the calibration and the MAP's log posterior. Its MAP
  // is the run's, after the adoption of the start search's mode and both polishes.
  opt::SamplerSummary sampler;
  // The local search before sampling (empty map: none), and its mode against the chains'.
  opt::MapSearchSummary start_search;
  opt::ModeComparison start_compared;
  opt::PolishSummary polish;       // BOBYQA from the MAP, at the run's atlas
  FinerAtlasPolish finer;          // then at twice the atlas's side (FinerAtlasPolish.h)
  std::vector<std::string> clutter_files;  // the final clutter masks, relative to output_dir
  Diagnosis diagnosis;             // whether the result can be trusted, and why not
  nlohmann::json settings;         // the effective settings, so that the run can be repeated
  // The likelihood the evidence ladder sampled (the chains' last calibration): σ, δ, κ and
  // whether each was fixed by the scene or estimated; map.json's evidence.likelihood.
  nlohmann::json evidence_likelihood;
  std::filesystem::path output_dir;
  std::vector<std::filesystem::path> written;  // the outputs, map.json among them

  bool completed() const { return termination == opt::Termination::Completed; }
  const std::vector<double>& map() const { return sampler.map; }
  // The model does not explain the images (`vkrecon run` exits 1).
  bool failed() const { return diagnosis.verdict == Diagnosis::Verdict::Failed; }

  std::string BriefReport() const;  // one line: how it ended, the MAP's log posterior, the verdict
  std::string FullReport() const;   // the sampler's tables, then the searches and the diagnosis
  nlohmann::json ToJson() const;    // map.json, byte for byte as `vkrecon run` writes it
};

// map.json's "start_search" before the end of the run (also OUT/start_search.json, which a
// resumed run reads back with StartSearchFromJson).
nlohmann::json ToJson(const opt::MapSearchSummary& start);
opt::MapSearchSummary StartSearchFromJson(const nlohmann::json& j);

// The posterior draws: every chain's coldest replica from the burn-in on, as in
// OUT/chains/stan-<k>.csv, chain by chain.
std::vector<const opt::Sample*> PosteriorDraws(const opt::SamplerSummary& summary);

}  // namespace vkr::recon
