#pragma once
// A search for the maximum a posteriori hypothesis with NLopt's derivative-free methods
// (bench/RESULTS.md, "Peers"): maximises log prior + log likelihood of a Target over the
// box of the priors' supports, optionally coarse-to-fine over its levels (§7.3). No
// intervals: where the sampler answers "how sure", this answers only "where is the mode",
// for `vkrecon fit`, for the peers benchmark, and to polish the sampler's MAP (`run`).
//
//   opt::MapSearchOptions options;  options.method = opt::SearchMethod::Bobyqa;
//   opt::MapSearchSummary summary;
//   opt::SearchMap(options, parameters, target, &summary, on_evaluation);
//
// NLopt scores one point at a time: every Evaluate() call here holds one hypothesis.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "optimiser/Parameter.h"
#include "optimiser/Target.h"

namespace vkr::opt {

enum class SearchMethod {
  Bobyqa,      // LN_BOBYQA: quadratic models in a trust region (Powell 2009); local
  NelderMead,  // LN_NELDERMEAD: the simplex method; local
  Sbplx,       // LN_SBPLX: Nelder–Mead on subspaces (Rowan 1990); local
  Crs2Lm,      // GN_CRS2_LM: controlled random search with local mutation; global
  Isres,       // GN_ISRES: improved stochastic ranking evolution strategy; global
};
const char* ToString(SearchMethod method);
bool FromString(const std::string& text, SearchMethod* method);
std::string SearchMethodNames();  // "bobyqa, neldermead, sbplx, crs2lm, isres"

struct MapSearchOptions {
  SearchMethod method = SearchMethod::Bobyqa;
  // Budget in full-resolution-equivalent evaluations: an evaluation at level l costs
  // level_cost^-l (4: each pyramid level halves both image sides, so a level-l hypothesis
  // is about 4^-l of the work of a full-resolution one; 1 counts every evaluation alike).
  // The search stops when the next evaluation would exceed it.
  double max_cost = 300.0;
  double level_cost = 4.0;
  // Coarse-to-fine: use at most this many of the target's levels (1: level 0 only), the
  // coarsest first, each started at the previous level's best. Every coarse level may spend
  // coarse_share of max_cost (what it leaves carries on); level 0 gets the rest.
  int levels = 1;
  double coarse_share = 0.15;
  // Start (empty: each parameter's Initial(), the prior's centre or `init`).
  std::vector<double> start;
  // First step of the local methods per parameter as a fraction of its prior width, at the
  // first level; later levels start from a better point and use step_shrink times the step
  // of the level before. initial_steps (absolute, one per parameter) overrides both.
  double initial_step = 0.1;
  double step_shrink = 0.25;
  std::vector<double> initial_steps;
  // Convergence: stop a level when a step moves no parameter by more than this fraction of
  // its prior width (level 0; coarse levels use coarse_tolerance, their mode is only a
  // start for the next). The global methods mostly run to the budget.
  double tolerance = 1e-6;
  double coarse_tolerance = 1e-4;
  // Normal priors without bounds have no box: the search keeps to mean ± this many sds.
  double normal_span = 5.0;
  // Restarts of a local method at level 0 from its best point (0: the method's one run, as
  // NLopt ends it). On a rasterised likelihood BOBYQA's trust region can shrink to nothing
  // on the roughness short of the mode and report convergence (house at 0.25×, σ 16: a roof
  // height 1.4 % of its prior off; restarted once, 0.35 %, 334 nats higher). Each restart
  // begins with steps of restart_step of each prior width; they end when the budget is
  // spent, after `restarts`, or when one moves no parameter by more than restart_tolerance
  // of its width. The global methods spend the budget and are never restarted.
  int restarts = 0;
  double restart_step = 0.02;
  double restart_tolerance = 1e-3;
  uint64_t seed = 1;  // NLopt's random numbers (crs2lm, isres; nlopt::srand)

  bool IsValid(std::string* why) const;
};

// What the per-evaluation callback sees.
struct SearchEvaluation {
  int level = 0;
  const std::vector<double>* psi = nullptr;
  double log_posterior = 0.0;  // log prior + log likelihood; −∞ when not scorable
  int64_t evaluations = 0;     // done, this one included
  double cost = 0.0;           // full-resolution equivalents spent, this one included
};
using SearchCallback = std::function<void(const SearchEvaluation&)>;

struct MapSearchSummary {
  bool ok = false;      // false: invalid input (message says why) or nothing finite scored
  std::string message;  // NLopt's reason for ending each level, or the failure
  SearchMethod method = SearchMethod::Bobyqa;
  std::vector<double> map;  // best hypothesis at level 0 (empty when none scored finite)
  double log_prior = 0.0, log_likelihood = 0.0, log_posterior = 0.0;
  int64_t evaluations = 0;
  double cost = 0.0;                         // full-resolution equivalents spent
  std::vector<int> levels;                   // the levels searched, in order
  std::vector<int64_t> level_evaluations;    // evaluations at each of `levels`
  int restarts = 0;                          // level-0 restarts run (each also listed in `levels`)

  std::string BriefReport() const;  // one line
};

// Valid options and parameters, target levels ≥ 1, a start (if given) of the right size
// inside the supports. Invalid input: returns false with summary->message.
bool SearchMap(const MapSearchOptions& options, const std::vector<ParameterSpec>& parameters, Target& target,
               MapSearchSummary* summary, const SearchCallback& on_evaluation = {});

// The search box: each parameter's support, a normal prior without bounds cut to mean ±
// normal_span sds.
double SearchLower(const ParameterSpec& parameter, double normal_span);
double SearchUpper(const ParameterSpec& parameter, double normal_span);

}  // namespace vkr::opt
