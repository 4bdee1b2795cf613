#pragma once
// `vkrecon compare A.json B.json … -o OUT` (docs/guide/WHICH_SCENE.md): which of several scenes
// the same photographs support, by their log evidence under one likelihood. Each scene runs
// with the evidence ladder on and the noise model (σ, δ, κ) the first run calibrated held
// fixed for the others, or a finished run is read from its folder; then a table of log Z, log
// Bayes factors against the best and posterior model probabilities under equal prior odds.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "recon/Reconstruct.h"

namespace vkr::recon {

// One scene's line of the table. ReadComparedRun fills the first block from a run's map.json;
// TabulateComparison the second.
struct ComparedScene {
  std::string name;              // the scene's name: its run's folder under OUT
  std::filesystem::path run;     // the run's folder (map.json)
  double log_z = 0.0, se = 0.0;  // stepping stone and its Monte Carlo error
  double log_z_ti = 0.0, se_ti = 0.0;  // corrected thermodynamic integration and its error
  bool agree = false;            // the two estimators agree (Evidence.h, EvidenceEstimate::Agree)
  double ess = 0.0;              // effective draws behind se
  double min_swap = 0.0;         // the ladder's lowest swap rate between neighbouring rungs
  double map_log_likelihood = 0.0;
  double chi2_per_dof = 0.0;     // the diagnosis's, at the MAP
  nlohmann::json likelihood;     // map.json's evidence.likelihood: what the evidence is of

  double log_bayes_factor = 0.0, se_log_bayes_factor = 0.0;  // ln(Z / Z_best); 0 for the best
  double probability = 0.0, se_probability = 0.0;            // under equal prior odds
  std::string verdict;
  std::vector<std::string> doubts;  // why the number may not be trusted (empty: none found)
  // Whether the verdict stays the same with every error ComparisonBars::doubt_error_factor
  // times as large: then the doubts cannot change it, and the table does not show them.
  bool robust = true;
};

// Bars a verdict needs (docs/guide/WHICH_SCENE.md, "When to trust it"); the defaults are the
// evidence documentation's (docs/internals/EVIDENCE.md).
struct ComparisonBars {
  double decisive_log_bayes_factor = 5.0;  // Kass & Raftery's "very strong" is ln B > 5
  double min_ess = 200.0;
  double min_swap = 0.2;
  // How much larger the errors may be than stated where a doubt holds: on photographs,
  // ladders of one run scattered two to three times their stated errors at ESS 20-60
  // (docs/internals/EVIDENCE.md, "At default settings").
  double doubt_error_factor = 4.0;
};

// A finished run's line from OUT/map.json. InputError naming the file and field when it has
// no evidence (run without sampler.evidence_rungs) or is no run's folder.
ComparedScene ReadComparedRun(const std::filesystem::path& run_folder, const std::string& name);

// Log Bayes factors against the best (errors in quadrature, the runs being independent),
// probabilities p_i = Z_i / Σ Z_j with their delta-method errors, the doubts and the verdicts.
void TabulateComparison(std::vector<ComparedScene>* rows, const ComparisonBars& bars = {});

// InputError unless every row's evidence is of the same likelihood (σ, δ, κ, kind, colour
// correction, clutter), naming the first row that differs and how.
void CheckOneLikelihood(const std::vector<ComparedScene>& rows);

// InputError unless the two scenes look through the same cameras at the same photographs:
// names, images, sizes, intrinsics and poses; the error names `second`'s file.
void CheckSamePhotographs(const Scene& first, const Scene& second);

nlohmann::json ToJson(const std::vector<ComparedScene>& rows);  // OUT/compare.json
std::string MarkdownTable(const std::vector<ComparedScene>& rows);  // OUT/compare.md, also printed

struct CompareOptions {
  // Scene files (or folders with a scene.json) to run, or finished runs' folders (a map.json).
  std::vector<std::filesystem::path> inputs;
  std::vector<SceneOverride> overrides;  // --set, for every scene after compare's own
  int rungs = 12;                        // sampler.evidence_rungs for the scenes it runs
  // Run options (output_dir is OUT; each scene runs into OUT/<name>), ranks included.
  ReconstructOptions base;
  ComparisonBars bars;
};

// Runs what must run, reads the rest and writes OUT/compare.json and compare.md (rank 0),
// and returns the table (empty on other ranks). InputError for bad input: a missing file,
// scenes of other photographs, runs of other likelihoods, two inputs of one name.
std::vector<ComparedScene> CompareScenes(const CompareOptions& options, vk::Device& device);

}  // namespace vkr::recon
