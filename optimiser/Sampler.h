#pragma once
// The sampler (docs/internals/SAMPLER.md; options and schedule in SamplerOptions.h).
//
//   opt::SamplerSummary summary;
//   opt::Run(options, parameters, target, &summary, callbacks);   // or Resume(checkpoint, …)
//
// or, frame by frame, opt::Sampler with Step(), Checkpoint() and Summary().
//
// Frames. Each Step() is one frame and makes exactly one call of Target::Evaluate (a
// refinement step whose 2d + 1 hypotheses exceed the target's batch makes ⌈(2d+1)/K⌉):
//   - the first frame evaluates every replica's starting point;
//   - a sampling frame evaluates one proposal per replica: chains × temperatures
//     hypotheses, always that many. A proposal outside the prior's support is rejected
//     without being scored; its slot carries the replica's current state instead (harmless:
//     a constant batch size keeps GPU timings comparable and the frame count simple);
//   - when the schedule moves to a finer level, one frame re-evaluates every replica's
//     current state at the new level (it is not an iteration);
//   - a refinement frame (settling's or the final one) evaluates the candidate and its
//     ± finite-difference neighbours;
//   - the restart frame after settling makes several calls: the curvature's 1 + 2d²
//     points (twice when the target recalibrates) and every replica's new start.
// A hypothesis whose log-likelihood is NaN or ±∞ is rejected (a numerical outcome, not an
// exception).
//
// Determinism. Each chain draws from its own Rng stream (Random.h) seeded from
// options.seed, so the same seed, options, parameters and target give the same chain.
// Checkpoint() captures the whole state (iteration, replicas, RNG states, adaptation
// accumulators, the chain so far, the best hypothesis, the refinement); a Sampler built
// from it continues exactly as the original would have, bit for bit.

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimiser/Evidence.h"
#include "optimiser/Parameter.h"
#include "optimiser/SamplerOptions.h"
#include "optimiser/Target.h"

namespace vkr::opt {

enum class Phase {
  Start,     // the starting points are not evaluated yet
  Sampling,  // Metropolis–Hastings iterations
  Settling,  // mid-run gradient refinement to the mode (SamplerOptions::settle)
  Restarting,  // calibration, curvature and restart around the mode (one frame)
  Refining,  // gradient refinement of the best hypothesis
  Done,
};
const char* ToString(Phase phase);
bool FromString(const std::string& text, Phase* phase);

enum class Termination {
  Completed,  // every iteration and the refinement ran
  Stopped,    // stopped before the end (a callback asked, or Summary() of a running sampler)
  Failed,     // invalid input, or no hypothesis had a finite log posterior at level 0
};
const char* ToString(Termination termination);
bool FromString(const std::string& text, Termination* termination);

// One row of the chain: the coldest replica of one chain after one iteration; once every
// replica samples at T = 1 (cool_after_settling), one row per replica k of chain c, as
// chain k·chains + c.
struct Sample {
  int iteration = 0;
  int chain = 0;
  int level = 0;             // likelihood level the state was scored at
  double temperature = 1.0;  // of the coldest replica (annealing)
  bool accepted = false;     // its proposal was accepted this iteration
  bool swapped = false;      // it took a hotter neighbour's state this iteration
  double log_prior = 0.0;
  double log_likelihood = 0.0;
  std::vector<double> psi;
  // log prior + log likelihood, untempered.
  double log_posterior() const { return log_prior + log_likelihood; }
};

// What the progress callback sees after each frame.
struct Progress {
  Phase phase = Phase::Start;  // after the frame
  int64_t frame = 0;           // frames done (≈ calls of Evaluate)
  int64_t evaluations = 0;     // hypotheses scored
  int iteration = 0;           // sampling iterations done
  int iterations = 0;          // planned (with until_converged: the schedule's, at least)
  bool until_converged = false;
  // Largest rank-normalised split-R̂ and smallest bulk-ESS over the parameters at the last
  // check (every convergence_interval iterations after the burn-in; NaN before).
  double max_rhat = 0.0, min_ess = 0.0;
  int refine_step = 0;         // refinement steps done
  int level = 0;
  double temperature = 1.0;    // of the coldest replicas
  // Best untempered log posterior scored at the current level (−∞ before any).
  double best_log_posterior = 0.0;
  // The hypothesis that scored it (empty before any): the running MAP, which the peers
  // benchmark watches (bench/peers/PeersBench.h).
  std::vector<double> best_psi;
  double acceptance = 0.0;       // coldest replicas, all chains, since the start
  double swap_acceptance = 0.0;  // all neighbour pairs, since the start (NaN before any)
};

struct ParameterSummary {
  std::string name;
  double map = 0.0;  // at the maximum a posteriori hypothesis
  // Over the post-burn-in states of the coldest replicas, all chains pooled; mean and
  // quantiles then moved by interval_shift.
  double mean = 0.0, sd = 0.0, q025 = 0.0, q975 = 0.0;
  // How far mean and quantiles were moved after sampling, with a MAP polished beyond the
  // chains' likelihood (recon/FinerAtlasPolish.h); 0 when not. chain.csv keeps the draws as
  // sampled.
  double interval_shift = 0.0;
  double ess = 0.0;   // EffectiveSampleSize (Statistics.h)
  double rhat = 0.0;  // SplitRhat over the chains
  // sd of the Laplace approximation at the mode found by settling (NaN without it).
  double laplace_sd = 0.0;
  // The posterior sd to measure steps and moves in: the sample's, else the Laplace
  // approximation's; NaN when neither is a positive number.
  double PosteriorSd() const {
    if (std::isfinite(sd) && sd > 0.0) return sd;
    if (std::isfinite(laplace_sd) && laplace_sd > 0.0) return laplace_sd;
    return std::numeric_limits<double>::quiet_NaN();
  }
};

struct ChainSummary {
  double acceptance = 0.0;                      // coldest replica, all iterations
  std::vector<double> replica_acceptance;       // per temperature, coldest first
  std::vector<double> swap_acceptance;          // per neighbour pair (k, k+1)
  // Of the independence proposals (SamplerOptions::independence_share), all replicas; NaN: none.
  double independence_acceptance = 0.0;
};

struct SamplerSummary {
  Termination termination = Termination::Stopped;
  std::string message;  // why it failed or stopped; empty when completed

  std::vector<ParameterSummary> parameters;
  // The maximum a posteriori hypothesis (best untempered log posterior at level 0 over
  // sampling and refinement); empty when none had a finite one.
  std::vector<double> map;
  double map_log_prior = 0.0, map_log_likelihood = 0.0, map_log_posterior = 0.0;
  double sampling_map_log_posterior = 0.0;  // before the refinement
  // The MAP is the local search's mode, which scored higher than the chains' (AdoptIfHigher,
  // Polish.h); the per-parameter summaries other than "map" are still the chains'.
  bool map_from_search = false;
  std::vector<ChainSummary> chains;
  // How many chains the posterior draws pool: `chains`, or chains × temperatures once every
  // replica sampled at T = 1 (SamplerOptions::cool_after_settling); Sample::chain counts them.
  int posterior_chains = 0;
  nlohmann::json calibration;  // the target's, from settling (null: none)
  std::vector<Sample> chain;  // every iteration of every chain's coldest replica

  int iterations = 0;  // sampling iterations done
  int burn_in = 0;
  // What ended the sampling: "iterations" (the fixed count), "converged" (R̂ and ESS met
  // their targets, at a check or when a time limit ended it), "max_iterations", "time_limit"
  // (FrameRequest::finish_sampling before they met them); empty while it runs.
  std::string ended_by;
  double max_rhat = 0.0, min_ess = 0.0;  // Progress's, at the end of sampling
  int refine_steps = 0;
  int64_t frames = 0, evaluations = 0;
  // The log evidence from the evidence ladder (SamplerOptions::evidence_rungs); empty with
  // the ladder off or before it has recorded 4 iterations.
  std::optional<EvidenceEstimate> evidence;

  std::string BriefReport() const;  // one line
  std::string FullReport() const;   // a table per parameter and per chain
};

// map.json's sampler part (docs/reference/OUTPUTS.md, "map.json"): {"parameters": {NAME:
// {"map", "mean", "sd", "q025", "q975", "ess", "rhat"}}, "log_likelihood", "log_prior",
// "log_posterior", "chains": [{"acceptance", …}], "termination", …, "evidence"? (ToJson of
// Evidence.h, only with the evidence ladder)}; the caller adds "settings". Undefined numbers
// are null.
nlohmann::json MapJson(const SamplerSummary& summary);
// chain.csv: a header `iteration,chain,level,temperature,accepted,swapped,log_posterior,
// log_likelihood,log_prior,<names…>`, one row per Sample, classic locale, full precision.
void WriteChainCsv(std::ostream& out, const std::vector<Sample>& chain,
                   const std::vector<ParameterSpec>& parameters);

// One chain's posterior draws (its post-burn-in rows of summary.chain) in CmdStan's CSV
// format, so ArviZ (`az.from_cmdstan`), CmdStan's stansummary-style readers and pandas
// (`read_csv(comment="#")`) read them: `#` comment lines with the run's configuration
// (`key = value`: num_samples, num_warmup = 0, thin, chain_id = chain + 1, seed), one
// header `lp__,accept_stat__,<names…>`, one row per draw. lp__ is the log posterior the
// chain sampled (after the calibration's κ), accept_stat__ whether the draw's proposal was
// accepted (Metropolis has no acceptance probability to report instead).
void WriteStanCsv(std::ostream& out, const SamplerSummary& summary, const std::vector<ParameterSpec>& parameters,
                  int chain, uint64_t seed);

// Options valid, parameters valid, chains × temperatures ≤ target.max_batch(), levels ≥ 1.
bool ValidateProblem(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
                     const Target& target, std::string* why);

class Sampler {
 public:
  // A fresh run. Throws std::invalid_argument when ValidateProblem fails.
  Sampler(const SamplerOptions& options, std::vector<ParameterSpec> parameters, Target& target);
  // Continues the run captured by Checkpoint(); sets the target's level. Throws
  // std::invalid_argument for a malformed checkpoint or one whose batch or levels do not
  // fit `target`.
  Sampler(const nlohmann::json& checkpoint, Target& target);
  ~Sampler();
  Sampler(const Sampler&) = delete;
  Sampler& operator=(const Sampler&) = delete;

  bool done() const;
  // One frame (see above). Throws std::logic_error when done().
  Progress Step();
  Progress progress() const;
  // Ends the sampling at the end of this iteration as FrameRequest::finish_sampling says;
  // whether it did (false before the burn-in ends or after sampling).
  bool FinishSampling();

  // The whole state as JSON, between frames.
  nlohmann::json Checkpoint() const;
  // Statistics of the chain so far; final once done().
  SamplerSummary Summary() const;

  const SamplerOptions& options() const;
  const std::vector<ParameterSpec>& parameters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What Run and Resume ask their caller after every frame.
struct FrameRequest {
  bool checkpoint = false;  // pass Checkpoint() to on_checkpoint now
  bool stop = false;        // stop after this frame (summary.termination = Stopped)
  // End the sampling now and go on to the refinement (a time limit): taken at the next
  // sampling frame, ignored before the burn-in ends (settling and exploration must finish)
  // and, with until_converged, before `iterations` are done.
  bool finish_sampling = false;
};
struct SamplerCallbacks {
  std::function<FrameRequest(const Progress&)> on_frame;
  std::function<void(const nlohmann::json&)> on_checkpoint;
};

// Runs to the end (or until a callback stops it) and fills `summary`. Returns true when
// completed. Invalid input is not thrown: summary->termination = Failed with a message.
bool Run(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
         Target& target, SamplerSummary* summary, const SamplerCallbacks& callbacks = {});
// The same from a checkpoint.
bool Resume(const nlohmann::json& checkpoint, Target& target, SamplerSummary* summary,
            const SamplerCallbacks& callbacks = {});
// Drives a sampler built by the caller (say from a checkpoint whose parameters() it first
// compared with the scene's) to the end.
bool Run(Sampler& sampler, SamplerSummary* summary, const SamplerCallbacks& callbacks = {});

}  // namespace vkr::opt
