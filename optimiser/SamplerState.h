#pragma once
// Internal to optimiser/: the sampler's whole state, shared by Sampler.cpp (the frames),
// Refinement.cpp, Checkpoint.cpp and Summary.cpp. Everything a run needs to continue lives
// here, so a checkpoint is this struct written out.

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "optimiser/Evidence.h"
#include "optimiser/JsonIntegers.h"
#include "optimiser/Parameter.h"
#include "optimiser/Random.h"
#include "optimiser/Sampler.h"
#include "optimiser/SamplerOptions.h"
#include "optimiser/Target.h"

namespace vkr::opt::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One replica of a chain: its current state and the statistics of its temperature slot.
// Replica exchange swaps states (psi, log_prior, log_likelihood) between slots; the
// counters and the adaptation accumulators stay with the slot (the temperature).
struct Replica {
  std::vector<double> psi;
  double log_prior = -kInf;
  double log_likelihood = -kInf;  // at the current level
  int64_t proposed = 0, accepted = 0;
  // Of those, the independence proposals (SamplerOptions::independence_share).
  int64_t independent_proposed = 0, independent_accepted = 0;
  // Log factor on the proposal scale, tuned during burn-in towards an acceptance of 0.234
  // (Robbins–Monro) and frozen after it; photographs make posteriors far narrower than a
  // fixed fraction of the prior width, and a too-wide walk accepts almost nothing.
  double log_scale = 0.0;
  // Welford accumulators of the states collected for adaptation (Haario et al. 2001).
  int64_t adapt_count = 0;
  Eigen::VectorXd adapt_mean;     // d
  Eigen::MatrixXd adapt_scatter;  // d × d: Σ (ψ − mean)(ψ − mean)ᵀ
};

struct ChainState {
  Rng rng;
  std::vector<Replica> replicas;  // coldest first
  std::vector<int64_t> swap_attempts, swap_accepts;  // per neighbour pair (k, k + 1)
};

// The evidence ladder (SamplerOptions::evidence_rungs): one more chain whose replicas sit at
// fixed β from 0 to 1 and target L^β·π. It steps every `every`-th iteration from `start`.
// Each rung tunes its own proposal (the power posterior at β = 0.001 is the prior's width,
// at β = 1 the posterior's) until collect_from, then keeps it fixed and records its log L
// every step.
struct EvidenceState {
  bool started = false;
  int start = 0;         // first iteration it ran
  int collect_from = 0;  // first iteration whose states are recorded
  int every = 1;         // SamplerOptions::evidence_every
  Rng rng;
  std::vector<double> beta;     // ascending, 0 … 1
  std::vector<Replica> rungs;   // one per β (Replica's counters and tuning serve as they are)
  // First guess of each rung's covariance: (β H + P⁻¹)⁻¹, H the Laplace precision at the
  // mode (settling's), P the prior's variances; and of its centre, the precision-weighted
  // mean of the mode and the prior's centre.
  std::vector<Eigen::MatrixXd> guess;
  std::vector<Eigen::VectorXd> guess_centre;
  std::vector<int64_t> swap_attempts, swap_accepts;  // per neighbour pair (k, k + 1)
  std::vector<std::vector<double>> draws;           // [rung][step since collect_from]: log L

  bool StepsAt(int t) const { return started && t >= start && (t - start) % every == 0; }
  int Step(int t) const { return (t - start) / every; }
  // Steps recorded before `iteration` (collect_from is a step).
  size_t Recorded(int iteration) const {
    return iteration <= collect_from ? 0 : size_t((iteration - collect_from + every - 1) / every);
  }
};

// The best hypothesis scored at `level` (reset when the level changes).
struct Best {
  bool valid = false;
  int level = 0;
  std::vector<double> psi;
  double log_prior = -kInf, log_likelihood = -kInf;
  double log_posterior() const { return valid ? log_prior + log_likelihood : -kInf; }
};

// Gradient refinement: BFGS ascent on the untempered log posterior at level 0, from the
// best hypothesis of the sampling, with the posterior covariance as first inverse Hessian.
struct RefineState {
  int step = 0;
  bool have_point = false;        // psi/gradient hold an evaluated point
  std::vector<double> psi;        // the current (accepted) point
  double log_prior = -kInf, log_likelihood = -kInf;
  std::vector<double> gradient;   // of the log posterior at psi
  Eigen::MatrixXd inverse_hessian;
  std::vector<double> candidate;  // evaluated by the next frame
  double step_scale = 1.0;        // fraction of the quasi-Newton step; shrinks on failure
};

struct State {
  SamplerOptions options;
  std::vector<ParameterSpec> parameters;
  int target_levels = 1;  // levels() of the target the run started with

  Phase phase = Phase::Start;
  int64_t frame = 0, evaluations = 0;
  int iteration = 0;  // sampling iterations done
  int level = 0;      // current likelihood level
  std::vector<ChainState> chains;
  Best best;
  double sampling_best = -kInf;  // best log posterior when sampling ended
  // What ended the sampling (EndedBy; "" while it runs) and the convergence measured last:
  // the largest rank-normalised split-R̂ and the smallest bulk-ESS over the parameters
  // (NaN before the first check).
  std::string ended_by;
  double max_rhat = kNaN, min_ess = kNaN;
  RefineState refine;
  // Settling (SamplerOptions::settle): rounds done; the target's calibration (null: none);
  // the Laplace covariance at the last mode (empty before settling or without it).
  int settle_rounds = 0;
  nlohmann::json calibration;
  Eigen::MatrixXd laplace;
  std::vector<double> mode;  // where the last settling round measured it (empty before)
  std::vector<Sample> samples;  // iteration-major: all chains of iteration 0, then 1, …
  EvidenceState evidence;

  int dimension() const { return int(parameters.size()); }
  int batch() const { return options.chains * options.temperatures; }
  int Levels() const;                     // levels the schedule uses
  int ScheduledLevel(int iteration) const;
  double AnnealTemperature(int iteration) const;  // of the coldest replicas
  double Temperature(int iteration, int replica) const;
  // Whether every replica samples at T = 1 as a chain of its own (cool_after_settling, once
  // the last settling round is done), and how many chains the posterior draws then pool:
  // replica k of chain c is chain k·chains + c, and those below posterior_chains sample.
  bool Cooled() const;
  int PosteriorChains() const;
  bool Samples(int chain, int replica) const {
    return !Cooled() || replica * options.chains + chain < PosteriorChains();
  }
  int AdaptStart() const;                 // first iteration whose states adaptation collects
  bool SettlesAt(int iteration) const;    // whether settling comes before this iteration
  int NextSettleAt() const;               // iteration of the next settling round; −1: none due
  // Records an evaluated hypothesis as the best so far at the current level if it is.
  void ConsiderBest(const std::vector<double>& psi, double log_prior, double log_likelihood);
};

// Summary.cpp: max_rhat and min_ess from the post-burn-in draws so far.
void MeasureConvergence(State& state);

// A fresh state: starting points (with jitter) and RNG streams; nothing evaluated yet.
State InitialState(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
                   int target_levels);

// Evaluates a batch of any size (split into calls of at most the target's batch), turning
// NaN and ±∞ into −∞ and counting evaluations.
using BatchEvaluator = std::function<std::vector<double>(const std::vector<std::vector<double>>&)>;

// Proposals.cpp: replica k's proposal at `temperature`. After settling, with probability
// independence_share an independence draw from a multivariate t around the mode (its
// log q(current) − log q(proposal) in log_q_ratio), else the random walk (log_q_ratio 0).
struct Proposal {
  std::vector<double> psi;
  double log_q_ratio = 0.0;
  bool independent = false;
};
Proposal Propose(const State& state, ChainState& chain, int k, double temperature);
// A draw from the multivariate t (ν = 8) around `centre` with `covariance` widened a little,
// and its log q(current) − log q(draw); nullopt where the covariance is not positive definite.
std::optional<Proposal> IndependenceDraw(const Eigen::VectorXd& centre, const Eigen::MatrixXd& covariance,
                                         const std::vector<double>& current, Rng& rng);

// Refinement.cpp. The refinement runs twice: in Phase::Settling to find the mode (then
// Phase::Restarting follows) and in Phase::Refining at the end (then Phase::Done).
void StartRefinement(State& state);
void RefineFrame(State& state, const BatchEvaluator& evaluate);
// Settle.cpp: the frame after the settling refinement (calibration, curvature, restart).
void RestartFrame(State& state, Target& target, const BatchEvaluator& evaluate);

// EvidenceSampling.cpp: the evidence ladder's part of a sampling frame. EvidenceProposals
// starts the ladder when its time has come and appends one hypothesis per rung to `batch`
// (a proposal outside the support is carried as the rung's current state); EvidenceStep
// takes their log-likelihoods (`values`, as many) after the chains' step of iteration t.
struct EvidenceProposal {
  std::vector<std::vector<double>> psi;
  std::vector<double> log_prior;
  std::vector<char> from_prior;  // an independent draw from the prior (β = 0): accepted when scored
  std::vector<char> independent;  // an independence draw (IndependenceDraw): log q ratio below
  std::vector<double> log_q_ratio;
};
EvidenceProposal EvidenceProposals(State& state, int t, std::vector<std::vector<double>>& batch);
void EvidenceStep(State& state, int t, EvidenceProposal proposal, const double* values);
// The estimate from the recorded draws; nullopt with the ladder off or fewer than 4 draws.
std::optional<EvidenceEstimate> EstimateFromLadder(const State& state);

// Checkpoint.cpp. StateFromJson throws std::invalid_argument naming what is wrong.
nlohmann::json StateToJson(const State& state);
State StateFromJson(const nlohmann::json& json);
nlohmann::json JsonNumber(double value);  // non-finite values as "nan", "inf", "-inf"
double ReadNumber(const nlohmann::json& json);

// Summary.cpp
SamplerSummary Summarise(const State& state);
// Post-burn-in states of the coldest replicas: [parameter][chain][draw].
std::vector<std::vector<std::vector<double>>> PosteriorDraws(const State& state);

}  // namespace vkr::opt::detail
