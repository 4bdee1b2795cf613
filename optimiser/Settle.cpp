// Settling (SamplerOptions::settle): the frame after the mid-run refinement has found the
// mode. The curvature of the log posterior there is measured by central finite
// differences, the target recalibrates its noise model at the mode given that curvature
// (and the curvature is measured again if it did, until κ settles), and every replica restarts
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

// Finite-difference step per parameter: about one posterior sd, as the refinement's
// inverse Hessian estimates it. Steps far below the sd measure rasterisation steps of
// the likelihood rather than its curvature; steps far above it leave the quadratic region.
std::vector<double> CurvatureSteps(const State& s) {
  const int d = s.dimension();
  std::vector<double> h(static_cast<size_t>(d), 0.0);
  for (int i = 0; i < d; ++i) {
    const double w = s.parameters[size_t(i)].Width();
    double sd = s.refine.inverse_hessian.rows() == d ? std::sqrt(std::max(s.refine.inverse_hessian(i, i), 0.0)) : 0.0;
    if (!std::isfinite(sd)) sd = 0.0;
    h[size_t(i)] = std::clamp(sd, 1e-5 * w, 0.02 * w);
  }
  return h;
}

// −∇² log p at `mode` from 1 + 2d + 2d(d − 1) points (evaluated in batches of the target's
// size). Empty when a needed point cannot be scored or lies outside the support.
Eigen::MatrixXd NegativeHessian(const State& s, const std::vector<double>& mode, const BatchEvaluator& evaluate,
                                double* mode_log_likelihood) {
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
  *mode_log_likelihood = values[0];
  std::vector<double> f(batch.size());
  for (size_t k = 0; k < batch.size(); ++k) {
    f[k] = LogPrior(s.parameters, batch[k]) + values[k];
    if (!std::isfinite(f[k])) return {};
  }
  Eigen::MatrixXd a(d, d);
  for (int i = 0; i < d; ++i) {
    const size_t plus = size_t(1 + 2 * i);
    a(i, i) = -(f[plus] - 2.0 * f[0] + f[plus + 1]) / (h[size_t(i)] * h[size_t(i)]);
  }
  size_t k = size_t(1 + 2 * d);
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j, k += 4) {
      // f(+i+j) − f(+i−j) − f(−i+j) + f(−i−j) over 4 h_i h_j.
      const double second = (f[k] - f[k + 1] - f[k + 2] + f[k + 3]) / (4.0 * h[size_t(i)] * h[size_t(j)]);
      a(i, j) = a(j, i) = -second;
    }
  return a;
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
  const std::vector<double> mode = s.refine.have_point ? s.refine.psi : s.best.psi;
  double mode_log_likelihood = -kInf;
  Eigen::MatrixXd inverse_curvature;
  const auto measure = [&] {
    const Eigen::MatrixXd curvature = NegativeHessian(s, mode, evaluate, &mode_log_likelihood);
    inverse_curvature = curvature.size() ? InverseCurvature(s, curvature) : Eigen::MatrixXd();
    if (inverse_curvature.size() == 0) inverse_curvature = FallbackCovariance(s);
    s.laplace = inverse_curvature.size() ? LaplaceCovariance(s, inverse_curvature) : Eigen::MatrixXd();
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
    measure();  // the log posterior changed: measure it again
    if (!s.calibration.is_object() || !s.calibration.contains("kappa")) break;
    const double next = s.calibration.value("kappa", 1.0);
    const bool settled = std::abs(next - kappa) <= kKappaSettled * next;
    kappa = next;
    if (settled) break;
  }

  // Log-likelihoods before the calibration are not comparable with those after it.
  s.best = Best{};
  s.best.level = s.level;
  s.ConsiderBest(mode, LogPrior(s.parameters, mode), mode_log_likelihood);

  // Every replica restarts around the mode; without a covariance, at the mode itself.
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
  ++s.settle_rounds;
  s.phase = Phase::Sampling;
}

}  // namespace vkr::opt::detail
