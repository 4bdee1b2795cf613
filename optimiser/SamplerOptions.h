#pragma once
// How the sampler runs (docs/internals/SAMPLER.md): Metropolis–Hastings on
//   log p(Ψ) + log L(Ψ) / T
// with `chains` independent chains, each a ladder of `temperatures` replicas that exchange
// states (parallel tempering), annealed from a hot start to T = 1 (§7.2, Fig 7.17), run
// coarse-to-fine over the likelihood's pyramid levels (§7.3), with an adaptive proposal
// covariance once the target stops changing (Haario et al. 2001), and finished by a
// gradient refinement of the best hypothesis from finite differences.
//
// One frame evaluates every replica's proposal in one call of Target::Evaluate, so
// chains × temperatures must not exceed the target's batch.
//
// Schedule of one run of N = `iterations` iterations:
//   [0, coarse)   coarse levels, coarsest first, equal shares    coarse = ⌊coarse_fraction·N⌋
//   [0, anneal)   T of the coldest replica falls to 1             anneal = ⌊anneal_fraction·N⌋
//   at max(coarse, anneal), with `settle`: the best hypothesis is refined to the mode, the
//                 target calibrates its noise model there, and every replica restarts
//                 around the mode with the curvature's covariance as its proposal
//   [max(coarse, anneal), N)   adaptation collects its statistics
//   [burn_in, N)  the cold replicas' states are the posterior sample  burn_in = ⌊burn_in_fraction·N⌋
//   then up to `refine_steps` gradient steps at level 0, T = 1.

#include <cstdint>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace vkr::opt {

enum class AnnealSchedule {
  Geometric,  // log T falls linearly: T(t) = T0^(1 − t/anneal)
  Linear,     // T falls linearly: T(t) = T0 + (1 − T0) t/anneal
};
const char* ToString(AnnealSchedule schedule);
bool FromString(const std::string& text, AnnealSchedule* schedule);

// The most hypotheses one frame may take (`batch`): 4,096 already take minutes per frame on
// lavapipe and a second on a large GPU; more can never be a useful ladder, only a run that
// looks hung.
constexpr int kMaxSamplerBatch = 4096;
// time_limit's default with until_converged: a run a user starts at a desk ends within
// minutes on a CPU device (lavapipe), converged or not; the report and the diagnosis say which.
constexpr double kDefaultTimeLimit = 240.0;

// The scene file's "sampler" block reads into this (docs/guide/SCENE_FORMAT.md, "sampler"):
// the defaults here are a run's.
struct SamplerOptions {
  // Metropolis–Hastings iterations; every frame advances every replica of every chain by one.
  // With `until_converged` they only lay out the schedule above (exploration, settling,
  // burn-in), and sampling goes on past them until the chains have converged.
  int iterations = 600;
  // Convergence-driven length (Vehtari et al. 2021): once `iterations` are done, every
  // `convergence_interval` iterations the post-burn-in draws are checked, and sampling ends
  // when every parameter has rank-normalised split-R̂ ≤ target_rhat and bulk-ESS ≥
  // target_ess, or at max_iterations. A caller's time limit ends it too
  // (FrameRequest::finish_sampling). In JSON, `"iterations": "auto"` sets it, and a number
  // of iterations clears it unless the same object sets it.
  bool until_converged = true;
  // Seconds of sampling before the caller ends it where it is (0: none; below 0, "auto":
  // kDefaultTimeLimit with until_converged, none with a fixed count). Applied by the
  // sampler's caller through FrameRequest::finish_sampling; see TimeLimit().
  double time_limit = -1.0;
  // The most hypotheses one frame evaluates: the likelihood's batch. A JSON object that sets
  // it without `temperatures` gives each chain batch / chains replicas.
  int batch = 16;
  double target_rhat = 1.01;
  double target_ess = 400.0;
  int max_iterations = 200000;
  int convergence_interval = 50;
  // Independent chains. R̂ compares them, so use several (≥ 2) when the statistics matter.
  int chains = 4;

  // Replicas per chain at temperatures T·ratio^k, k = 0 … temperatures − 1, where T is
  // the annealing temperature; neighbours try to swap states every `swap_interval`
  // iterations (even pairs and odd pairs in turn). 1 turns replica exchange off.
  int temperatures = 4;
  double temperature_ratio = 2.0;  // > 1
  int swap_interval = 1;

  // Annealing: the coldest replica's temperature falls from `initial_temperature` to 1
  // over the first anneal_fraction · iterations. initial_temperature = 1 disables it.
  double initial_temperature = 10.0;
  double anneal_fraction = 0.4;
  AnnealSchedule anneal_schedule = AnnealSchedule::Geometric;

  // Fraction of the iterations left out of the posterior statistics. It must cover the
  // annealing and the coarse levels, whose states do not sample the posterior.
  double burn_in_fraction = 0.6;

  // Once the last settling round has restarted the replicas around the mode, every replica
  // samples at T = 1 as a chain of its own: tempering is for finding modes, and hot replicas
  // would otherwise spend three quarters of every frame on states that are not draws.
  // Replica exchange stops then; the posterior statistics pool the chains that sample on.
  bool cool_after_settling = true;
  // Of those chains × temperatures chains at T = 1, how many go on sampling (0: all). On
  // both devices measured a frame costs about its number of hypotheses (bench's batch sweep:
  // 16 cost 16 on lavapipe, 13 on an H200), and R̂ needs about 100 effective draws from each
  // chain however many there are, so 4 chains reach it in about a quarter of the evaluations
  // 16 take. Reads min(posterior_chains, chains × temperatures).
  int posterior_chains = 4;
  // After settling, this share of the proposals is drawn independently of the current state
  // from a multivariate t (ν = 8) around the mode, with the covariance the random walk uses
  // (the Laplace approximation blended with the adapted one, whose states are all posterior
  // chains' once cooled), and accepted by the Metropolis–Hastings ratio with the proposal's
  // densities. Where the posterior is near the Laplace approximation a draw is nearly
  // independent of the last; the random walk keeps the rest. 0: the random walk only.
  double independence_share = 0.8;

  // Random-walk proposal sd of each parameter as a fraction of its prior width (Width()),
  // times √T of the replica (a hot replica's target is wider), at most one width.
  double proposal_scale = 0.05;
  // Starting points: each replica starts at the parameters' initial values plus a normal
  // jitter of this fraction of the prior width (0: all at the initial values).
  double init_jitter = 0.0;

  // Adaptive Metropolis (Haario et al. 2001): once annealing and the coarse levels are over
  // and a replica has collected `adapt_min_samples` states, its proposal covariance becomes
  // 2.38²/d · (Σ + ε·diag(width²)), Σ the covariance of its states so far (once cooled, of
  // the states of every replica that samples, pooled: they sample one posterior).
  bool adapt = true;
  int adapt_min_samples = 100;  // ≥ 2
  double adapt_epsilon = 1e-6;  // ε, > 0: keeps the covariance positive definite

  // Coarse-to-fine (§7.3): use at most this many levels of the target (1: level 0 only),
  // spending coarse_fraction · iterations on the coarse ones, coarsest first. Coarse
  // iterations cost a quarter to a sixteenth of fine ones and find the basin the fine
  // likelihood's ridges hide (on `box` with 20 % the chains settled 7 000 nats below the
  // truth; with 40 % they found it).
  int coarse_levels = 3;
  double coarse_fraction = 0.4;

  // Settling, once the exploration (annealing, coarse levels) is over: the gradient
  // refinement takes the best hypothesis to the mode, the target recalibrates there
  // (Target::Calibrate), the log posterior's curvature is measured by finite differences,
  // and every replica restarts at mode + settle_spread · √T · N(0, Σ), Σ the inverse of
  // that curvature (a Laplace approximation), which is also its proposal covariance until
  // the adaptation has enough states. Photographs give posteriors 10⁻³–10⁻⁴ of the prior
  // wide: a random walk that has to find that scale by itself spends the run climbing,
  // and chains that climbed different ridges never meet. A spread above 1 starts the
  // chains overdispersed, as R̂ wants.
  // Later rounds, evenly spaced over the first half of the rest of the burn-in (the second
  // half tunes the proposal), start again from the best
  // hypothesis found since: the first mode is rarely converged on photographs (the chains
  // after it still climb tens of nats), and each round measures the curvature closer to it.
  bool settle = true;
  int settle_rounds = 2;
  int settle_steps = 50;  // gradient steps of each round's refinement (stops at refine_tolerance)
  double settle_spread = 1.5;

  // Gradient refinement after sampling: at most this many steps (0: none), each one batch
  // with the candidate and its ± central-difference neighbours (2d + 1 hypotheses), steps
  // preconditioned by the posterior covariance and improved by BFGS updates.
  int refine_steps = 20;
  double refine_difference = 1e-4;  // finite-difference step, fraction of the prior width
  double refine_tolerance = 1e-7;   // stop when no parameter moves by more width than this
  // Polish after the refinement: BOBYQA (MapSearch.h) at level 0 from the MAP,
  // first steps of two posterior sds, at most this many evaluations (0: none); the MAP moves
  // only where it scores higher. The finite-difference steps above stall a few hundredths of
  // a percent of the prior width from the mode on the photographs' rough likelihood, where a
  // model-based search still gains; one point per evaluation, so ~1 % of a run's work. Run
  // by the sampler's caller with PolishMap (Polish.h), after Run; not by the Sampler itself.
  int polish_evaluations = 80;
  // After the polish: at most this many evaluations of BOBYQA at twice the atlas's side (0:
  // no check), to see whether the MAP depends on the atlas's resolution (recon/
  // FinerAtlasPolish.h; the surface likelihood only). Each costs about four of the run's.
  // Run by the sampler's caller; not by the Sampler itself.
  int finer_atlas_polish = 60;
  // A local search before the sampler (docs/internals/SAMPLER.md, stage 1): BOBYQA
  // (MapSearch.h) coarse-to-fine over every level from the parameters' initial values, at
  // most this many full-resolution-equivalent evaluations (0: none), a few per cent of a run.
  // It stops at the first local mode it climbs, so it does not steer the sampler: its mode is
  // scored again after the run beside the sampler's MAP, each with the nuisances a
  // calibration at it would fit (Target::ScoreModes, a fair comparison: where the model is
  // wrong a higher posterior is not a better answer), and becomes the MAP (then polished)
  // only where it scores higher. An adopted mode keeps the chains' intervals; where it lies
  // outside them the diagnosis says so. Run by the sampler's caller with SearchStart and
  // AdoptIfHigher (Polish.h); not by the Sampler itself. Why on by default, and what it was
  // measured to do: docs/internals/DECISIONS.md, 2026-11-25 to 2026-11-27.
  double start_search = 100.0;

  // Log evidence (docs/internals/EVIDENCE.md): 0 turns it off. Otherwise one more ladder of
  // evidence_rungs + 1 replicas at β_k = (k/K)^(1/evidence_alpha), k = 0 … K = evidence_rungs,
  // from the prior (β = 0) to the posterior (β = 1), samples L^β·π with replica exchange
  // from the end of settling (or of the exploration) on, tunes its proposals until the
  // burn-in ends (at least 2·adapt_min_samples iterations), and records every rung's log L
  // after it; SamplerSummary::evidence gives stepping-stone and thermodynamic-integration
  // estimates with their errors. It has its own random stream: the chains sample exactly as
  // without it. It adds evidence_rungs + 1 hypotheses to every evidence_every-th frame once
  // it runs (a batch over the target's size is evaluated in two calls): at 12 rungs and every
  // second frame, about a quarter more evaluations. evidence_alpha = 0.3 is Xie et al. 2011's
  // Beta(0.3, 1) spacing, which crowds the rungs near the prior.
  int evidence_rungs = 0;
  double evidence_alpha = 0.3;
  // Frames per ladder step: its Monte Carlo error grows as √evidence_every, its cost falls as
  // 1 / evidence_every (why 2: docs/internals/DECISIONS.md, 2026-11-28).
  int evidence_every = 2;

  uint64_t seed = 1;

  // Whether every field is in range; otherwise `why` names the field and the problem.
  bool IsValid(std::string* why) const;

  // time_limit with "auto" resolved: seconds, 0 for none.
  double TimeLimit() const { return time_limit >= 0.0 ? time_limit : until_converged ? kDefaultTimeLimit : 0.0; }

  // Derived iteration counts (see the schedule above).
  int BurnIn() const;
  int AnnealIterations() const;
  int CoarseIterations() const;
};

// Every field by name; FromJson takes any subset of them (the others keep `options`'s
// values) and rejects unknown keys, wrong types and invalid results with a reason
// ("sampler.FIELD: …"). Words for enums; "auto" for iterations (until_converged) and for
// time_limit below 0, "none" for a time_limit of 0.
nlohmann::json ToJson(const SamplerOptions& options);
bool FromJson(const nlohmann::json& json, SamplerOptions* options, std::string* why);

}  // namespace vkr::opt
