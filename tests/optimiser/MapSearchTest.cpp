// The MAP search with NLopt (MapSearch.h): every method finds the mode of a correlated
// quadratic and of a curved valley, keeps to the box of the priors and to its budget, counts
// what it spends, walks the levels coarsest first, restarts past roughness that stopped it,
// and reports what it was given wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "optimiser/MapSearch.h"
#include "tests/optimiser/Targets.h"

namespace vkr::opt::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

const SearchMethod kAll[] = {SearchMethod::Bobyqa, SearchMethod::NelderMead, SearchMethod::Sbplx,
                             SearchMethod::Crs2Lm, SearchMethod::Isres};
const SearchMethod kLocal[] = {SearchMethod::Bobyqa, SearchMethod::NelderMead, SearchMethod::Sbplx};

// A correlated quadratic, its mode off the prior centre (a = 0.3, b = −0.6, c = 1.2).
double Quadratic(const std::vector<double>& x) {
  const double u = x[0] - 0.3, v = x[1] + 0.6, w = x[2] - 1.2;
  return -50.0 * (u * u + 2.0 * v * v + 0.5 * w * w + 0.8 * u * v);
}
std::vector<ParameterSpec> QuadraticParameters() {
  return {Uniform("a", -1, 1), Uniform("b", -1, 1), Uniform("c", 0, 2)};
}

// Rosenbrock's valley (log posterior = −Rosenbrock), mode at (1, 1).
double Rosenbrock(const std::vector<double>& x) {
  const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
  return -(a * a + 100.0 * b * b);
}

TEST(MapSearch, EveryMethodFindsTheModeOfAQuadratic) {
  for (SearchMethod method : kAll) {
    FunctionTarget target([](const std::vector<double>& x, int) { return Quadratic(x); }, 1);
    MapSearchOptions o;
    o.method = method;
    o.max_cost = 6000;  // the global methods need thousands; the local ones stop long before
    MapSearchSummary s;
    ASSERT_TRUE(SearchMap(o, QuadraticParameters(), target, &s)) << ToString(method) << ": " << s.message;
    // The global methods' random searches end near, not at, the mode.
    const double tolerance = method == SearchMethod::Crs2Lm || method == SearchMethod::Isres ? 2e-2 : 1e-4;
    EXPECT_NEAR(s.map[0], 0.3, tolerance) << ToString(method);
    EXPECT_NEAR(s.map[1], -0.6, tolerance) << ToString(method);
    EXPECT_NEAR(s.map[2], 1.2, tolerance) << ToString(method);
    // The summary's numbers are of its MAP: log prior of three uniforms of width 2.
    EXPECT_NEAR(s.log_prior, -3.0 * std::log(2.0), 1e-12);
    EXPECT_DOUBLE_EQ(s.log_likelihood, Quadratic(s.map));
    EXPECT_DOUBLE_EQ(s.log_posterior, s.log_prior + s.log_likelihood);
  }
}

TEST(MapSearch, LocalMethodsFollowACurvedValley) {
  for (SearchMethod method : kLocal) {
    FunctionTarget target([](const std::vector<double>& x, int) { return Rosenbrock(x); }, 1);
    MapSearchOptions o;
    o.method = method;
    o.max_cost = 5000;
    o.tolerance = 1e-9;
    MapSearchSummary s;
    ASSERT_TRUE(SearchMap(o, {Uniform("x", -2, 2), Uniform("y", -1, 3)}, target, &s)) << s.message;
    EXPECT_NEAR(s.map[0], 1.0, 1e-3) << ToString(method);
    EXPECT_NEAR(s.map[1], 1.0, 2e-3) << ToString(method);
  }
}

TEST(MapSearch, KeepsToTheBoxAndFindsAModeOnItsEdge) {
  // The unconstrained maximum (0.3, −0.6, 1.2) lies outside a ≤ 0.1: the constrained mode
  // has a = 0.1 and b, c at their conditional best (b = −0.6 − 0.2(a − 0.3) = −0.56).
  const std::vector<ParameterSpec> parameters = {Uniform("a", -1, 0.1), Uniform("b", -1, 1), Uniform("c", 0, 2)};
  for (SearchMethod method : kAll) {
    RecordingTarget target([](const std::vector<double>& x, int) { return Quadratic(x); }, 1, 1, parameters);
    MapSearchOptions o;
    o.method = method;
    o.max_cost = 3000;
    MapSearchSummary s;
    ASSERT_TRUE(SearchMap(o, parameters, target, &s)) << s.message;  // RecordingTarget checks every point
    for (int size : target.batch_sizes) EXPECT_EQ(size, 1);
    if (method == SearchMethod::Crs2Lm || method == SearchMethod::Isres) continue;
    EXPECT_NEAR(s.map[0], 0.1, 1e-4) << ToString(method);
    EXPECT_NEAR(s.map[1], -0.56, 1e-3) << ToString(method);
  }
}

TEST(MapSearch, SpendsNoMoreThanItsBudgetAndCountsEveryEvaluation) {
  for (SearchMethod method : kAll) {
    int calls = 0;
    FunctionTarget target(
        [&](const std::vector<double>& x, int) {
          ++calls;
          return Rosenbrock(x);
        },
        1);
    MapSearchOptions o;
    o.method = method;
    o.max_cost = 37;
    o.tolerance = 0;  // never converged: only the budget ends it
    int64_t last = 0;
    MapSearchSummary s;
    SearchMap(o, {Uniform("x", -2, 2), Uniform("y", -1, 3)}, target, &s, [&](const SearchEvaluation& e) {
      EXPECT_EQ(e.evaluations, last + 1);
      last = e.evaluations;
      EXPECT_DOUBLE_EQ(e.cost, double(e.evaluations));  // one level: every evaluation costs 1
    });
    EXPECT_EQ(s.evaluations, calls) << ToString(method);
    EXPECT_LE(s.evaluations, 37) << ToString(method);
    EXPECT_GE(s.evaluations, 30) << ToString(method) << ": stopped long before the budget";
    EXPECT_EQ(last, s.evaluations);
  }
}

TEST(MapSearch, CoarseToFineVisitsTheLevelsInOrderWithinTheirShares) {
  // Each level's mode is offset by its level, so that the start of a level is not its mode.
  std::vector<int> seen_levels;
  FunctionTarget target(
      [&](const std::vector<double>& x, int level) {
        if (seen_levels.empty() || seen_levels.back() != level) seen_levels.push_back(level);
        return Quadratic({x[0] + 0.01 * level, x[1], x[2]});
      },
      1, 3);
  MapSearchOptions o;
  o.levels = 3;
  o.max_cost = 40;
  o.coarse_share = 0.25;  // 10 full-resolution equivalents: 160 evaluations at level 2, 40 at 1
  MapSearchSummary s;
  double cost = 0.0;
  ASSERT_TRUE(SearchMap(o, QuadraticParameters(), target, &s, [&](const SearchEvaluation& e) {
    cost += std::pow(4.0, -e.level);
    EXPECT_DOUBLE_EQ(e.cost, cost);
  })) << s.message;
  EXPECT_EQ(seen_levels, (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(s.levels, (std::vector<int>{2, 1, 0}));
  ASSERT_EQ(s.level_evaluations.size(), 3u);
  EXPECT_LE(s.level_evaluations[0], 160);
  EXPECT_LE(s.level_evaluations[0] / 16.0 + s.level_evaluations[1] / 4.0, 20.0 + 1e-9);
  EXPECT_EQ(s.level_evaluations[0] + s.level_evaluations[1] + s.level_evaluations[2], s.evaluations);
  EXPECT_LE(s.cost, 40.0 + 1e-9);
  EXPECT_DOUBLE_EQ(s.cost, cost);
  EXPECT_EQ(target.level(), 0) << "the target is left at level 0";
  // The MAP is level 0's: the unshifted mode.
  EXPECT_NEAR(s.map[0], 0.3, 1e-4);
}

TEST(MapSearch, UnscorableHypothesesAreStepsAwayNotErrors) {
  // NaN right of a = 0.35, just past the mode (a = 0.3): the search steps into it and back.
  int unscorable = 0;
  FunctionTarget target(
      [&](const std::vector<double>& x, int) {
        if (x[0] <= 0.35) return Quadratic(x);
        ++unscorable;
        return std::nan("");
      },
      1);
  MapSearchOptions o;
  o.max_cost = 2000;
  o.initial_step = 0.3;
  MapSearchSummary s;
  ASSERT_TRUE(SearchMap(o, QuadraticParameters(), target, &s)) << s.message;
  EXPECT_GT(unscorable, 0) << "the test never reached the unscorable region";
  EXPECT_NEAR(s.map[0], 0.3, 1e-3);
  EXPECT_NEAR(s.map[1], -0.6, 1e-3);
  // Nothing scorable anywhere: a failed search with the reason, not an exception.
  FunctionTarget nothing([](const std::vector<double>&, int) { return -INFINITY; }, 1);
  EXPECT_FALSE(SearchMap(MapSearchOptions{}, QuadraticParameters(), nothing, &s));
  EXPECT_NE(s.message.find("no hypothesis with a finite log posterior"), std::string::npos) << s.message;
  EXPECT_TRUE(s.map.empty());
}

TEST(MapSearch, NormalPriorsWithoutBoundsSearchMeanPlusMinusFiveSd) {
  ParameterSpec p;
  p.name = "z";
  p.prior = PriorKind::Normal;
  p.a = 2.0;
  p.b = 0.5;
  EXPECT_DOUBLE_EQ(SearchLower(p, 5.0), -0.5);
  EXPECT_DOUBLE_EQ(SearchUpper(p, 5.0), 4.5);
  // With a flat likelihood the MAP is the prior's mean.
  FunctionTarget target([](const std::vector<double>&, int) { return 0.0; }, 1);
  MapSearchOptions o;
  o.start = {3.0};
  MapSearchSummary s;
  ASSERT_TRUE(SearchMap(o, {p}, target, &s)) << s.message;
  EXPECT_NEAR(s.map[0], 2.0, 1e-4);
}

// The quadratic as a rasterised likelihood sees it: a washboard of local maxima every 1/100
// (texel columns that switch between views as a face moves) on top of the trend.
double RoughQuadratic(const std::vector<double>& x) {
  double ripple = 0.0;
  for (double xi : x) ripple += std::abs(std::sin(kPi * 100.0 * xi));
  return Quadratic(x) - 0.05 * ripple;
}

double DistanceToQuadraticMode(const std::vector<double>& x) {
  return std::hypot(x[0] - 0.3, x[1] + 0.6, x[2] - 1.2);
}

TEST(MapSearch, RestartsCarryBobyqaPastWhereRoughnessStoppedIt) {
  auto search = [](int restarts) {
    FunctionTarget target([](const std::vector<double>& x, int) { return RoughQuadratic(x); }, 1);
    MapSearchOptions o;
    o.max_cost = 400;
    o.restarts = restarts;
    MapSearchSummary s;
    EXPECT_TRUE(SearchMap(o, QuadraticParameters(), target, &s)) << s.message;
    EXPECT_LE(s.cost, 400.0 + 1e-9);
    return s;
  };
  const MapSearchSummary plain = search(0), restarted = search(5);
  EXPECT_EQ(plain.restarts, 0);
  EXPECT_EQ(plain.levels, std::vector<int>{0});
  // Alone, BOBYQA's trust region shrinks onto a ripple four periods short of the mode.
  EXPECT_GT(DistanceToQuadraticMode(plain.map), 0.01);
  EXPECT_LT(DistanceToQuadraticMode(restarted.map), 1e-3);
  ASSERT_GE(restarted.restarts, 1);
  // Each restart is another run at level 0, counted as such.
  EXPECT_EQ(restarted.levels.size(), size_t(1 + restarted.restarts));
  int64_t evaluations = 0;
  for (int64_t e : restarted.level_evaluations) evaluations += e;
  EXPECT_EQ(evaluations, restarted.evaluations);
  EXPECT_NE(restarted.message.find("restart 1: "), std::string::npos) << restarted.message;
  EXPECT_GE(restarted.log_posterior, plain.log_posterior);
  // Where the first run found the mode, one restart confirms it and the rest are not spent.
  FunctionTarget smooth([](const std::vector<double>& x, int) { return Quadratic(x); }, 1);
  MapSearchOptions o;
  o.restarts = 5;
  MapSearchSummary s;
  ASSERT_TRUE(SearchMap(o, QuadraticParameters(), smooth, &s)) << s.message;
  EXPECT_EQ(s.restarts, 1) << s.message;
  EXPECT_LT(DistanceToQuadraticMode(s.map), 1e-4);
}

TEST(MapSearch, BadInputIsAReasonNotACrash) {
  FunctionTarget target([](const std::vector<double>& x, int) { return Quadratic(x); }, 1);
  MapSearchSummary s;
  MapSearchOptions o;
  o.max_cost = 0;
  EXPECT_FALSE(SearchMap(o, QuadraticParameters(), target, &s));
  EXPECT_NE(s.message.find("max_cost"), std::string::npos) << s.message;
  o = MapSearchOptions{};
  o.restarts = -1;
  EXPECT_FALSE(SearchMap(o, QuadraticParameters(), target, &s));
  EXPECT_NE(s.message.find("restarts"), std::string::npos) << s.message;
  o = MapSearchOptions{};
  o.restart_step = 0;
  EXPECT_FALSE(SearchMap(o, QuadraticParameters(), target, &s));
  EXPECT_NE(s.message.find("restart_step"), std::string::npos) << s.message;
  o = MapSearchOptions{};
  o.start = {0.0, 0.0, 5.0};  // c outside [0, 2]
  EXPECT_FALSE(SearchMap(o, QuadraticParameters(), target, &s));
  EXPECT_NE(s.message.find("start"), std::string::npos) << s.message;
  // A target error reaches the caller as it was thrown, not as NLopt's "nlopt failure".
  FunctionTarget failing([](const std::vector<double>&, int) -> double { throw std::runtime_error("device lost"); }, 1);
  EXPECT_THROW(
      {
        try {
          SearchMap(MapSearchOptions{}, QuadraticParameters(), failing, &s);
        } catch (const std::runtime_error& e) {
          EXPECT_STREQ(e.what(), "device lost");
          throw;
        }
      },
      std::runtime_error);
}

TEST(MapSearch, MethodNamesRoundTrip) {
  for (SearchMethod method : kAll) {
    SearchMethod back = SearchMethod::Isres;
    ASSERT_TRUE(FromString(ToString(method), &back));
    EXPECT_EQ(back, method);
  }
  SearchMethod m;
  EXPECT_FALSE(FromString("BOBYQA", &m));
  EXPECT_EQ(SearchMethodNames(), "bobyqa, neldermead, sbplx, crs2lm, isres");
}

TEST(MapSearch, TheSameSeedGivesTheSameGlobalSearch) {
  auto run = [](uint64_t seed) {
    FunctionTarget target([](const std::vector<double>& x, int) { return Rosenbrock(x); }, 1);
    MapSearchOptions o;
    o.method = SearchMethod::Crs2Lm;
    o.max_cost = 200;
    o.seed = seed;
    MapSearchSummary s;
    SearchMap(o, {Uniform("x", -2, 2), Uniform("y", -1, 3)}, target, &s);
    return s.map;
  };
  EXPECT_EQ(run(4), run(4));
  EXPECT_NE(run(4), run(5));
}

}  // namespace
}  // namespace vkr::opt::test
