#pragma once
// Polishing the sampler's MAP with BOBYQA (issue 15, "Peer comparison"): the sampler's best
// hypothesis plus its finite-difference refinement ends a few hundredths of a percent of the
// prior width from the mode, where a quadratic-model search from it converges in a few dozen
// evaluations. Used by `vkrecon run` after opt::Run (SamplerOptions::polish_evaluations).

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

// BOBYQA at level 0 from summary->map, first steps of two posterior sds per parameter
// (the sample's, else the Laplace approximation's, within [1e-6, 0.05] of the prior width),
// at most `evaluations` evaluations. Where it finds a higher log posterior it replaces the
// summary's MAP and its log prior, likelihood, posterior and per-parameter "map", and adds
// its evaluations to summary->evaluations. A summary without a MAP, or 0 evaluations:
// nothing happens. Deterministic: every MPI rank that runs it runs the same search.
PolishSummary PolishMap(const std::vector<ParameterSpec>& parameters, Target& target, int evaluations,
                        SamplerSummary* summary, const SearchCallback& on_evaluation = {});

}  // namespace vkr::opt
