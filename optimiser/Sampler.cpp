// The frames of the sampler: starting points, Metropolis–Hastings iterations with replica
// exchange and adaptation, level changes; and Run/Resume around them.

#include "optimiser/Sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "optimiser/SamplerState.h"

namespace vkr::opt {

const char* ToString(Phase phase) {
  switch (phase) {
    case Phase::Start: return "start";
    case Phase::Sampling: return "sampling";
    case Phase::Settling: return "settling";
    case Phase::Restarting: return "restarting";
    case Phase::Refining: return "refining";
    case Phase::Done: return "done";
  }
  return "?";
}

bool FromString(const std::string& text, Phase* phase) {
  for (Phase p : {Phase::Start, Phase::Sampling, Phase::Settling, Phase::Restarting, Phase::Refining,
                  Phase::Done})
    if (text == ToString(p)) {
      *phase = p;
      return true;
    }
  return false;
}

namespace detail {

int State::Levels() const { return std::max(1, std::min(options.coarse_levels, target_levels)); }

int State::ScheduledLevel(int t) const {
  const int coarse = options.CoarseIterations();
  const int levels = Levels();
  if (levels <= 1 || t >= coarse) return 0;
  // Equal shares of the coarse iterations, coarsest level first.
  return (levels - 1) - int(int64_t(t) * (levels - 1) / coarse);
}

double State::AnnealTemperature(int t) const {
  const int n = options.AnnealIterations();
  if (n == 0 || t >= n) return 1.0;
  const double f = double(t) / double(n);
  const double t0 = options.initial_temperature;
  if (options.anneal_schedule == AnnealSchedule::Linear) return t0 + (1.0 - t0) * f;
  return std::pow(t0, 1.0 - f);
}

double State::Temperature(int t, int replica) const {
  if (Cooled()) return 1.0;
  return AnnealTemperature(t) * std::pow(options.temperature_ratio, replica);
}

bool State::Cooled() const {
  return options.cool_after_settling && options.settle && settle_rounds >= options.settle_rounds;
}

int State::PosteriorChains() const {
  if (!Cooled()) return options.chains;
  const int all = options.chains * options.temperatures;
  return options.posterior_chains > 0 ? std::min(options.posterior_chains, all) : all;
}

int State::AdaptStart() const {
  return std::max(options.AnnealIterations(), options.CoarseIterations());
}

int State::NextSettleAt() const {
  if (!options.settle || settle_rounds >= options.settle_rounds) return -1;
  // Rounds evenly spaced over the first half of what lies between the end of the
  // exploration and the end of the burn-in; the second half tunes the proposal.
  const int start = AdaptStart(), end = options.BurnIn();
  const int at = start + int(int64_t(end - start) * settle_rounds / (2 * options.settle_rounds));
  return at < end ? at : -1;
}

bool State::SettlesAt(int t) const { return t >= 0 && t == NextSettleAt(); }

void State::ConsiderBest(const std::vector<double>& psi, double log_prior, double log_likelihood) {
  const double lp = log_prior + log_likelihood;
  if (!std::isfinite(lp) || (best.valid && !(lp > best.log_posterior()))) return;
  best.valid = true;
  best.level = level;
  best.psi = psi;
  best.log_prior = log_prior;
  best.log_likelihood = log_likelihood;
}

State InitialState(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
                   int target_levels) {
  State s;
  s.options = options;
  s.parameters = parameters;
  s.target_levels = target_levels;
  const int d = s.dimension();
  for (int c = 0; c < options.chains; ++c) {
    ChainState chain;
    chain.rng = Rng::ForStream(options.seed, uint64_t(c));
    for (int k = 0; k < options.temperatures; ++k) {
      Replica r;
      r.psi.resize(d);
      for (int i = 0; i < d; ++i) {
        const ParameterSpec& p = parameters[i];
        double x = p.Initial();
        if (options.init_jitter > 0.0)
          x = p.Clamp(x + options.init_jitter * p.Width() * chain.rng.Normal());
        r.psi[i] = x;
      }
      r.log_prior = LogPrior(parameters, r.psi);
      r.adapt_mean = Eigen::VectorXd::Zero(d);
      r.adapt_scatter = Eigen::MatrixXd::Zero(d, d);
      chain.replicas.push_back(std::move(r));
    }
    chain.swap_attempts.assign(std::max(0, options.temperatures - 1), 0);
    chain.swap_accepts.assign(std::max(0, options.temperatures - 1), 0);
    s.chains.push_back(std::move(chain));
  }
  return s;
}

}  // namespace detail

bool ValidateProblem(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
                     const Target& target, std::string* why) {
  if (!options.IsValid(why) || !IsValid(parameters, why)) return false;
  const int batch = options.chains * options.temperatures;
  if (target.max_batch() < batch) {
    if (why)
      *why = "chains × temperatures = " + std::to_string(batch) +
             " hypotheses per frame exceed the likelihood's batch of " +
             std::to_string(target.max_batch());
    return false;
  }
  if (target.levels() < 1) {
    if (why) *why = "the likelihood has no levels";
    return false;
  }
  return true;
}

namespace detail {

// The frames, on a State and a Target.
struct Engine {
  State s;
  Target& target;

  Engine(State state, Target& t) : s(std::move(state)), target(t) {}

  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) {
    std::vector<double> out;
    out.reserve(batch.size());
    const size_t k = size_t(target.max_batch());
    for (size_t begin = 0; begin < batch.size(); begin += k) {
      const size_t end = std::min(batch.size(), begin + k);
      std::vector<std::vector<double>> part(batch.begin() + begin, batch.begin() + end);
      const std::vector<double> values = target.Evaluate(part);
      if (values.size() != part.size())
        throw std::logic_error("Target::Evaluate returned " + std::to_string(values.size()) +
                               " values for " + std::to_string(part.size()) + " hypotheses");
      for (double v : values) out.push_back(std::isfinite(v) ? v : -kInf);
    }
    s.evaluations += int64_t(batch.size());
    return out;
  }

  std::vector<std::vector<double>> CurrentStates() const {
    std::vector<std::vector<double>> batch;
    for (const ChainState& c : s.chains)
      for (const Replica& r : c.replicas) batch.push_back(r.psi);
    return batch;
  }

  // Scores every replica's current state at the current level (the first frame, and the
  // frame after a level change). The best so far restarts: levels are not comparable.
  void EvaluateCurrentStates() {
    target.SetLevel(s.level);
    const std::vector<double> values = Evaluate(CurrentStates());
    s.best = Best{};
    size_t i = 0;
    for (ChainState& c : s.chains)
      for (Replica& r : c.replicas) {
        r.log_likelihood = values[i++];
        s.ConsiderBest(r.psi, r.log_prior, r.log_likelihood);
      }
  }

  void SamplingFrame() {
    const int t = s.iteration;
    if (const int level = s.ScheduledLevel(t); level != s.level) {
      s.level = level;
      EvaluateCurrentStates();
      return;
    }
    if (s.SettlesAt(t) && s.best.valid && s.best.level == 0) {
      // Exploration is over: find the mode (SamplerOptions::settle). This frame is the
      // refinement's first, or with no refinement steps the restart itself.
      StartRefinement(s);
      if (s.options.settle_steps > 0) {
        s.phase = Phase::Settling;
        RefineFrame(s, [this](const auto& batch) { return Evaluate(batch); });
      } else {
        RestartFrame(s, target, [this](const auto& batch) { return Evaluate(batch); });
      }
      return;
    }
    const int chains = s.options.chains, temps = s.options.temperatures, d = s.dimension();
    std::vector<double> temperature(temps);
    for (int k = 0; k < temps; ++k) temperature[k] = s.Temperature(t, k);

    // Proposals, one batch, from the replicas that sample (State::Samples): slot[c][k] is
    // replica k of chain c's place in it, −1 for none.
    std::vector<std::vector<int>> slot(size_t(chains), std::vector<int>(size_t(temps), -1));
    std::vector<Proposal> proposals;
    std::vector<std::vector<double>> batch;
    std::vector<double> proposal_prior;
    for (int c = 0; c < chains; ++c)
      for (int k = 0; k < temps; ++k) {
        if (!s.Samples(c, k)) continue;
        ChainState& chain = s.chains[size_t(c)];
        slot[size_t(c)][size_t(k)] = int(batch.size());
        proposals.push_back(Propose(s, chain, k, temperature[k]));
        proposal_prior.push_back(LogPrior(s.parameters, proposals.back().psi));
        // Outside the support: rejected unscored; the slot carries the current state.
        batch.push_back(std::isfinite(proposal_prior.back()) ? proposals.back().psi
                                                             : chain.replicas[k].psi);
      }
    const size_t sampled = batch.size();
    // The evidence ladder's hypotheses ride in the same batch (nothing when it is off).
    EvidenceProposal ladder;
    if (s.options.evidence_rungs > 0) ladder = EvidenceProposals(s, t, batch);
    const std::vector<double> values = Evaluate(batch);

    // Metropolis–Hastings on log p + log L / T.
    std::vector<char> accepted(sampled, 0), swapped(sampled, 0);
    for (int c = 0; c < chains; ++c) {
      ChainState& chain = s.chains[c];
      for (int k = 0; k < temps; ++k) {
        const int i = slot[size_t(c)][size_t(k)];
        if (i < 0) continue;
        Replica& r = chain.replicas[k];
        Proposal& proposal = proposals[size_t(i)];
        ++r.proposed;
        r.independent_proposed += proposal.independent;
        const double log_u = std::log(chain.rng.UniformOpen());
        const double lp = proposal_prior[size_t(i)], ll = values[size_t(i)];
        const bool scored = std::isfinite(lp) && std::isfinite(ll);
        const double current = r.log_prior + r.log_likelihood / temperature[k];
        const double proposed = lp + ll / temperature[k];
        const bool accept =
            scored && (current == -kInf || log_u < proposed - current + proposal.log_q_ratio);
        if (t < s.options.BurnIn() && !proposal.independent) {
          // Robbins–Monro towards 0.234 acceptance (Replica::log_scale), burn-in only. After a
          // settling restart the gain starts afresh (adapt_count counts the iterations since).
          const double n = s.laplace.rows() == d ? double(r.adapt_count + 1) : double(r.proposed);
          const double gain = 1.0 / std::sqrt(n);
          r.log_scale = std::clamp(r.log_scale + gain * ((accept ? 1.0 : 0.0) - 0.234), -12.0, 3.0);
        }
        if (!scored) continue;
        s.ConsiderBest(proposal.psi, lp, ll);
        if (accept) {
          r.psi = std::move(proposal.psi);
          r.log_prior = lp;
          r.log_likelihood = ll;
          ++r.accepted;
          r.independent_accepted += proposal.independent;
          accepted[size_t(i)] = 1;
        }
      }
      // Replica exchange between neighbours, even and odd pairs in turn (only before cooling,
      // when every replica samples). The prior is not tempered, so only the likelihoods enter
      // the ratio.
      if (temps > 1 && !s.Cooled() && t % s.options.swap_interval == 0) {
        for (int k = (t / s.options.swap_interval) % 2; k + 1 < temps; k += 2) {
          Replica& cold = chain.replicas[k];
          Replica& hot = chain.replicas[k + 1];
          ++chain.swap_attempts[k];
          const double log_u = std::log(chain.rng.UniformOpen());
          const double log_alpha = (1.0 / temperature[k] - 1.0 / temperature[k + 1]) *
                                   (hot.log_likelihood - cold.log_likelihood);
          if (!(log_u < log_alpha)) continue;  // NaN (both −∞) rejects too
          std::swap(cold.psi, hot.psi);
          std::swap(cold.log_prior, hot.log_prior);
          std::swap(cold.log_likelihood, hot.log_likelihood);
          ++chain.swap_accepts[k];
          swapped[size_t(slot[size_t(c)][size_t(k)])] = swapped[size_t(slot[size_t(c)][size_t(k + 1)])] = 1;
        }
      }
    }

    if (!ladder.psi.empty()) EvidenceStep(s, t, std::move(ladder), values.data() + sampled);

    // Adaptation statistics (Welford), once the target distribution stopped moving.
    if (s.options.adapt && t >= s.AdaptStart())
      for (int c = 0; c < chains; ++c)
        for (int k = 0; k < temps; ++k) {
          if (slot[size_t(c)][size_t(k)] < 0) continue;
          Replica& r = s.chains[size_t(c)].replicas[size_t(k)];
          const Eigen::Map<const Eigen::VectorXd> x(r.psi.data(), d);
          ++r.adapt_count;
          const Eigen::VectorXd delta = x - r.adapt_mean;
          r.adapt_mean += delta / double(r.adapt_count);
          r.adapt_scatter += delta * (x - r.adapt_mean).transpose();
        }

    // The coldest replica of every chain; once cooled, every replica that samples, as chain
    // k·chains + c.
    for (int k = 0; k < (s.Cooled() ? temps : 1); ++k)
      for (int c = 0; c < chains; ++c) {
        const int i = slot[size_t(c)][size_t(k)];
        if (i < 0) continue;
        const Replica& r = s.chains[c].replicas[k];
        Sample row;
        row.iteration = t;
        row.chain = k * chains + c;
        row.level = s.level;
        row.temperature = temperature[k];
        row.accepted = accepted[size_t(i)];
        row.swapped = swapped[size_t(i)];
        row.log_prior = r.log_prior;
        row.log_likelihood = r.log_likelihood;
        row.psi = r.psi;
        s.samples.push_back(std::move(row));
      }

    ++s.iteration;
    // Convergence is measured for the progress line with either length; with
    // until_converged it also decides the length.
    const int interval = s.options.convergence_interval;
    const bool check = s.iteration > s.options.BurnIn() && (s.iteration - s.options.BurnIn()) % interval == 0;
    if (check) MeasureConvergence(s);
    if (!s.options.until_converged) {
      if (s.iteration == s.options.iterations) EndSampling("iterations");
    } else if (s.iteration >= s.options.iterations) {
      if (check && TargetsMet())
        EndSampling("converged");
      else if (s.iteration >= s.options.max_iterations)
        EndSampling("max_iterations");
    }
  }

  // Whether the last convergence measurement meets R̂ and ESS targets.
  bool TargetsMet() const {
    return s.max_rhat <= s.options.target_rhat && s.min_ess >= s.options.target_ess;
  }

  void EndSampling(const char* why) {
    MeasureConvergence(s);
    s.ended_by = why;
    // Convergence is checked every convergence_interval iterations; draws that meet the
    // targets when the time limit falls between two checks have converged all the same.
    if (s.options.until_converged && s.ended_by == "time_limit" && TargetsMet()) s.ended_by = "converged";
    s.sampling_best = s.best.valid && s.best.level == 0 ? s.best.log_posterior() : -kInf;
    if (s.options.refine_steps > 0 && s.best.valid && s.best.level == 0) {
      s.phase = Phase::Refining;
      StartRefinement(s);
    } else {
      s.phase = Phase::Done;
    }
  }

  Progress MakeProgress() const {
    Progress p;
    p.phase = s.phase;
    p.frame = s.frame;
    p.evaluations = s.evaluations;
    p.iteration = s.iteration;
    p.iterations = s.options.iterations;
    p.until_converged = s.options.until_converged;
    p.max_rhat = s.max_rhat;
    p.min_ess = s.min_ess;
    p.refine_step = s.refine.step;
    p.level = s.level;
    p.temperature = s.AnnealTemperature(std::min(s.iteration, s.options.iterations - 1));
    if (s.phase == Phase::Refining || s.phase == Phase::Done) p.temperature = 1.0;
    p.best_log_posterior = s.best.log_posterior();
    if (s.best.valid) p.best_psi = s.best.psi;
    int64_t proposed = 0, accepted = 0, attempts = 0, swaps = 0;
    for (const ChainState& c : s.chains) {
      proposed += c.replicas[0].proposed;
      accepted += c.replicas[0].accepted;
      for (size_t k = 0; k < c.swap_attempts.size(); ++k) {
        attempts += c.swap_attempts[k];
        swaps += c.swap_accepts[k];
      }
    }
    p.acceptance = proposed ? double(accepted) / double(proposed) : 0.0;
    p.swap_acceptance = attempts ? double(swaps) / double(attempts) : kNaN;
    return p;
  }
};

}  // namespace detail

struct Sampler::Impl : detail::Engine {
  using Engine::Engine;
};

Sampler::Sampler(const SamplerOptions& options, std::vector<ParameterSpec> parameters,
                 Target& target) {
  std::string why;
  if (!ValidateProblem(options, parameters, target, &why)) throw std::invalid_argument(why);
  impl_ = std::make_unique<Impl>(detail::InitialState(options, parameters, target.levels()), target);
}

Sampler::Sampler(const nlohmann::json& checkpoint, Target& target) {
  detail::State state = detail::StateFromJson(checkpoint);
  std::string why;
  if (!ValidateProblem(state.options, state.parameters, target, &why))
    throw std::invalid_argument("checkpoint: " + why);
  if (target.levels() != state.target_levels)
    throw std::invalid_argument("checkpoint: the run had " + std::to_string(state.target_levels) +
                                " likelihood levels, this likelihood has " +
                                std::to_string(target.levels()));
  if (!state.calibration.is_null()) target.RestoreCalibration(state.calibration);
  impl_ = std::make_unique<Impl>(std::move(state), target);
  if (impl_->s.phase != Phase::Start) target.SetLevel(impl_->s.level);
}

Sampler::~Sampler() = default;

bool Sampler::done() const { return impl_->s.phase == Phase::Done; }

Progress Sampler::Step() {
  detail::State& s = impl_->s;
  switch (s.phase) {
    case Phase::Start:
      s.level = s.ScheduledLevel(0);
      impl_->EvaluateCurrentStates();
      s.phase = Phase::Sampling;
      break;
    case Phase::Sampling:
      impl_->SamplingFrame();
      break;
    case Phase::Settling:
    case Phase::Refining:
      detail::RefineFrame(s, [this](const auto& batch) { return impl_->Evaluate(batch); });
      break;
    case Phase::Restarting:
      detail::RestartFrame(s, impl_->target, [this](const auto& batch) { return impl_->Evaluate(batch); });
      break;
    case Phase::Done:
      throw std::logic_error("Sampler::Step after the run is done");
  }
  ++s.frame;
  return impl_->MakeProgress();
}

Progress Sampler::progress() const { return impl_->MakeProgress(); }

bool Sampler::FinishSampling() {
  detail::State& s = impl_->s;
  // A convergence-driven run does its schedule first: its exploration and burn-in are what
  // a fixed count of that length would do, whatever the machine's speed.
  if (s.phase != Phase::Sampling || s.iteration <= s.options.BurnIn()) return false;
  if (s.options.until_converged && s.iteration < s.options.iterations) return false;
  impl_->EndSampling("time_limit");
  return true;
}
nlohmann::json Sampler::Checkpoint() const { return detail::StateToJson(impl_->s); }
SamplerSummary Sampler::Summary() const { return detail::Summarise(impl_->s); }
const SamplerOptions& Sampler::options() const { return impl_->s.options; }
const std::vector<ParameterSpec>& Sampler::parameters() const { return impl_->s.parameters; }

namespace {

bool Drive(Sampler& sampler, SamplerSummary* summary, const SamplerCallbacks& callbacks) {
  bool stopped = false;
  while (!sampler.done() && !stopped) {
    const Progress progress = sampler.Step();
    if (!callbacks.on_frame) continue;
    const FrameRequest request = callbacks.on_frame(progress);
    if (request.finish_sampling) sampler.FinishSampling();
    if (request.checkpoint && callbacks.on_checkpoint) callbacks.on_checkpoint(sampler.Checkpoint());
    stopped = request.stop;
  }
  *summary = sampler.Summary();
  if (stopped && !sampler.done()) summary->message = "stopped by the caller; " + summary->message;
  return summary->termination == Termination::Completed;
}

bool FailRun(SamplerSummary* summary, const std::string& why) {
  *summary = SamplerSummary{};
  summary->termination = Termination::Failed;
  summary->message = why;
  return false;
}

}  // namespace

bool Run(const SamplerOptions& options, const std::vector<ParameterSpec>& parameters,
         Target& target, SamplerSummary* summary, const SamplerCallbacks& callbacks) {
  std::string why;
  if (!ValidateProblem(options, parameters, target, &why)) return FailRun(summary, why);
  Sampler sampler(options, parameters, target);
  return Drive(sampler, summary, callbacks);
}

bool Run(Sampler& sampler, SamplerSummary* summary, const SamplerCallbacks& callbacks) {
  return Drive(sampler, summary, callbacks);
}

bool Resume(const nlohmann::json& checkpoint, Target& target, SamplerSummary* summary,
            const SamplerCallbacks& callbacks) {
  std::unique_ptr<Sampler> sampler;
  try {
    sampler = std::make_unique<Sampler>(checkpoint, target);
  } catch (const std::invalid_argument& e) {
    return FailRun(summary, e.what());
  }
  return Drive(*sampler, summary, callbacks);
}

}  // namespace vkr::opt
