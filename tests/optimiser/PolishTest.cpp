// PolishMap (Polish.h): BOBYQA from the sampler's MAP takes it to the mode within its budget,
// never makes it worse, and adds what it spent to the summary.

#include <gtest/gtest.h>

#include <cmath>

#include "optimiser/Polish.h"
#include "tests/optimiser/Targets.h"

namespace vkr::opt::test {
namespace {

// A narrow posterior (sds 1e-3 of a prior width 2), mode at (0.2, −0.3), and a summary whose
// MAP stopped two sds short of it, as the finite-difference refinement leaves photographs'.
struct Narrow {
  std::vector<ParameterSpec> parameters = {Uniform("a", -1, 1), Uniform("b", -1, 1)};
  static double LogLikelihood(const std::vector<double>& x) {
    const double u = (x[0] - 0.2) / 1e-3, v = (x[1] + 0.3) / 1e-3;
    return -0.5 * (u * u + v * v + u * v);
  }
  SamplerSummary Summary() const {
    SamplerSummary s;
    s.map = {0.202, -0.298};
    s.map_log_prior = LogPrior(parameters, s.map);
    s.map_log_likelihood = LogLikelihood(s.map);
    s.map_log_posterior = s.map_log_prior + s.map_log_likelihood;
    for (const auto& p : parameters) {
      ParameterSummary q;
      q.name = p.name;
      q.sd = 1e-3;
      s.parameters.push_back(q);
    }
    s.parameters[0].map = s.map[0];
    s.parameters[1].map = s.map[1];
    s.evaluations = 1000;
    return s;
  }
};

TEST(Polish, TakesTheMapToTheModeAndCountsItsEvaluations) {
  const Narrow n;
  SamplerSummary s = n.Summary();
  const double before = s.map_log_posterior;
  RecordingTarget target([](const std::vector<double>& x, int) { return Narrow::LogLikelihood(x); }, 16, 1,
                         n.parameters);
  const PolishSummary p = PolishMap(n.parameters, target, 40, &s);
  EXPECT_TRUE(p.improved);
  EXPECT_LE(p.evaluations, 40);
  EXPECT_EQ(s.evaluations, 1000 + p.evaluations);
  EXPECT_EQ(int64_t(target.batch_sizes.size()), p.evaluations);
  EXPECT_NEAR(s.map[0], 0.2, 1e-5);
  EXPECT_NEAR(s.map[1], -0.3, 1e-5);
  EXPECT_DOUBLE_EQ(s.parameters[0].map, s.map[0]);
  EXPECT_DOUBLE_EQ(s.map_log_posterior, s.map_log_prior + s.map_log_likelihood);
  EXPECT_DOUBLE_EQ(p.improvement, s.map_log_posterior - before);
  EXPECT_GT(p.improvement, 0.0);
}

TEST(Polish, NeverMakesTheMapWorseAndZeroEvaluationsDoNothing) {
  const Narrow n;
  SamplerSummary s = n.Summary();
  s.map = {0.2, -0.3};  // already the mode
  s.map_log_likelihood = 0.0;
  s.map_log_posterior = s.map_log_prior;
  FunctionTarget target([](const std::vector<double>& x, int) { return Narrow::LogLikelihood(x); }, 1);
  const PolishSummary p = PolishMap(n.parameters, target, 30, &s);
  EXPECT_FALSE(p.improved);
  EXPECT_EQ(s.map, (std::vector<double>{0.2, -0.3}));
  SamplerSummary untouched = n.Summary();
  const PolishSummary none = PolishMap(n.parameters, target, 0, &untouched);
  EXPECT_EQ(none.evaluations, 0);
  EXPECT_EQ(untouched.evaluations, 1000);
  EXPECT_EQ(untouched.map, n.Summary().map);
}

}  // namespace
}  // namespace vkr::opt::test
