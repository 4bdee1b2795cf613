#pragma once
// Polishing the sampler's MAP with BOBYQA (bench/RESULTS.md, "Peers"): the sampler's best
// hypothesis plus its finite-difference refinement ends a few hundredths of a percent of the
// prior width from the mode, where a quadratic-model search from it converges in a few dozen
// evaluations. Used by `vkrecon run` after opt::Run (SamplerOptions::polish_evaluations).

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "optimiser/MapSearch.h"
#include "optimiser/Parameter.h"
#include "optimiser/Sampler.h"
#include "optimiser/Target.h"

namespace vkr::opt {

struct PolishSummary {
  int64_t evaluations = 0;
  bool improved = false;     // the MAP moved
  double improvement = 0.0;  // log posterior gained (nats, ≥ 0)
  std::string message;       // MapSearchSummary's
};

// The polish's search: BOBYQA at level 0 from summary.map, first steps of two posterior sds
// per parameter (the sample's, else the Laplace approximation's, within [1e-6, 0.05] of the
// prior width), at most `evaluations` evaluations, converging far below what photographs
// resolve (the budget ends it). Also what the polish at the finer atlas climbs with
// (recon/FinerAtlasPolish.h).
MapSearchOptions PolishOptions(const std::vector<ParameterSpec>& parameters, const SamplerSummary& summary,
                               int evaluations);

// PolishOptions' search. Where it finds a higher log posterior it replaces the
// summary's MAP and its log prior, likelihood, posterior and per-parameter "map", and adds
// its evaluations to summary->evaluations. A summary without a MAP, or 0 evaluations:
// nothing happens. Deterministic: every MPI rank that runs it runs the same search.
PolishSummary PolishMap(const std::vector<ParameterSpec>& parameters, Target& target, int evaluations,
                        SamplerSummary* summary, const SearchCallback& on_evaluation = {});

// Before the sampler (SamplerOptions::start_search): BOBYQA coarse-to-fine over the target's
// levels from each parameter's Initial(), at most `cost` full-resolution equivalents.
// Deterministic, like PolishMap. Its map is empty when nothing scored finite.
MapSearchSummary SearchStart(const std::vector<ParameterSpec>& parameters, Target& target, double cost,
                             const SearchCallback& on_evaluation = {});

// The chains' MAP against another mode (the local search's), as AdoptIfHigher compared them:
// log posteriors from Target::ScoreModes (−∞ where one cannot be scored).
struct ModeComparison {
  double chains = -INFINITY;
  double candidate = -INFINITY;
  bool adopted = false;
};

// After the sampler: scores the summary's MAP and `candidate` with Target::ScoreModes (each
// with the nuisances a calibration at it would fit: masks found at the chains' mode would
// otherwise protect it) and makes `candidate` summary's MAP where its log posterior is higher.
// The target's nuisances are then refitted at it (Target::RefitAt; summary's calibration
// becomes the refit's, with the chains' κ), and the adopted MAP's log likelihood is the
// target's own under them, so that what follows compares with it; the per-parameter
// summaries other than "map" stay the chains'. A candidate outside the prior or of the
// wrong length, or a summary without a MAP, is not scored.
ModeComparison AdoptIfHigher(const std::vector<ParameterSpec>& parameters, Target& target,
                             const std::vector<double>& candidate, SamplerSummary* summary);

}  // namespace vkr::opt
