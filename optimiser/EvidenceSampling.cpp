// The evidence ladder's part of a sampling frame (SamplerOptions::evidence_rungs): one chain
// of replicas at fixed β from the prior to the posterior, Metropolis–Hastings on
// log π + β log L with replica exchange between neighbours, and its log L recorded after
// the burn-in for Evidence.h's estimators (docs/internals/EVIDENCE.md).

#include <algorithm>
#include <cmath>

#include "optimiser/SamplerState.h"

namespace vkr::opt::detail {
namespace {

// Its own stream, far from the chains' 0 … chains − 1: the chains draw exactly the numbers
// they draw without the ladder.
constexpr uint64_t kEvidenceStream = uint64_t(1) << 32;

// Variance of one parameter's prior over its support: what the β = 0 rung must cover.
double PriorVariance(const ParameterSpec& p) {
  const double lo = p.Lower(), hi = p.Upper();
  const double box = std::isfinite(lo) && std::isfinite(hi) ? (hi - lo) * (hi - lo) / 12.0 : kInf;
  return p.prior == PriorKind::Uniform ? box : std::min(p.b * p.b, box);
}

// The posterior covariance the chains know at the ladder's start: settling's Laplace
// approximation, else the coldest replica's adapted covariance, else the first proposal's.
Eigen::MatrixXd PosteriorGuess(const State& s) {
  const int d = s.dimension();
  if (s.laplace.rows() == d) return s.laplace;
  const Replica& cold = s.chains[0].replicas[0];
  if (cold.adapt_count > d + 1) {
    const Eigen::MatrixXd cov = cold.adapt_scatter / double(cold.adapt_count - 1);
    if (Eigen::LLT<Eigen::MatrixXd>(cov).info() == Eigen::Success) return cov;
  }
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(d, d);
  for (int i = 0; i < d; ++i) cov(i, i) = std::pow(s.options.proposal_scale * s.parameters[size_t(i)].Width(), 2);
  return cov;
}

// Where the chains say the posterior lies: settling's mode, else the coldest replica's
// adapted mean, else its state.
Eigen::VectorXd PosteriorCentre(const State& s) {
  const int d = s.dimension();
  if (int(s.mode.size()) == d) return Eigen::Map<const Eigen::VectorXd>(s.mode.data(), d);
  const Replica& cold = s.chains[0].replicas[0];
  if (cold.adapt_count > d + 1) return cold.adapt_mean;
  return Eigen::Map<const Eigen::VectorXd>(cold.psi.data(), d);
}

// The prior's centre: a uniform's middle, a normal's mean (inside its bounds).
double PriorCentre(const ParameterSpec& p) {
  if (p.prior == PriorKind::Uniform) return 0.5 * (p.Lower() + p.Upper());
  return std::clamp(p.a, p.Lower(), p.Upper());
}

// A power posterior's shape when L is Gaussian with the guess's covariance: the precisions
// add, β times the likelihood's and the prior's, and the centre is their weighted mean.
void GuessRungs(const State& s, EvidenceState& e) {
  const int d = s.dimension();
  const Eigen::MatrixXd precision = PosteriorGuess(s).inverse();
  const Eigen::VectorXd mode = PosteriorCentre(s);
  Eigen::VectorXd prior_precision(d), prior_centre(d);
  for (int i = 0; i < d; ++i) {
    prior_precision[i] = 1.0 / PriorVariance(s.parameters[size_t(i)]);
    prior_centre[i] = PriorCentre(s.parameters[size_t(i)]);
  }
  e.guess.clear();
  e.guess_centre.clear();
  for (double b : e.beta) {
    Eigen::MatrixXd m = b * precision;
    m.diagonal() += prior_precision;
    Eigen::MatrixXd cov = m.inverse();
    Eigen::VectorXd centre = cov * (b * precision * mode + prior_precision.cwiseProduct(prior_centre));
    if (!cov.allFinite() || !centre.allFinite() || Eigen::LLT<Eigen::MatrixXd>(cov).info() != Eigen::Success) {
      cov = prior_precision.cwiseInverse().cwiseMin(1e300).asDiagonal();
      centre = b > 0.0 ? mode : prior_centre;
    }
    e.guess.push_back(cov);
    e.guess_centre.push_back(centre);
  }
}

// An independent draw from the prior (normalised over its support), by rejection for a
// normal prior cut by bounds; false when 64 tries of one parameter all fall outside.
bool DrawFromPrior(const std::vector<ParameterSpec>& parameters, Rng& rng, std::vector<double>* psi) {
  for (size_t i = 0; i < parameters.size(); ++i) {
    const ParameterSpec& p = parameters[i];
    bool drawn = false;
    for (int attempt = 0; attempt < 64 && !drawn; ++attempt) {
      const double x = p.prior == PriorKind::Uniform ? p.Lower() + (p.Upper() - p.Lower()) * rng.Uniform()
                                                     : p.a + p.b * rng.Normal();
      if (p.Admissible(x)) {
        (*psi)[i] = x;
        drawn = true;
      }
    }
    if (!drawn) return false;
  }
  return true;
}

void StartLadder(State& s, int t) {
  EvidenceState& e = s.evidence;
  const int d = s.dimension();
  e.started = true;
  e.start = t;
  e.every = s.options.evidence_every;
  // Tuned for 2·adapt_min_samples iterations (not steps), recorded from a step on.
  const int tuned = std::max(s.options.BurnIn(), t + 2 * s.options.adapt_min_samples);
  e.collect_from = t + e.every * ((tuned - t + e.every - 1) / e.every);
  e.rng = Rng::ForStream(s.options.seed, kEvidenceStream);
  e.beta = EvidenceLadder(s.options.evidence_rungs, s.options.evidence_alpha);
  GuessRungs(s, e);
  const Replica& cold = s.chains[0].replicas[0];
  e.rungs.clear();
  for (size_t k = 0; k < e.beta.size(); ++k) {
    Replica r;
    r.psi = cold.psi;
    r.log_prior = cold.log_prior;
    r.log_likelihood = cold.log_likelihood;
    r.adapt_mean = Eigen::VectorXd::Zero(d);
    r.adapt_scatter = Eigen::MatrixXd::Zero(d, d);
    e.rungs.push_back(std::move(r));
  }
  e.swap_attempts.assign(e.beta.size() - 1, 0);
  e.swap_accepts.assign(e.beta.size() - 1, 0);
  e.draws.assign(e.beta.size(), {});
}

// log π + β log L; −∞ for an unscored state (and never 0 · ∞).
double Tempered(double log_prior, double log_likelihood, double beta) {
  if (!std::isfinite(log_prior) || !std::isfinite(log_likelihood)) return -kInf;
  return log_prior + beta * log_likelihood;
}

}  // namespace

EvidenceProposal EvidenceProposals(State& s, int t, std::vector<std::vector<double>>& batch) {
  EvidenceState& e = s.evidence;
  if (!e.started) {
    // After the exploration, at level 0, and after the last settling round: the target
    // calibrates there, and the ladder must sample the likelihood the chains end with.
    const int next_settle = s.NextSettleAt();
    if (t < s.AdaptStart() || s.level != 0 || next_settle >= t) return {};
    StartLadder(s, t);
  }
  if (!e.StepsAt(t)) return {};
  const int d = s.dimension();
  EvidenceProposal out;
  for (size_t k = 0; k < e.rungs.size(); ++k) {
    const Replica& r = e.rungs[k];
    Eigen::MatrixXd cov = e.guess[k];
    Eigen::VectorXd centre = e.guess_centre[k];
    if (r.adapt_count >= s.options.adapt_min_samples) {
      // As Sampler's adaptation: the first guess counts as adapt_min_samples prior states.
      const double n0 = double(s.options.adapt_min_samples), n = double(r.adapt_count - 1);
      cov = (r.adapt_scatter + n0 * e.guess[k]) / (n + n0);
      centre = (n * r.adapt_mean + n0 * e.guess_centre[k]) / (n + n0);
    }
    Eigen::LLT<Eigen::MatrixXd> llt(cov);
    if (llt.info() != Eigen::Success) {
      cov = e.guess[k];
      llt.compute(cov);
    }
    // As the chains (SamplerOptions::independence_share): mostly independence draws from a
    // t around the rung's centre, which for a near-Gaussian power posterior are nearly
    // independent of the last state; else the random walk.
    std::optional<Proposal> independent;
    if (e.beta[k] > 0.0 && e.rng.Uniform() < s.options.independence_share)
      independent = IndependenceDraw(centre, cov, r.psi, e.rng);
    std::vector<double> psi = r.psi;
    if (independent) {
      psi = independent->psi;
    } else {
      Eigen::VectorXd z(d);
      for (int i = 0; i < d; ++i) z[i] = e.rng.Normal();
      const Eigen::VectorXd lz = llt.matrixL() * z;
      const Eigen::VectorXd step = (2.38 / std::sqrt(double(d))) * std::exp(r.log_scale) * lz;
      for (int i = 0; i < d; ++i) psi[size_t(i)] += step[i];
    }
    // At β = 0 the target is the prior itself: an independent draw from it is always
    // accepted, and every iteration brings a fresh state to the bottom of the ladder, which
    // the swaps carry up (a random walk there would mix over the whole prior slowly, and
    // the error bars would not see it in a run's length).
    const bool from_prior = e.beta[k] == 0.0 && DrawFromPrior(s.parameters, e.rng, &psi);
    const double lp = LogPrior(s.parameters, psi);
    batch.push_back(std::isfinite(lp) ? psi : r.psi);
    out.psi.push_back(std::move(psi));
    out.log_prior.push_back(lp);
    out.from_prior.push_back(from_prior);
    out.independent.push_back(independent.has_value());
    out.log_q_ratio.push_back(independent ? independent->log_q_ratio : 0.0);
  }
  return out;
}

void EvidenceStep(State& s, int t, EvidenceProposal proposal, const double* values) {
  EvidenceState& e = s.evidence;
  const int d = s.dimension();
  const bool tuning = t < e.collect_from;
  for (size_t k = 0; k < e.rungs.size(); ++k) {
    Replica& r = e.rungs[k];
    ++r.proposed;
    const double log_u = std::log(e.rng.UniformOpen());
    const double lp = proposal.log_prior[k], ll = values[k];
    const bool scored = std::isfinite(lp) && std::isfinite(ll);
    const double current = Tempered(r.log_prior, r.log_likelihood, e.beta[k]);
    const bool accept = scored && (proposal.from_prior[k] || current == -kInf ||
                                   log_u < Tempered(lp, ll, e.beta[k]) - current + proposal.log_q_ratio[k]);
    if (tuning && !proposal.independent[k])  // Robbins–Monro towards 0.234, as the chains' replicas
      r.log_scale = std::clamp(r.log_scale + ((accept ? 1.0 : 0.0) - 0.234) / std::sqrt(double(r.proposed)),
                               -12.0, 3.0);
    if (accept) {
      r.psi = std::move(proposal.psi[k]);
      r.log_prior = lp;
      r.log_likelihood = ll;
      ++r.accepted;
    }
  }
  // Replica exchange, even and odd pairs in turn: swapping the states of β_k and β_k+1 has
  // log ratio (β_k+1 − β_k)(log L_k − log L_k+1); the prior cancels.
  for (size_t k = size_t(e.Step(t) % 2); k + 1 < e.rungs.size(); k += 2) {
    Replica& low = e.rungs[k];
    Replica& high = e.rungs[k + 1];
    ++e.swap_attempts[k];
    const double log_u = std::log(e.rng.UniformOpen());
    const double log_alpha = (e.beta[k + 1] - e.beta[k]) * (low.log_likelihood - high.log_likelihood);
    if (!(log_u < log_alpha)) continue;
    std::swap(low.psi, high.psi);
    std::swap(low.log_prior, high.log_prior);
    std::swap(low.log_likelihood, high.log_likelihood);
    ++e.swap_accepts[k];
  }
  for (size_t k = 0; k < e.rungs.size(); ++k) {
    Replica& r = e.rungs[k];
    if (tuning) {  // Welford, as the chains' adaptation; frozen once the draws count
      const Eigen::Map<const Eigen::VectorXd> x(r.psi.data(), d);
      ++r.adapt_count;
      const Eigen::VectorXd delta = x - r.adapt_mean;
      r.adapt_mean += delta / double(r.adapt_count);
      r.adapt_scatter += delta * (x - r.adapt_mean).transpose();
    } else {
      e.draws[k].push_back(r.log_likelihood);
    }
  }
}

std::optional<EvidenceEstimate> EstimateFromLadder(const State& s) {
  const EvidenceState& e = s.evidence;
  if (!e.started || e.draws.empty() || e.draws[0].size() < 4) return std::nullopt;
  EvidenceEstimate estimate = EstimateEvidence(e.beta, e.draws);
  for (size_t k = 0; k < e.swap_attempts.size(); ++k)
    estimate.swap_acceptance.push_back(e.swap_attempts[k] ? double(e.swap_accepts[k]) / double(e.swap_attempts[k]) : kNaN);
  for (const Replica& r : e.rungs)
    estimate.acceptance.push_back(r.proposed ? double(r.accepted) / double(r.proposed) : kNaN);
  return estimate;
}

}  // namespace vkr::opt::detail
