// The proposals of a sampling frame (SamplerOptions: proposal_scale, adapt,
// independence_share): a random walk shaped by the adapted or the Laplace covariance, and,
// once settled, independence draws from a multivariate t around the mode.

#include <cmath>

#include "optimiser/SamplerState.h"

namespace vkr::opt::detail {
namespace {

// Degrees of freedom of the independence proposal: tails heavier than a Gaussian's, so that
// the ratio q(current)/q(proposal) stays moderate where the posterior's tails are heavier
// than its Laplace approximation's (tuning: docs/internals/DECISIONS.md).
constexpr int kDegreesOfFreedom = 8;
// The independence proposal's scale over the covariance it is given: a little wider than
// the posterior, for the same reason.
constexpr double kIndependenceScale = 1.1;

// The covariance the replica's states say the posterior at `temperature` has, and their
// centre: the adapted one, with the Laplace approximation counted as adapt_min_samples prior
// states once settled (it keeps the estimate positive definite at the posterior's own scale,
// where ε·width² would be 10–100× too wide for photographs); without settling, ε·width² on the
// diagonal. Empty when the replica has too few states and there is no Laplace approximation.
struct Shape {
  Eigen::MatrixXd covariance;
  Eigen::VectorXd centre;
};

// The states adaptation collected: the replica's own; once cooled, those of every replica
// that samples, pooled (Welford's statistics combined). They all sample one posterior then,
// and four chains' states outweigh the Laplace approximation, which can be twice the
// posterior's width, four times sooner (docs/internals/DECISIONS.md, "Once cooled…").
struct Adapted {
  int64_t count = 0;
  Eigen::VectorXd mean;
  Eigen::MatrixXd scatter;
};

Adapted AdaptedStates(const State& s, const Replica& r) {
  if (!s.Cooled()) return {r.adapt_count, r.adapt_mean, r.adapt_scatter};
  const int d = s.dimension();
  Adapted out{0, Eigen::VectorXd::Zero(d), Eigen::MatrixXd::Zero(d, d)};
  std::vector<const Replica*> pooled;
  for (int c = 0; c < s.options.chains; ++c)
    for (int k = 0; k < s.options.temperatures; ++k)
      if (s.Samples(c, k) && s.chains[size_t(c)].replicas[size_t(k)].adapt_count > 0)
        pooled.push_back(&s.chains[size_t(c)].replicas[size_t(k)]);
  for (const Replica* p : pooled) {
    out.count += p->adapt_count;
    out.mean += double(p->adapt_count) * p->adapt_mean;
  }
  if (out.count == 0) return out;
  out.mean /= double(out.count);
  for (const Replica* p : pooled) {
    const Eigen::VectorXd offset = p->adapt_mean - out.mean;
    out.scatter += p->adapt_scatter + double(p->adapt_count) * offset * offset.transpose();
  }
  return out;
}

Shape ReplicaShape(const State& s, const Replica& r, double temperature) {
  const int d = s.dimension();
  const bool settled = s.laplace.rows() == d;
  Shape out;
  const Adapted a = s.options.adapt ? AdaptedStates(s, r) : Adapted{};
  if (s.options.adapt && a.count >= s.options.adapt_min_samples) {
    out.covariance = a.scatter / double(a.count - 1);
    out.centre = a.mean;
    if (settled) {
      const double n0 = double(s.options.adapt_min_samples), n = double(a.count - 1);
      out.covariance = (n * out.covariance + n0 * temperature * s.laplace) / (n + n0);
      if (int(s.mode.size()) == d)
        out.centre = (n * a.mean + n0 * Eigen::Map<const Eigen::VectorXd>(s.mode.data(), d)) / (n + n0);
    } else {
      for (int i = 0; i < d; ++i) {
        const double w = s.parameters[size_t(i)].Width();
        out.covariance(i, i) += s.options.adapt_epsilon * w * w;
      }
    }
  } else if (settled) {
    out.covariance = temperature * s.laplace;
    if (int(s.mode.size()) == d) out.centre = Eigen::Map<const Eigen::VectorXd>(s.mode.data(), d);
  }
  return out;
}

std::vector<double> RandomWalk(const State& s, ChainState& chain, int k, double temperature) {
  const int d = s.dimension();
  const Replica& r = chain.replicas[size_t(k)];
  const bool settled = s.laplace.rows() == d;
  Eigen::VectorXd z(d);
  for (int i = 0; i < d; ++i) z[i] = chain.rng.Normal();
  Eigen::VectorXd step(d);
  bool shaped = false;
  // The replica's shape (adapted, or the Laplace approximation once settled) times 2.38²/d
  // (Haario et al. 2001); after settling the burn-in's tuning scales it too: a likelihood
  // that is rough below its curvature's scale wants smaller steps.
  if (const Shape shape = ReplicaShape(s, r, temperature); shape.covariance.size()) {
    Eigen::MatrixXd cov = shape.covariance * (2.38 * 2.38 / double(d));
    if (settled) cov *= std::exp(2.0 * r.log_scale);
    const Eigen::LLT<Eigen::MatrixXd> llt(cov);
    if (llt.info() == Eigen::Success) {
      step = llt.matrixL() * z;
      shaped = true;
    }
  }
  if (!shaped) {
    const double f = std::min(s.options.proposal_scale * std::sqrt(temperature) * std::exp(r.log_scale), 1.0);
    for (int i = 0; i < d; ++i) step[i] = f * s.parameters[size_t(i)].Width() * z[i];
  }
  std::vector<double> psi = r.psi;
  for (int i = 0; i < d; ++i) psi[size_t(i)] += step[i];
  return psi;
}

// log q(x) of the multivariate t with centre μ and scale matrix L Lᵀ, up to a constant.
double LogT(const Eigen::LLT<Eigen::MatrixXd>& llt, const Eigen::VectorXd& centre, const std::vector<double>& x) {
  const Eigen::Index d = centre.size();
  const Eigen::VectorXd u = llt.matrixL().solve(Eigen::Map<const Eigen::VectorXd>(x.data(), d) - centre);
  return -0.5 * double(kDegreesOfFreedom + d) * std::log1p(u.squaredNorm() / kDegreesOfFreedom);
}

// An independence draw; nullopt where there is no shape to draw from.
std::optional<Proposal> Independent(const State& s, ChainState& chain, int k, double temperature) {
  const Shape shape = ReplicaShape(s, chain.replicas[size_t(k)], temperature);
  if (shape.covariance.size() == 0 || shape.centre.size() != s.dimension()) return std::nullopt;
  return IndependenceDraw(shape.centre, shape.covariance, chain.replicas[size_t(k)].psi, chain.rng);
}

}  // namespace

std::optional<Proposal> IndependenceDraw(const Eigen::VectorXd& centre, const Eigen::MatrixXd& covariance,
                                         const std::vector<double>& current, Rng& rng) {
  const Eigen::Index d = centre.size();
  const Eigen::LLT<Eigen::MatrixXd> llt(kIndependenceScale * kIndependenceScale * covariance);
  if (llt.info() != Eigen::Success) return std::nullopt;
  Eigen::VectorXd z(d);
  for (Eigen::Index i = 0; i < d; ++i) z[i] = rng.Normal();
  double chi2 = 0.0;
  for (int i = 0; i < kDegreesOfFreedom; ++i) chi2 += std::pow(rng.Normal(), 2);
  const Eigen::VectorXd y = centre + (llt.matrixL() * z) / std::sqrt(chi2 / kDegreesOfFreedom);
  Proposal p;
  p.psi.assign(y.data(), y.data() + d);
  p.independent = true;
  p.log_q_ratio = LogT(llt, centre, current) - LogT(llt, centre, p.psi);
  return p;
}

Proposal Propose(const State& s, ChainState& chain, int k, double temperature) {
  const bool settled = s.laplace.rows() == s.dimension() && int(s.mode.size()) == s.dimension();
  if (settled && s.options.independence_share > 0.0 && chain.rng.Uniform() < s.options.independence_share)
    if (std::optional<Proposal> p = Independent(s, chain, k, temperature)) return *std::move(p);
  Proposal p;
  p.psi = RandomWalk(s, chain, k, temperature);
  return p;
}

}  // namespace vkr::opt::detail
