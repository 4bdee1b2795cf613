// Gradient refinement (docs/internals/SAMPLER.md, stages 3 and 5): quasi-Newton ascent on the
// untempered log posterior at level 0 with central finite differences, mid-run to find the mode
// (settling) and at the end to polish the MAP. Each frame scores one candidate and its 2d
// neighbours ψ ± h_i e_i in one batch; a candidate that improves on the current point is accepted
// (and its gradient is already known), one that does not shortens the step. The first inverse
// Hessian is the posterior covariance of the sample (exact for a Gaussian posterior), then BFGS
// updates refine it.

#include <algorithm>
#include <cmath>

#include "optimiser/SamplerState.h"

namespace vkr::opt::detail {
namespace {

// Pooled covariance of the post-burn-in sample, regularised like the adaptive proposal;
// the initial proposal's diagonal when the sample is too small to estimate it.
Eigen::MatrixXd InitialInverseHessian(const State& s) {
  const int d = s.dimension();
  const auto draws = PosteriorDraws(s);
  std::vector<Eigen::VectorXd> points;
  for (size_t c = 0; c < draws[0].size(); ++c)
    for (size_t n = 0; n < draws[0][c].size(); ++n) {
      Eigen::VectorXd x(d);
      for (int i = 0; i < d; ++i) x[i] = draws[i][c][n];
      points.push_back(x);
    }
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(d, d);
  if (int(points.size()) > 2 * d) {
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(d);
    for (const auto& x : points) mean += x;
    mean /= double(points.size());
    for (const auto& x : points) h += (x - mean) * (x - mean).transpose();
    h /= double(points.size() - 1);
    for (int i = 0; i < d; ++i) {
      const double w = s.parameters[i].Width();
      h(i, i) += s.options.adapt_epsilon * w * w;
    }
    if (Eigen::LLT<Eigen::MatrixXd>(h).info() == Eigen::Success) return h;
    h.setZero();
  }
  // The scale the cold replicas' burn-in tuning arrived at (Replica::log_scale): during
  // settling there is no posterior sample yet, and the untuned proposal is often 100×
  // wider than the posterior, which would cost the quasi-Newton steps many halvings.
  double log_scale = 0.0;
  for (const ChainState& c : s.chains) log_scale += c.replicas[0].log_scale / double(s.chains.size());
  for (int i = 0; i < d; ++i) {
    const double sd = s.options.proposal_scale * std::exp(log_scale) * s.parameters[i].Width();
    h(i, i) = sd * sd;
  }
  return h;
}

// The quasi-Newton direction H g. Parameters held at a bound by a gradient pointing out of
// the support are fixed, and the others take the Newton step of the reduced problem,
// B_ff⁻¹ g_f with B = H⁻¹ (the Schur complement of H): H g itself would move the free
// parameters as if the fixed ones could follow, and the clamped step need not ascend.
Eigen::VectorXd Direction(const State& s, const RefineState& r) {
  const int d = s.dimension();
  const Eigen::Map<const Eigen::VectorXd> g(r.gradient.data(), d);
  std::vector<int> free;
  for (int i = 0; i < d; ++i) {
    const ParameterSpec& p = s.parameters[size_t(i)];
    const bool held = (r.psi[size_t(i)] <= p.Lower() && g[i] < 0.0) ||
                      (r.psi[size_t(i)] >= p.Upper() && g[i] > 0.0);
    if (!held) free.push_back(i);
  }
  if (int(free.size()) == d) return r.inverse_hessian * g;
  Eigen::VectorXd direction = Eigen::VectorXd::Zero(d);
  if (free.empty()) return direction;
  const Eigen::MatrixXd hessian = r.inverse_hessian.llt().solve(Eigen::MatrixXd::Identity(d, d));
  const int n = int(free.size());
  Eigen::MatrixXd reduced(n, n);
  Eigen::VectorXd g_free(n);
  for (int a = 0; a < n; ++a) {
    g_free[a] = g[free[size_t(a)]];
    for (int b = 0; b < n; ++b) reduced(a, b) = hessian(free[size_t(a)], free[size_t(b)]);
  }
  const Eigen::VectorXd step = reduced.llt().solve(g_free);
  for (int a = 0; a < n; ++a) direction[free[size_t(a)]] = step[a];
  return direction;
}

// The settling refinement hands over to the restart, the final one ends the run.
void FinishRefinement(State& s) {
  s.phase = s.phase == Phase::Settling ? Phase::Restarting : Phase::Done;
}

}  // namespace

void StartRefinement(State& s) {
  s.refine = RefineState{};
  // A later settling round starts from the curvature the last one measured at the mode: the
  // proposal's scale (reset at the restart) is tens of times wider than the posterior, and
  // almost every step it proposed was shortened four to ten times before one was accepted.
  const bool settling_again = s.phase != Phase::Refining && s.settle_rounds > 0 &&
                              s.laplace.rows() == s.dimension();
  s.refine.inverse_hessian = settling_again ? s.laplace : InitialInverseHessian(s);
  s.refine.candidate = s.best.psi;
}

void RefineFrame(State& s, const BatchEvaluator& evaluate) {
  RefineState& r = s.refine;
  const int d = s.dimension();
  const std::vector<double> centre = r.candidate;

  // The candidate and its neighbours, clamped into the support (a one-sided difference at
  // a bound).
  std::vector<std::vector<double>> batch{centre};
  for (int i = 0; i < d; ++i) {
    const ParameterSpec& p = s.parameters[i];
    const double h = s.options.refine_difference * p.Width();
    for (const double sign : {1.0, -1.0}) {
      std::vector<double> x = centre;
      x[i] = p.Clamp(centre[i] + sign * h);
      batch.push_back(std::move(x));
    }
  }
  const std::vector<double> values = evaluate(batch);
  std::vector<double> f(batch.size()), lp(batch.size());
  for (size_t j = 0; j < batch.size(); ++j) {
    lp[j] = LogPrior(s.parameters, batch[j]);
    f[j] = lp[j] + values[j];
    if (!std::isfinite(f[j])) f[j] = -kInf;
    else s.ConsiderBest(batch[j], lp[j], values[j]);
  }

  ++r.step;
  if (f[0] > -kInf && (!r.have_point || f[0] > r.log_prior + r.log_likelihood)) {
    // Accept: the gradient at the centre from whichever differences are defined.
    std::vector<double> g(d, 0.0);
    for (int i = 0; i < d; ++i) {
      const size_t plus = size_t(1 + 2 * i), minus = plus + 1;
      const double xp = batch[plus][i], xm = batch[minus][i], xc = centre[i];
      if (f[plus] > -kInf && f[minus] > -kInf && xp != xm) g[i] = (f[plus] - f[minus]) / (xp - xm);
      else if (f[plus] > -kInf && xp != xc) g[i] = (f[plus] - f[0]) / (xp - xc);
      else if (f[minus] > -kInf && xm != xc) g[i] = (f[0] - f[minus]) / (xc - xm);
    }
    if (r.have_point) {
      // BFGS on −log posterior: s = Δψ, y = Δ(−g).
      const Eigen::Map<const Eigen::VectorXd> x_new(centre.data(), d), x_old(r.psi.data(), d);
      const Eigen::Map<const Eigen::VectorXd> g_new(g.data(), d), g_old(r.gradient.data(), d);
      const Eigen::VectorXd step = x_new - x_old;
      const Eigen::VectorXd y = g_old - g_new;
      const double sy = step.dot(y);
      if (sy > 1e-12 * step.norm() * y.norm()) {
        const double rho = 1.0 / sy;
        const Eigen::MatrixXd left =
            Eigen::MatrixXd::Identity(d, d) - rho * step * y.transpose();
        r.inverse_hessian =
            left * r.inverse_hessian * left.transpose() + rho * step * step.transpose();
      }
    }
    r.psi = centre;
    r.log_prior = lp[0];
    r.log_likelihood = values[0];
    r.gradient = std::move(g);
    r.have_point = true;
    r.step_scale = 1.0;
  } else {
    r.step_scale *= 0.25;
  }
  if (!r.have_point) {  // the starting point itself no longer scores: nothing to refine
    FinishRefinement(s);
    return;
  }

  // Next candidate: ψ + step_scale · H g, clamped into the support.
  const Eigen::VectorXd direction = Direction(s, r);
  double moved = 0.0;
  std::vector<double> next(d);
  for (int i = 0; i < d; ++i) {
    const ParameterSpec& p = s.parameters[i];
    next[i] = p.Clamp(r.psi[i] + r.step_scale * direction[i]);
    moved = std::max(moved, std::abs(next[i] - r.psi[i]) / p.Width());
  }
  r.candidate = std::move(next);
  const int steps = s.phase == Phase::Settling ? s.options.settle_steps : s.options.refine_steps;
  if (!(moved >= s.options.refine_tolerance) || r.step >= steps)
    FinishRefinement(s);
}

}  // namespace vkr::opt::detail
