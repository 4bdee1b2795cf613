// The sampler on analytic targets: posterior statistics of a correlated Gaussian, replica
// exchange across a barrier, determinism, the one-batch-per-frame contract, rejection of
// unscorable hypotheses, gradient refinement.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <sstream>

#include <nlohmann/json.hpp>

#include "optimiser/Sampler.h"
#include "optimiser/Statistics.h"
#include "tests/optimiser/Targets.h"

namespace vkr::opt::test {
namespace {

// x ~ N(μ, Σ), sds (1, 2), correlation 0.8, inside wide uniform priors.
struct CorrelatedGaussian {
  Eigen::Vector2d mu{1.0, -2.0};
  Eigen::Vector2d sd{1.0, 2.0};
  double rho = 0.8;
  Eigen::Matrix2d Covariance() const {
    Eigen::Matrix2d c;
    c << sd[0] * sd[0], rho * sd[0] * sd[1], rho * sd[0] * sd[1], sd[1] * sd[1];
    return c;
  }
  std::vector<ParameterSpec> Parameters() const {
    return {Uniform("a", -9.0, 11.0), Uniform("b", -22.0, 18.0)};
  }
};

TEST(Sampler, RecoversACorrelatedGaussianPosterior) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  FunctionTarget target([&](const std::vector<double>& x, int) { return log_density(x); }, 16);
  SamplerOptions o;
  o.iterations = 6000;
  o.until_converged = false;
  o.chains = 4;
  o.temperatures = 4;
  o.burn_in_fraction = 0.3;
  o.anneal_fraction = 0.1;
  o.init_jitter = 0.1;
  o.coarse_levels = 1;
  o.refine_steps = 0;
  o.seed = 3;
  SamplerSummary s;
  ASSERT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
  EXPECT_EQ(s.termination, Termination::Completed);
  EXPECT_EQ(s.burn_in, 1800);
  // Once settled, the replicas sample at T = 1 as chains of their own, 4 of them by default.
  ASSERT_EQ(s.posterior_chains, 4);
  size_t posterior_rows = 0;
  for (const Sample& row : s.chain) posterior_rows += row.iteration >= s.burn_in;
  ASSERT_EQ(posterior_rows, size_t((6000 - 1800) * 4));

  for (int i = 0; i < 2; ++i) {
    const ParameterSummary& p = s.parameters[size_t(i)];
    const double mu = g.mu[i], sd = g.sd[i];
    SCOPED_TRACE(p.name);
    EXPECT_GT(p.ess, 500.0);
    EXPECT_LT(p.rhat, 1.05);
    // Monte Carlo errors: mean sd/√ESS; sd about sd/√(2 ESS); a 2.5 % quantile about
    // √(p(1−p)/ESS)/φ(1.96) · sd ≈ 2.7 sd/√ESS. Four of each.
    const double root = std::sqrt(p.ess);
    EXPECT_NEAR(p.mean, mu, 4.0 * sd / root);
    EXPECT_NEAR(p.sd, sd, 4.0 * sd / std::sqrt(2.0 * p.ess));
    EXPECT_NEAR(p.q025, mu - 1.959964 * sd, 4.0 * 2.7 * sd / root);
    EXPECT_NEAR(p.q975, mu + 1.959964 * sd, 4.0 * 2.7 * sd / root);
    EXPECT_NEAR(p.map, mu, 0.5 * sd);
  }
  // The correlation too, from the pooled post-burn-in draws.
  double sab = 0, saa = 0, sbb = 0;
  for (const Sample& row : s.chain) {
    if (row.iteration < s.burn_in) continue;
    const double da = row.psi[0] - s.parameters[0].mean, db = row.psi[1] - s.parameters[1].mean;
    sab += da * db;
    saa += da * da;
    sbb += db * db;
  }
  EXPECT_NEAR(sab / std::sqrt(saa * sbb), g.rho, 0.05);
  for (const ChainSummary& c : s.chains) {
    EXPECT_GT(c.acceptance, 0.1);
    EXPECT_LT(c.acceptance, 0.9);
  }
  // Reports and outputs carry every parameter.
  EXPECT_NE(s.FullReport().find("rhat"), std::string::npos);
  const nlohmann::json map = MapJson(s);
  EXPECT_TRUE(map["parameters"].contains("a"));
  EXPECT_TRUE(map["parameters"]["b"].contains("q975"));
  EXPECT_EQ(map["chains"].size(), 4u);
  std::ostringstream csv;
  WriteChainCsv(csv, s.chain, g.Parameters());
  EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')),
            "iteration,chain,level,temperature,accepted,swapped,log_posterior,log_likelihood,"
            "log_prior,a,b");
}

// Two narrow modes 10 apart (barrier ≈ 139 nats); the one at +5 is e⁵ times heavier.
double TwoModes(const std::vector<double>& x) {
  const double low = -0.5 * std::pow((x[0] + 5.0) / 0.3, 2);
  const double high = 5.0 - 0.5 * std::pow((x[0] - 5.0) / 0.3, 2);
  const double m = std::max(low, high);
  return m + std::log(std::exp(low - m) + std::exp(high - m));
}

SamplerSummary RunTwoModes(int temperatures, double initial_temperature, uint64_t seed) {
  FunctionTarget target([](const std::vector<double>& x, int) { return TwoModes(x); }, 24);
  SamplerOptions o;
  o.iterations = 3000;
  o.until_converged = false;
  o.chains = 4;
  o.temperatures = temperatures;
  o.temperature_ratio = 3.0;  // up to T = 243: the barrier is < 1 nat there
  o.initial_temperature = initial_temperature;
  o.anneal_fraction = 0.2;
  o.burn_in_fraction = 0.4;
  o.coarse_levels = 1;
  o.refine_steps = 0;
  o.seed = seed;
  SamplerSummary s;
  EXPECT_TRUE(opt::Run(o, {Uniform("x", -10, 10, -5.0)}, target, &s)) << s.message;
  return s;
}

double FractionInHighMode(const SamplerSummary& s) {
  int n = 0, high = 0;
  for (const Sample& row : s.chain)
    if (row.iteration >= s.burn_in) {
      ++n;
      high += row.psi[0] > 0.0;
    }
  return double(high) / n;
}

SamplerOptions ConvergenceOptions() {
  SamplerOptions o;
  o.iterations = 400;  // the schedule only
  o.until_converged = true;
  o.chains = 4;
  o.temperatures = 2;
  o.burn_in_fraction = 0.3;
  o.anneal_fraction = 0.1;
  o.coarse_levels = 1;
  o.refine_steps = 0;
  o.seed = 9;
  return o;
}

// iterations "auto": sampling goes on until every R̂ ≤ 1.01 and bulk-ESS ≥ 400 (checked
// every convergence_interval iterations), and no longer; max_iterations and a caller's
// time limit end it too, and the summary says which.
// Once cooled, replica k of chain c samples as chain k·chains + c while that is below
// posterior_chains (0: every replica); the others stop, and a frame evaluates only those
// that sample.
TEST(Sampler, OnlyThePosteriorChainsSampleOnceCooled) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  for (const int asked : {6, 0, 40}) {
    SCOPED_TRACE(asked);
    const int expected = asked == 0 || asked > 16 ? 16 : asked;
    RecordingTarget target([&](const std::vector<double>& x, int) { return log_density(x); }, 16, 1,
                           g.Parameters());
    SamplerOptions o;
    o.iterations = 400;
    o.until_converged = false;
    o.chains = 4;
    o.temperatures = 4;
    o.posterior_chains = asked;
    o.coarse_levels = 1;
    o.refine_steps = 0;
    o.seed = 5;
    SamplerSummary s;
    ASSERT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
    EXPECT_EQ(s.posterior_chains, expected);
    std::vector<int> rows(16, 0);
    for (const Sample& row : s.chain)
      if (row.iteration >= s.burn_in) ++rows[size_t(row.chain)];
    for (int chain = 0; chain < 16; ++chain)
      EXPECT_EQ(rows[size_t(chain)], chain < expected ? 400 - s.burn_in : 0) << "chain " << chain;
    // The last frames of sampling evaluated one hypothesis per posterior chain.
    ASSERT_FALSE(target.batch_sizes.empty());
    EXPECT_EQ(target.batch_sizes.back(), expected);
  }
}

TEST(Sampler, UntilConvergedStopsWhenRhatAndEssMeetTheirTargets) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  FunctionTarget target([&](const std::vector<double>& x, int) { return log_density(x); }, 16);
  const SamplerOptions o = ConvergenceOptions();
  SamplerSummary s;
  ASSERT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
  EXPECT_EQ(s.ended_by, "converged");
  EXPECT_GT(s.iterations, o.iterations);  // 400 alone leave ESS < 400
  EXPECT_EQ((s.iterations - s.burn_in) % o.convergence_interval, 0);
  EXPECT_LE(s.max_rhat, 1.01);
  EXPECT_GE(s.min_ess, 400.0);
  for (const ParameterSummary& p : s.parameters) {
    EXPECT_LE(p.rhat, 1.01) << p.name;
    EXPECT_GE(p.ess, 400.0) << p.name;
  }
  EXPECT_EQ(MapJson(s)["sampling"]["ended_by"], "converged");

  // One check earlier the targets were not met (otherwise it would have stopped there).
  SamplerOptions shorter = o;
  shorter.until_converged = false;
  shorter.iterations = s.iterations - o.convergence_interval;
  SamplerSummary t;
  ASSERT_TRUE(opt::Run(shorter, g.Parameters(), target, &t)) << t.message;
  EXPECT_EQ(t.ended_by, "iterations");
  if (t.iterations > o.iterations) EXPECT_TRUE(t.max_rhat > 1.01 || t.min_ess < 400.0);

  SamplerOptions capped = o;
  capped.target_ess = 1e9;
  capped.max_iterations = 700;
  SamplerSummary m;
  ASSERT_TRUE(opt::Run(capped, g.Parameters(), target, &m)) << m.message;
  EXPECT_EQ(m.ended_by, "max_iterations");
  EXPECT_EQ(m.iterations, 700);

  // A time limit: the caller asks from iteration 10 on; it takes once the schedule's
  // iterations are done (with a fixed count: once the burn-in is over).
  SamplerOptions endless = o;
  endless.target_ess = 1e9;
  SamplerSummary l;
  SamplerCallbacks callbacks;
  callbacks.on_frame = [](const Progress& p) {
    FrameRequest r;
    r.finish_sampling = p.iteration >= 10;
    return r;
  };
  ASSERT_TRUE(opt::Run(endless, g.Parameters(), target, &l, callbacks)) << l.message;
  EXPECT_EQ(l.ended_by, "time_limit");
  EXPECT_EQ(l.iterations, o.iterations);
  // A time limit that falls between two checks after the draws have met the targets: they
  // have converged (here with the converged run's draws, checks too rare to see them).
  SamplerOptions rare = o;
  rare.convergence_interval = 100000;
  SamplerSummary c;
  callbacks.on_frame = [&](const Progress& p) {
    FrameRequest r;
    r.finish_sampling = p.iteration >= s.iterations;
    return r;
  };
  ASSERT_TRUE(opt::Run(rare, g.Parameters(), target, &c, callbacks)) << c.message;
  EXPECT_EQ(c.iterations, s.iterations);
  EXPECT_EQ(c.ended_by, "converged");
  EXPECT_EQ(c.max_rhat, s.max_rhat);
  callbacks.on_frame = [](const Progress& p) {
    FrameRequest r;
    r.finish_sampling = p.iteration >= 10;
    return r;
  };
  SamplerOptions fixed = o;
  fixed.until_converged = false;
  SamplerSummary f;
  ASSERT_TRUE(opt::Run(fixed, g.Parameters(), target, &f, callbacks)) << f.message;
  EXPECT_EQ(f.ended_by, "time_limit");
  EXPECT_EQ(f.iterations, f.burn_in + 1);
}

// chains/stan-K.csv read the way ArviZ's from_cmdstan reads CmdStan output: `#` lines are
// comments, some `key = value` configuration; the first other line names the columns, those
// ending in "__" being sample statistics; every further line is one draw of numbers.
TEST(Sampler, StanCsvIsReadAsCmdStanReadersReadIt) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  FunctionTarget target([&](const std::vector<double>& x, int) { return log_density(x); }, 16);
  SamplerOptions o = ConvergenceOptions();
  o.until_converged = false;
  SamplerSummary s;
  ASSERT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
  for (int chain = 0; chain < o.chains; ++chain) {
    SCOPED_TRACE(chain);
    std::ostringstream out;
    WriteStanCsv(out, s, g.Parameters(), chain, o.seed);
    std::istringstream in(out.str());
    std::map<std::string, std::string> config;
    std::vector<std::string> columns;
    std::vector<std::vector<double>> rows;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("#", 0) == 0) {
        const size_t eq = line.find(" = ");
        if (eq != std::string::npos) config[line.substr(2, eq - 2)] = line.substr(eq + 3);
        continue;
      }
      std::vector<std::string> cells;
      std::stringstream cells_in(line);
      for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
      if (columns.empty()) {
        columns = cells;
        continue;
      }
      ASSERT_EQ(cells.size(), columns.size());
      std::vector<double> row;
      for (const std::string& cell : cells) {
        size_t used = 0;
        row.push_back(std::stod(cell, &used));
        EXPECT_EQ(used, cell.size()) << cell;
      }
      rows.push_back(row);
    }
    ASSERT_EQ(columns, (std::vector<std::string>{"lp__", "accept_stat__", "a", "b"}));
    EXPECT_EQ(config["num_warmup"], "0");
    EXPECT_EQ(config["chain_id"], std::to_string(chain + 1));
    ASSERT_EQ(config["num_samples"], std::to_string(rows.size()));
    ASSERT_EQ(int(rows.size()), s.iterations - s.burn_in);
    // The draws are the chain's post-burn-in rows of the summary, exactly.
    size_t k = 0;
    for (const Sample& row : s.chain) {
      if (row.chain != chain || row.iteration < s.burn_in) continue;
      EXPECT_EQ(rows[k][0], row.log_posterior());
      EXPECT_EQ(rows[k][2], row.psi[0]);
      EXPECT_EQ(rows[k][3], row.psi[1]);
      ++k;
    }
  }
}

TEST(Sampler, ReplicaExchangeFindsTheHigherMode) {
  for (uint64_t seed : {1, 2}) {
    SCOPED_TRACE(seed);
    const SamplerSummary tempered = RunTwoModes(6, 50.0, seed);
    EXPECT_NEAR(tempered.map[0], 5.0, 0.1);
    EXPECT_GT(FractionInHighMode(tempered), 0.9);  // the posterior puts 99.3 % there
    for (const ChainSummary& c : tempered.chains) EXPECT_GT(c.swap_acceptance.back(), 0.05);

    // A lone random walk at T = 1 never crosses the barrier.
    const SamplerSummary plain = RunTwoModes(1, 1.0, seed);
    EXPECT_NEAR(plain.map[0], -5.0, 0.1);
    EXPECT_EQ(FractionInHighMode(plain), 0.0);
  }
}

SamplerSummary SmallRun(uint64_t seed) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  FunctionTarget target(
      [&](const std::vector<double>& x, int level) { return log_density(x) / (1 + level); }, 8, 3);
  SamplerOptions o;
  o.iterations = 400;
  o.until_converged = false;
  o.chains = 2;
  o.temperatures = 3;
  o.init_jitter = 0.05;
  o.adapt_min_samples = 20;
  o.refine_steps = 5;
  o.seed = seed;
  SamplerSummary s;
  EXPECT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
  return s;
}

TEST(Sampler, SameSeedSameChainOtherSeedOtherChain) {
  const SamplerSummary a = SmallRun(7), b = SmallRun(7), c = SmallRun(8);
  EXPECT_TRUE(SameChain(a.chain, b.chain));
  EXPECT_EQ(MapJson(a).dump(), MapJson(b).dump());
  EXPECT_FALSE(SameChain(a.chain, c.chain));
  EXPECT_NE(a.map, c.map);
}

TEST(Sampler, EveryFrameIsOneBatchOfAtMostK) {
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  // Narrow priors and wide steps: many proposals fall outside the support; none may reach
  // the target (RecordingTarget checks).
  const std::vector<ParameterSpec> params = {Uniform("a", 0.0, 2.0), Uniform("b", -3.0, -1.0)};
  const int k = 8;
  RecordingTarget target(
      [&](const std::vector<double>& x, int level) { return log_density(x) / (1 + level); }, k, 3,
      params);
  SamplerOptions o;
  o.iterations = 300;
  o.until_converged = false;
  o.chains = 2;
  o.temperatures = 4;  // 8 hypotheses per sampling frame
  o.proposal_scale = 0.5;
  o.refine_steps = 10;  // 2·2 + 1 = 5 hypotheses per refinement frame
  o.settle = false;     // its frames are counted in SettleTest.cpp
  int64_t frames = 0;
  std::vector<int> sampling_frames;
  SamplerCallbacks callbacks;
  int last_iteration = 0;
  callbacks.on_frame = [&](const Progress& p) {
    ++frames;
    EXPECT_EQ(p.frame, frames);
    EXPECT_EQ(int64_t(target.batch_sizes.size()), frames) << "one call per frame";
    EXPECT_EQ(p.evaluations, std::accumulate(target.batch_sizes.begin(), target.batch_sizes.end(), int64_t(0)));
    EXPECT_GE(p.iteration, last_iteration);
    EXPECT_LE(p.iteration - last_iteration, 1);
    last_iteration = p.iteration;
    EXPECT_EQ(p.iterations, 300);
    EXPECT_TRUE(std::isfinite(p.best_log_posterior));
    EXPECT_GE(p.acceptance, 0.0);
    EXPECT_LE(p.acceptance, 1.0);
    EXPECT_GE(p.temperature, 1.0);
    return FrameRequest{};
  };
  SamplerSummary s;
  ASSERT_TRUE(opt::Run(o, params, target, &s, callbacks)) << s.message;
  EXPECT_EQ(s.frames, frames);
  // Start + 300 iterations + 2 level changes (levels 2 → 1 → 0) + refinement.
  EXPECT_EQ(frames, 1 + 300 + 2 + s.refine_steps);
  EXPECT_EQ(target.level_history, (std::vector<int>{2, 1, 0}));
  int64_t total = 0;
  for (size_t i = 0; i < target.batch_sizes.size(); ++i) {
    total += target.batch_sizes[i];
    if (i < size_t(1 + 300 + 2)) EXPECT_EQ(target.batch_sizes[i], 8);
    else EXPECT_EQ(target.batch_sizes[i], 5);
  }
  EXPECT_EQ(s.evaluations, total);
  // Out-of-support proposals count as rejections.
  EXPECT_LT(s.chains[0].acceptance, 0.5);

  // A target smaller than one refinement batch: refinement frames split into calls of ≤ K.
  RecordingTarget small(
      [&](const std::vector<double>& x, int) { return log_density(x); }, 4, 1, params);
  o.chains = 2;
  o.temperatures = 2;
  ASSERT_TRUE(opt::Run(o, params, small, &s)) << s.message;
  for (int size : small.batch_sizes) EXPECT_LE(size, 4);
  EXPECT_EQ(int64_t(small.batch_sizes.size()), 1 + 300 + 2 * s.refine_steps);
}

TEST(Sampler, UnscorableHypothesesAreRejected) {
  // NaN for b > 0 and −∞ for a > 2: the chain must never stand there.
  const CorrelatedGaussian g;
  const Gaussian log_density(g.mu, g.Covariance());
  FunctionTarget target(
      [&](const std::vector<double>& x, int) {
        if (x[1] > 0.0) return std::numeric_limits<double>::quiet_NaN();
        if (x[0] > 2.0) return -std::numeric_limits<double>::infinity();
        return log_density(x);
      },
      4);
  SamplerOptions o;
  o.iterations = 1000;
  o.until_converged = false;
  o.chains = 2;
  o.temperatures = 2;
  o.coarse_levels = 1;
  SamplerSummary s;
  ASSERT_TRUE(opt::Run(o, g.Parameters(), target, &s)) << s.message;
  for (const Sample& row : s.chain) {
    EXPECT_LE(row.psi[1], 0.0);
    EXPECT_LE(row.psi[0], 2.0);
    EXPECT_TRUE(std::isfinite(row.log_posterior()));
  }
  EXPECT_LE(s.parameters[0].q975, 2.0);
}

TEST(Sampler, GradientRefinementReachesTheOptimumOfAQuadratic) {
  Eigen::Vector3d mu(0.3, -1.2, 2.0);
  Eigen::Matrix3d cov;
  cov << 0.25, 0.1, -0.05, 0.1, 0.5, 0.2, -0.05, 0.2, 1.0;
  const Gaussian log_density(mu, cov);
  const std::vector<ParameterSpec> params = {Uniform("x", -10, 10), Uniform("y", -10, 10),
                                             Uniform("z", -10, 10)};
  FunctionTarget target([&](const std::vector<double>& x, int) { return log_density(x); }, 8);
  SamplerOptions o;
  o.iterations = 400;
  o.until_converged = false;
  o.chains = 2;
  o.temperatures = 1;
  o.initial_temperature = 1.0;
  o.coarse_levels = 1;
  o.refine_steps = 0;
  o.settle = false;  // settling would find the optimum before the final refinement does
  SamplerSummary sampled, refined;
  ASSERT_TRUE(opt::Run(o, params, target, &sampled)) << sampled.message;
  o.refine_steps = 30;
  ASSERT_TRUE(opt::Run(o, params, target, &refined)) << refined.message;

  const auto distance = [&](const std::vector<double>& x) {
    return (Eigen::Map<const Eigen::Vector3d>(x.data()) - mu).cwiseAbs().maxCoeff();
  };
  EXPECT_GT(distance(sampled.map), 1e-3);  // sampling alone is not that precise
  EXPECT_LT(distance(refined.map), 1e-3);
  EXPECT_GT(refined.map_log_posterior, refined.sampling_map_log_posterior);
  EXPECT_EQ(refined.sampling_map_log_posterior, sampled.map_log_posterior);
  EXPECT_LE(refined.refine_steps, 30);
  EXPECT_GT(refined.refine_steps, 0);

  // With x's prior [−1, 0] the optimum sits on the bound x = 0, where y and z take their
  // conditional optimum μ_yz + Σ_yz,x / Σ_xx · (0 − μ_x).
  std::vector<ParameterSpec> bounded = params;
  bounded[0] = Uniform("x", -1, 0);
  SamplerSummary on_bound;
  ASSERT_TRUE(opt::Run(o, bounded, target, &on_bound)) << on_bound.message;
  EXPECT_EQ(on_bound.map[0], 0.0);
  EXPECT_NEAR(on_bound.map[1], -1.2 + 0.1 / 0.25 * -0.3, 1e-3);
  EXPECT_NEAR(on_bound.map[2], 2.0 + -0.05 / 0.25 * -0.3, 1e-3);
}

}  // namespace
}  // namespace vkr::opt::test
