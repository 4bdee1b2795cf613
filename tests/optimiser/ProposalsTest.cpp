// The proposals' shape once settled: the Laplace approximation blended with the states the
// adaptation collected; once cooled, every posterior chain's states pooled, so that a chain
// with few states of its own already proposes at the posterior's scale.

#include <gtest/gtest.h>

#include <cmath>

#include "optimiser/SamplerState.h"
#include "tests/optimiser/Targets.h"

namespace vkr::opt::test {
namespace {

constexpr int kDimension = 3;
const Eigen::Vector3d kMode{0.2, -0.1, 0.4};
const Eigen::Vector3d kSd{1e-4, 2e-4, 3e-4};  // the posterior's, as the states say

// Four chains of two replicas after the last settling round: replica 0 of every chain
// samples on (posterior_chains 4), replica 1 stops. The Laplace approximation is twice as
// wide as the posterior (as where its curvature was measured 2 % of the prior apart).
// Chain 0's sampling replica has no states yet; the other three have 1,000 each at the
// posterior's covariance; the stopped replicas hold states 100 times wider that must not
// count.
detail::State SettledState(int settle_rounds_done) {
  detail::State s;
  s.options.chains = 4;
  s.options.temperatures = 2;
  s.options.posterior_chains = 4;
  s.options.settle_rounds = 2;
  s.options.independence_share = 1.0;
  s.parameters = {Uniform("a", -1, 1), Uniform("b", -1, 1), Uniform("c", -1, 1)};
  s.settle_rounds = settle_rounds_done;
  const Eigen::Matrix3d posterior = kSd.cwiseAbs2().asDiagonal();
  s.laplace = 4.0 * posterior;
  s.mode.assign(kMode.data(), kMode.data() + kDimension);
  s.chains.resize(4);
  for (int c = 0; c < 4; ++c) {
    detail::ChainState& chain = s.chains[size_t(c)];
    chain.rng = Rng(uint64_t(11 + c));
    chain.replicas.resize(2);
    for (int k = 0; k < 2; ++k) {
      detail::Replica& r = chain.replicas[size_t(k)];
      r.psi = s.mode;
      const bool sampling = k == 0;
      r.adapt_count = sampling && c == 0 ? 0 : 1000;
      r.adapt_mean = kMode;
      r.adapt_scatter = double(r.adapt_count - 1) * (sampling ? 1.0 : 1e4) * posterior;
      if (r.adapt_count == 0) r.adapt_scatter.setZero();
    }
  }
  return s;
}

// The sd of chain 0's proposals along each parameter, over many draws.
Eigen::Vector3d ProposalSd(detail::State s) {
  constexpr int kDraws = 20000;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero(), squares = Eigen::Vector3d::Zero();
  for (int n = 0; n < kDraws; ++n) {
    const detail::Proposal p = detail::Propose(s, s.chains[0], 0, 1.0);
    EXPECT_TRUE(p.independent);
    const Eigen::Vector3d x = Eigen::Map<const Eigen::Vector3d>(p.psi.data());
    sum += x;
    squares += x.cwiseAbs2();
  }
  const Eigen::Vector3d mean = sum / kDraws;
  return (squares / kDraws - mean.cwiseAbs2()).cwiseSqrt();
}

TEST(Proposals, OnceCooledAChainProposesFromEveryPosteriorChainsStates) {
  // Independence draws: a t with ν = 8 (sd √(8/6) times its scale), 1.1 times the shape.
  const double t_sd = 1.1 * std::sqrt(8.0 / 6.0);
  // Cooled: 3,000 pooled states at the posterior's covariance, blended with the Laplace
  // approximation counted as 100 states: variance (2,999 + 4·100) / 3,099 of the posterior's.
  detail::State cooled = SettledState(2);
  ASSERT_TRUE(cooled.Cooled());
  const Eigen::Vector3d pooled = ProposalSd(cooled);
  const double blended = std::sqrt((2999.0 + 400.0) / 3099.0);
  for (int i = 0; i < kDimension; ++i) EXPECT_NEAR(pooled[i], t_sd * blended * kSd[i], 0.05 * t_sd * kSd[i]) << i;

  // Between the rounds every replica is its own: chain 0's has no states and proposes from
  // the Laplace approximation, twice as wide.
  detail::State between = SettledState(1);
  ASSERT_FALSE(between.Cooled());
  const Eigen::Vector3d own = ProposalSd(between);
  for (int i = 0; i < kDimension; ++i) EXPECT_NEAR(own[i], t_sd * 2.0 * kSd[i], 0.1 * t_sd * kSd[i]) << i;
}

}  // namespace
}  // namespace vkr::opt::test
