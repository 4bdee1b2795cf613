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
  target.SetLevel(1);  // where the sampler might have left it: both modes are scored at level 0
  // The chains found the higher mode: the start's lower one is scored and left out.
  SamplerSummary high = summary_at({0.8, 0.8});
  const ModeComparison kept_chains = AdoptIfHigher(parameters, target, {0.1, -0.1}, &high);
  EXPECT_FALSE(kept_chains.adopted);
  EXPECT_FALSE(high.map_from_search);
  EXPECT_EQ(high.map, (std::vector<double>{0.8, 0.8}));
  EXPECT_DOUBLE_EQ(kept_chains.candidate, LogPrior(parameters, {0.1, -0.1}) + TwoModes({0.1, -0.1}, 0));
  EXPECT_DOUBLE_EQ(kept_chains.chains, high.map_log_posterior);
  EXPECT_EQ(target.level_history.back(), 0);
  // The chains stayed on a worse point: the start's mode becomes the MAP, flagged.
  SamplerSummary low = summary_at({0.3, 0.1});
  low.evaluations = 10;
  EXPECT_TRUE(AdoptIfHigher(parameters, target, {0.1, -0.1}, &low).adopted);
  EXPECT_TRUE(low.map_from_search);
  EXPECT_EQ(low.map, (std::vector<double>{0.1, -0.1}));
  EXPECT_DOUBLE_EQ(low.parameters[1].map, -0.1);
  EXPECT_DOUBLE_EQ(low.map_log_posterior, low.map_log_prior + low.map_log_likelihood);
  EXPECT_EQ(low.evaluations, 13);  // both modes compared, then the adopted one as the target scores it
  // Outside the prior, or of the wrong length: never scored, never adopted.
  SamplerSummary kept = summary_at({0.3, 0.1});
  EXPECT_EQ(AdoptIfHigher(parameters, target, {1.5, 0.0}, &kept).candidate, -INFINITY);
  EXPECT_EQ(AdoptIfHigher(parameters, target, {0.1}, &kept).candidate, -INFINITY);
  EXPECT_FALSE(AdoptIfHigher(parameters, target, {0.1}, &kept).adopted);
  EXPECT_EQ(kept.map, (std::vector<double>{0.3, 0.1}));
}

// A target whose calibration favours the mode it was made at (as clutter masks found there
// do): Evaluate() prefers the chains' MAP, ScoreModes(), which refits per mode, the other.
// The decision follows ScoreModes(); the adopted MAP's log likelihood is Evaluate()'s.
class FavouringTarget : public Target {
 public:
  explicit FavouringTarget(std::vector<double> favoured) : favoured_(std::move(favoured)) {}
  int max_batch() const override { return 4; }
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override {
    std::vector<double> out;
    for (const auto& psi : batch) out.push_back(psi == favoured_ ? 0.0 : TwoModes(psi, 0) - 6.0);
    return out;
  }
  std::vector<double> ScoreModes(const std::vector<std::vector<double>>& modes) override {
    ++score_calls;
    std::vector<double> out;
    for (const auto& psi : modes) out.push_back(TwoModes(psi, 0));
    return out;
  }
  // Refitted at a mode, the calibration favours that mode instead.
  nlohmann::json RefitAt(const std::vector<double>& psi) override {
    ++refit_calls;
    favoured_ = psi;
    return {{"fitted_at", psi}};
  }
  void RestoreCalibration(const nlohmann::json& calibration) override {
    favoured_ = calibration.at("fitted_at").get<std::vector<double>>();
  }
  int score_calls = 0, refit_calls = 0;

 private:
  std::vector<double> favoured_;
};

TEST(StartSearch, TheModesAreComparedAsScoreModesScoresThemNotUnderTheChainsCalibration) {
  const std::vector<ParameterSpec> parameters = {Uniform("a", -1, 1), Uniform("b", -1, 1)};
  const std::vector<double> chains = {0.3, 0.1}, search = {0.8, 0.8};  // TwoModes is higher at 0.8, 0.8
  FavouringTarget target(chains);
  SamplerSummary summary;
  summary.map = chains;
  summary.map_log_prior = LogPrior(parameters, chains);
  summary.map_log_likelihood = target.Evaluate({chains})[0];
  summary.map_log_posterior = summary.map_log_prior + summary.map_log_likelihood;
  summary.calibration = {{"fitted_at", chains}};
  for (const ParameterSpec& p : parameters) summary.parameters.push_back(ParameterSummary{p.name});
  ASSERT_GT(target.Evaluate({chains})[0], target.Evaluate({search})[0]);  // the trap
  // A lower mode is not adopted, and the calibration stays the chains'.
  SamplerSummary kept = summary;
  EXPECT_FALSE(AdoptIfHigher(parameters, target, {-0.6, 0.6}, &kept).adopted);
  EXPECT_EQ(target.refit_calls, 0);
  EXPECT_EQ(kept.calibration, summary.calibration);
  const ModeComparison c = AdoptIfHigher(parameters, target, search, &summary);
  EXPECT_EQ(target.score_calls, 2);
  EXPECT_TRUE(c.adopted);
  EXPECT_DOUBLE_EQ(c.candidate - c.chains, TwoModes(search, 0) - TwoModes(chains, 0));
  EXPECT_EQ(summary.map, search);
  // The nuisances are refitted at the adopted mode; its log likelihood is the target's under them.
  EXPECT_EQ(target.refit_calls, 1);
  EXPECT_EQ(summary.calibration, nlohmann::json({{"fitted_at", search}}));
  EXPECT_DOUBLE_EQ(summary.map_log_likelihood, 0.0);
  EXPECT_DOUBLE_EQ(summary.map_log_likelihood, target.Evaluate({search})[0]);
}

}  // namespace
}  // namespace vkr::opt::test
