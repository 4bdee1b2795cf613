// PolishMap (Polish.h): BOBYQA from the sampler's MAP takes it to the mode within its budget,
// never makes it worse, and adds what it spent to the summary. SearchStart and AdoptIfHigher:
// the local search before sampling, and its mode against the chains' at the end.

#include <gtest/gtest.h>

#include <algorithm>
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

// Two modes: a lower one near the prior centre, where a local search from the centre ends,
// and a higher one the chains may find. Level 1 is the same function, smoothed a little.
double TwoModes(const std::vector<double>& x, int level) {
  const double near_centre = -0.5 * ((x[0] - 0.1) * (x[0] - 0.1) + (x[1] + 0.1) * (x[1] + 0.1)) / 0.01;
  const double far = 5.0 - 0.5 * ((x[0] - 0.8) * (x[0] - 0.8) + (x[1] - 0.8) * (x[1] - 0.8)) / 0.01;
  const double m = std::max(near_centre, far);
  const double value = m + std::log(std::exp(near_centre - m) + std::exp(far - m));
  return level == 0 ? value : 0.9 * value;
}

TEST(StartSearch, ClimbsCoarseToFineFromTheCentreWithinItsBudget) {
  const std::vector<ParameterSpec> parameters = {Uniform("a", -1, 1), Uniform("b", -1, 1)};
  RecordingTarget target(TwoModes, 16, 2, parameters);
  const MapSearchSummary s = SearchStart(parameters, target, 40.0);
  ASSERT_TRUE(s.ok) << s.message;
  EXPECT_EQ(s.levels, (std::vector<int>{1, 0}));  // the coarse level first
  EXPECT_LE(s.cost, 40.0);
  EXPECT_EQ(int64_t(target.batch_sizes.size()), s.evaluations);
  // The local mode near the centre, not the higher one at (0.8, 0.8).
  EXPECT_NEAR(s.map[0], 0.1, 1e-3);
  EXPECT_NEAR(s.map[1], -0.1, 1e-3);
  RecordingTarget none(TwoModes, 16, 2, parameters);
  EXPECT_TRUE(SearchStart(parameters, none, 0.0).map.empty());
  EXPECT_TRUE(none.batch_sizes.empty());
}

TEST(StartSearch, ItsModeReplacesTheChainsMapOnlyWhereItScoresHigher) {
  const std::vector<ParameterSpec> parameters = {Uniform("a", -1, 1), Uniform("b", -1, 1)};
  auto summary_at = [&](std::vector<double> map) {
    SamplerSummary s;
    s.map = map;
    s.map_log_prior = LogPrior(parameters, map);
    s.map_log_likelihood = TwoModes(map, 0);
    s.map_log_posterior = s.map_log_prior + s.map_log_likelihood;
    for (size_t i = 0; i < parameters.size(); ++i) {
      ParameterSummary q;
      q.name = parameters[i].name;
      q.map = map[i];
      s.parameters.push_back(q);
    }
    return s;
  };
  RecordingTarget target(TwoModes, 16, 2, parameters);
  target.SetLevel(1);  // where the sampler might have left it: the candidate is scored at level 0
  bool adopted = true;
  // The chains found the higher mode: the start's lower one is scored and left out.
  SamplerSummary high = summary_at({0.8, 0.8});
  const double at_start = AdoptIfHigher(parameters, target, {0.1, -0.1}, &high, &adopted);
  EXPECT_FALSE(adopted);
  EXPECT_FALSE(high.map_from_search);
  EXPECT_EQ(high.map, (std::vector<double>{0.8, 0.8}));
  EXPECT_DOUBLE_EQ(at_start, LogPrior(parameters, {0.1, -0.1}) + TwoModes({0.1, -0.1}, 0));
  EXPECT_EQ(target.level_history.back(), 0);
  // The chains stayed on a worse point: the start's mode becomes the MAP, flagged.
  SamplerSummary low = summary_at({0.3, 0.1});
  low.evaluations = 10;
  AdoptIfHigher(parameters, target, {0.1, -0.1}, &low, &adopted);
  EXPECT_TRUE(adopted);
  EXPECT_TRUE(low.map_from_search);
  EXPECT_EQ(low.map, (std::vector<double>{0.1, -0.1}));
  EXPECT_DOUBLE_EQ(low.parameters[1].map, -0.1);
  EXPECT_DOUBLE_EQ(low.map_log_posterior, low.map_log_prior + low.map_log_likelihood);
  EXPECT_EQ(low.evaluations, 11);
  // Outside the prior, or of the wrong length: never scored, never adopted.
  SamplerSummary kept = summary_at({0.3, 0.1});
  EXPECT_EQ(AdoptIfHigher(parameters, target, {1.5, 0.0}, &kept, &adopted), -INFINITY);
  EXPECT_EQ(AdoptIfHigher(parameters, target, {0.1}, &kept, &adopted), -INFINITY);
  EXPECT_FALSE(adopted);
  EXPECT_EQ(kept.map, (std::vector<double>{0.3, 0.1}));
}

}  // namespace
}  // namespace vkr::opt::test
