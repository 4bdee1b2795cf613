// Settling (SamplerOptions::settle): the frame after the mid-run refinement has found the
// mode. The curvature of the log posterior there is measured by central finite
// differences (climbing first where it is not a maximum's), the target recalibrates its
// noise model at the mode given that curvature (and the curvature is measured again if it
// did, until κ settles), and every replica restarts
// around the mode, drawn from the Laplace approximation N(mode, spread² · T · Σ) with
// Σ = (−∇² log p)⁻¹. Σ is also each replica's proposal covariance until the adaptation
// has collected enough states.

#include <algorithm>
#include <cmath>

#include "optimiser/SamplerState.h"

namespace vkr::opt::detail {
namespace {

// Calibrations at one mode until κ moves by less than this share (or kMaxCalibrations).
constexpr double kKappaSettled = 0.1;
constexpr int kMaxCalibrations = 4;
// Where the curvature measured at the refinement's end is not a maximum's: at most this many
// moves to a better point (of the stencil, or along its Newton step), each gaining at least
// a tenth of a nat of log posterior (less the chains would not notice).
constexpr int kMaxModeMoves = 4;
constexpr double kModeGain = 0.1;
constexpr double kMaxNewtonSteps = 4.0;  // stencil steps along any axis

// Finite-difference step per parameter: about one posterior sd, as the refinement's
// inverse Hessian estimates it. Steps far below the sd measure rasterisation steps of
// the likelihood rather than its curvature; steps far above it leave the quadratic region.
// In later rounds, whose calibration sets the κ the chains sample at, the largest step:
// there the likelihood's roughness at one posterior sd made κ fall below 1 and the chains
// stick (docs/internals/DECISIONS.md, "The settling refinement").
constexpr double kLargestCurvatureStep = 0.02;  // of the prior width
std::vector<double> CurvatureSteps(const State& s) {
  const int d = s.dimension();
  std::vector<double> h(static_cast<size_t>(d), 0.0);
  for (int i = 0; i < d; ++i) {
    const double w = s.parameters[size_t(i)].Width();
    if (s.settle_rounds > 0) {
      h[size_t(i)] = kLargestCurvatureStep * w;
      continue;
    }
    double sd = s.refine.inverse_hessian.rows() == d ? std::sqrt(std::max(s.refine.inverse_hessian(i, i), 0.0)) : 0.0;
    if (!std::isfinite(sd)) sd = 0.0;
    h[size_t(i)] = std::clamp(sd, 1e-5 * w, kLargestCurvatureStep * w);
  }
  return h;
}

// What the curvature's stencil around a point found: −∇² log p there (empty when a needed
// point cannot be scored or lies outside the support), the point's log-likelihood, and the
// stencil's best point where it scores higher than the centre.
struct Stencil {
  Eigen::MatrixXd curvature;
  Eigen::VectorXd gradient;  // of log p, central differences along the axes
  double centre_log_likelihood = -kInf;
  double gain = 0.0;  // best log posterior of the stencil minus the centre's (≥ 0)
  std::vector<double> best;
};

// −∇² log p at `mode` from 1 + 2d + 2d(d − 1) points (evaluated in batches of the target's
// size).
Stencil NegativeHessian(const State& s, const std::vector<double>& mode, const BatchEvaluator& evaluate) {
  const int d = s.dimension();
  const std::vector<double> h = CurvatureSteps(s);
  std::vector<std::vector<double>> batch{mode};
  auto shifted = [&](int i, double si, int j, double sj) {
    std::vector<double> x = mode;
    x[size_t(i)] += si * h[size_t(i)];
    if (j >= 0) x[size_t(j)] += sj * h[size_t(j)];
    return x;
  };
  for (int i = 0; i < d; ++i)
    for (const double si : {1.0, -1.0}) batch.push_back(shifted(i, si, -1, 0.0));
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j)
      for (const double si : {1.0, -1.0})
        for (const double sj : {1.0, -1.0}) batch.push_back(shifted(i, si, j, sj));
  const std::vector<double> values = evaluate(batch);
  Stencil out;
  out.centre_log_likelihood = values[0];
  std::vector<double> f(batch.size());
  for (size_t k = 0; k < batch.size(); ++k) {
    f[k] = LogPrior(s.parameters, batch[k]) + values[k];
    if (std::isfinite(f[k]) && f[k] - f[0] > out.gain) {
      out.gain = f[k] - f[0];
      out.best = batch[k];
    }
  }
  for (size_t k = 0; k < batch.size(); ++k)
    if (!std::isfinite(f[k])) return out;
  Eigen::MatrixXd a(d, d);
  out.gradient.resize(d);
  for (int i = 0; i < d; ++i) {
    const size_t plus = size_t(1 + 2 * i);
    a(i, i) = -(f[plus] - 2.0 * f[0] + f[plus + 1]) / (h[size_t(i)] * h[size_t(i)]);
    out.gradient[i] = (f[plus] - f[plus + 1]) / (2.0 * h[size_t(i)]);
  }
  size_t k = size_t(1 + 2 * d);
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j, k += 4) {
      // f(+i+j) − f(+i−j) − f(−i+j) + f(−i−j) over 4 h_i h_j.
      const double second = (f[k] - f[k + 1] - f[k + 2] + f[k + 3]) / (4.0 * h[size_t(i)] * h[size_t(j)]);
      a(i, j) = a(j, i) = -second;
    }
  out.curvature = a;
  return out;
}

// (−∇² log p)⁻¹, with the curvature made positive definite (a direction measured flat or
// convex gets the smallest positive curvature found, i.e. the widest sd). It is what the
// target calibrates with: a covariance exactly κ times the raw likelihood's, whatever κ is.
Eigen::MatrixXd InverseCurvature(const State& s, const Eigen::MatrixXd& curvature) {
  const int d = s.dimension();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(curvature);
  if (eigen.info() != Eigen::Success) return {};
  Eigen::VectorXd lambda = eigen.eigenvalues();
  const double largest = lambda.maxCoeff();
  if (!(largest > 0.0)) return {};
  double smallest_positive = largest;
  for (int i = 0; i < d; ++i)
    if (lambda[i] > 0.0) smallest_positive = std::min(smallest_positive, lambda[i]);
  for (int i = 0; i < d; ++i) lambda[i] = std::max(lambda[i], smallest_positive);
  const Eigen::MatrixXd& v = eigen.eigenvectors();
  const Eigen::MatrixXd cov = v * lambda.cwiseInverse().asDiagonal() * v.transpose();
  return 0.5 * (cov + cov.transpose());
}

// Whether −∇² log p is positive definite: the point is a maximum as far as the stencil can
// tell (an empty curvature is not).
bool AtAMaximum(const Eigen::MatrixXd& curvature) {
  if (curvature.size() == 0) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(curvature, Eigen::EigenvaluesOnly);
  return eigen.info() == Eigen::Success && eigen.eigenvalues().minCoeff() > 0.0;
}

// The best of a few points along the Newton step the stencil implies, ψ + t·Σ∇log p with
// the repaired inverse curvature Σ (t = ½, 1, 2; the step shortened to at most four
// stencil steps along any axis): the refinement's end can lie hundreds of nats below the
// mode (Merton, first round), and moving one stencil step at a time took 8 measurements
// per calibration there. gain = 0 when none scores above the centre.
struct NewtonStep {
  std::vector<double> psi;
  double gain = 0.0;
};
NewtonStep LineSearch(const State& s, const std::vector<double>& mode, const Stencil& stencil,
                      const BatchEvaluator& evaluate) {
  NewtonStep out;
  const int d = s.dimension();
  if (stencil.curvature.size() == 0) return out;
  const Eigen::MatrixXd sigma = InverseCurvature(s, stencil.curvature);
  if (sigma.size() == 0) return out;
  Eigen::VectorXd step = sigma * stencil.gradient;
  const std::vector<double> h = CurvatureSteps(s);
  double longest = 0.0;
  for (int i = 0; i < d; ++i) longest = std::max(longest, std::abs(step[i]) / h[size_t(i)]);
  if (!(longest > 0.0) || !std::isfinite(longest)) return out;
  if (longest > kMaxNewtonSteps) step *= kMaxNewtonSteps / longest;
  std::vector<std::vector<double>> batch;
  for (const double t : {0.5, 1.0, 2.0}) {
    std::vector<double> x = mode;
    for (int i = 0; i < d; ++i) x[size_t(i)] = s.parameters[size_t(i)].Clamp(mode[size_t(i)] + t * step[i]);
    batch.push_back(std::move(x));
  }
  const std::vector<double> values = evaluate(batch);
  const double centre = LogPrior(s.parameters, mode) + stencil.centre_log_likelihood;
  for (size_t k = 0; k < batch.size(); ++k) {
    const double f = LogPrior(s.parameters, batch[k]) + values[k];
    if (std::isfinite(f) && f - centre > out.gain) {
      out.gain = f - centre;
      out.psi = batch[k];
    }
  }
  return out;
}

// The inverse curvature with every sd capped at a quarter of the prior width, where the
// prior takes over: the covariance replicas restart from and propose with. The cap depends
// on κ, so the target never sees this one (a capped covariance fed back into the
// calibration moved κ 56 → 964 → 158 at one mode on the demo's house).
Eigen::MatrixXd LaplaceCovariance(const State& s, Eigen::MatrixXd cov) {
  const int d = s.dimension();
  for (int i = 0; i < d; ++i) {
    const double cap = 0.25 * s.parameters[size_t(i)].Width();
    const double sd = std::sqrt(cov(i, i));
    if (sd > cap) {
      const double f = cap / sd;
      cov.row(i) *= f;
      cov.col(i) *= f;
    }
  }
  return 0.5 * (cov + cov.transpose());
}

// Without a usable curvature: the refinement's inverse Hessian, or nothing.
Eigen::MatrixXd FallbackCovariance(const State& s) {
  const int d = s.dimension();
  if (s.refine.inverse_hessian.rows() != d) return {};
  if (Eigen::LLT<Eigen::MatrixXd>(s.refine.inverse_hessian).info() != Eigen::Success) return {};
  return s.refine.inverse_hessian;
}

}  // namespace

void RestartFrame(State& s, Target& target, const BatchEvaluator& evaluate) {
  const int d = s.dimension();
  std::vector<double> mode = s.refine.have_point ? s.refine.psi : s.best.psi;
  double mode_log_likelihood = -kInf;
  Eigen::MatrixXd inverse_curvature;
  int moves = 0;
  const int earlier_moves = s.calibration.is_object() ? s.calibration.value("mode_moves", 0) : 0;
  const auto measure = [&] {
    // The refinement may stop short of the mode, where the log posterior still rises along
    // some direction; a curvature measured there is not negative definite, and the repair
    // below gives that direction the flattest curvature found. On Merton's photographs it
    // stopped where a mix of corner, yaw and angle curved upward (eigenvalue −21,917 against
    // +225 … +215,111 in prior widths); the sandwich then saw a near-flat direction and κ
    // went 147 → 8,400 → 39,428, intervals as wide as the priors. So where the curvature is
    // not a maximum's, climb to the better of the stencil's best point and the Newton step's
    // and measure again. Where it is, nothing moves: runs that settle well are unchanged.
    Stencil stencil = NegativeHessian(s, mode, evaluate);
    bool moved = false;
    for (int move = 0; move < kMaxModeMoves && !AtAMaximum(stencil.curvature); ++move) {
      const NewtonStep newton = LineSearch(s, mode, stencil, evaluate);
      const double gain = std::max(stencil.gain, newton.gain);
      if (!(gain > kModeGain)) break;
      mode = newton.gain >= stencil.gain ? newton.psi : stencil.best;
      moved = true;
      ++moves;
      stencil = NegativeHessian(s, mode, evaluate);
    }
    mode_log_likelihood = stencil.centre_log_likelihood;
    const Eigen::MatrixXd& curvature = stencil.curvature;
    inverse_curvature = curvature.size() ? InverseCurvature(s, curvature) : Eigen::MatrixXd();
    if (inverse_curvature.size() == 0) inverse_curvature = FallbackCovariance(s);
    s.laplace = inverse_curvature.size() ? LaplaceCovariance(s, inverse_curvature) : Eigen::MatrixXd();
    return moved;
  };
  measure();
  // The target corrects the curvature it is given for the noise model it changes, which is
  // only approximate when σ moves far (σ 8 → 3.9 on the demo's house gave κ 2,476, then
  // 10.1 measured again under the new σ): calibrate again, with the curvature measured
  // under the last calibration, until κ settles.
  double kappa = 0.0;
  for (int round = 0; round < kMaxCalibrations; ++round) {
    std::vector<double> covariance;
    for (int i = 0; i < inverse_curvature.rows(); ++i)
      for (int k = 0; k < inverse_curvature.cols(); ++k) covariance.push_back(inverse_curvature(i, k));
    s.calibration = target.Calibrate(mode, covariance);
    if (s.calibration.is_null()) break;
    // The log posterior changed: measure it again; if the mode moved under the new
    // calibration, that calibration belongs to the old point: calibrate again while rounds
    // remain.
    const bool moved = measure();
    if (!s.calibration.is_object() || !s.calibration.contains("kappa")) break;
    const double next = s.calibration.value("kappa", 1.0);
    const bool settled = !moved && std::abs(next - kappa) <= kKappaSettled * next;
    kappa = next;
    if (settled) break;
  }

  // map.json says how far the settling had to climb, over all its rounds so far (0: every
  // refinement ended at a maximum).
  if (s.calibration.is_object()) s.calibration["mode_moves"] = earlier_moves + moves;

  // Log-likelihoods before the calibration are not comparable with those after it.
  s.best = Best{};
  s.best.level = s.level;
  s.ConsiderBest(mode, LogPrior(s.parameters, mode), mode_log_likelihood);

  // Every replica restarts around the mode; without a covariance, at the mode itself. After
  // the last round, at T = 1 (cool_after_settling).
  s.mode = mode;
  ++s.settle_rounds;
  Eigen::MatrixXd lower;
  if (s.laplace.size()) lower = Eigen::MatrixXd(Eigen::LLT<Eigen::MatrixXd>(s.laplace).matrixL());
  std::vector<std::vector<double>> starts;
  for (ChainState& chain : s.chains)
    for (int k = 0; k < int(chain.replicas.size()); ++k) {
      std::vector<double> psi = mode;
      if (lower.size()) {
        Eigen::VectorXd z(d);
        for (int i = 0; i < d; ++i) z[i] = chain.rng.Normal();
        const Eigen::VectorXd step =
            s.options.settle_spread * std::sqrt(s.Temperature(s.iteration, k)) * (lower * z);
        for (int i = 0; i < d; ++i) psi[size_t(i)] = s.parameters[size_t(i)].Clamp(mode[size_t(i)] + step[i]);
      }
      starts.push_back(std::move(psi));
    }
  const std::vector<double> values = evaluate(starts);
  size_t i = 0;
  for (ChainState& chain : s.chains)
    for (Replica& r : chain.replicas) {
      const double lp = LogPrior(s.parameters, starts[i]);
      if (std::isfinite(lp) && std::isfinite(values[i])) {
        r.psi = starts[i];
        r.log_prior = lp;
        r.log_likelihood = values[i];
      } else {  // the draw cannot be scored: start at the mode
        r.psi = mode;
        r.log_prior = LogPrior(s.parameters, mode);
        r.log_likelihood = mode_log_likelihood;
      }
      s.ConsiderBest(r.psi, r.log_prior, r.log_likelihood);
      // The Laplace covariance already has the posterior's scale, and the states adaptation
      // collected belong to the previous round's neighbourhood.
      r.log_scale = 0.0;
      r.adapt_count = 0;
      r.adapt_mean.setZero();
      r.adapt_scatter.setZero();
      ++i;
    }
  s.phase = Phase::Sampling;
}

}  // namespace vkr::opt::detail
