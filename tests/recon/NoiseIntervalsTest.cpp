// Which κ a run's intervals are stated at (recon/NoiseIntervals.h), and how stating them there
// moves the summaries: toward the MAP, by √(κ_noise/κ).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "recon/NoiseIntervals.h"

namespace vkr::recon {
namespace {

nlohmann::json Calibration(double sandwich, double noise) {
  return {{"kappa", sandwich}, {"noise_correlation", {{"kappa", noise}, {"rings", {1.0, 0.3}}}}};
}

TEST(NoiseIntervals, ResidualsLikeNoiseGetTheNoisesKappa) {
  const LikelihoodSettings defaults;
  for (const Diagnosis::Verdict verdict : {Diagnosis::Verdict::Ok, Diagnosis::Verdict::Unsettled}) {
    const NoiseIntervals i = ChooseNoiseIntervals(defaults, Calibration(100.0, 4.0), verdict);
    EXPECT_EQ(i.from, "noise");
    EXPECT_DOUBLE_EQ(i.kappa, 4.0);
    EXPECT_DOUBLE_EQ(i.scale, 0.2);
    EXPECT_TRUE(i.why.empty());
  }
}

TEST(NoiseIntervals, ModelErrorKeepsTheSandwichsWidth) {
  const LikelihoodSettings defaults;
  for (const Diagnosis::Verdict verdict :
       {Diagnosis::Verdict::ModelError, Diagnosis::Verdict::Failed, Diagnosis::Verdict::NotDiagnosed}) {
    const NoiseIntervals i = ChooseNoiseIntervals(defaults, Calibration(100.0, 4.0), verdict);
    EXPECT_EQ(i.from, "sandwich");
    EXPECT_DOUBLE_EQ(i.kappa, 100.0);
    EXPECT_DOUBLE_EQ(i.scale, 1.0);
    EXPECT_FALSE(i.why.empty());
  }
  EXPECT_NE(ChooseNoiseIntervals(defaults, Calibration(100.0, 4.0), Diagnosis::Verdict::ModelError).why.find("model error"),
            std::string::npos);
}

TEST(NoiseIntervals, SettingsAndMissingMeasurementsKeepTheChainsKappa) {
  LikelihoodSettings s;
  s.kappa_estimate = KappaEstimate::Sandwich;
  EXPECT_EQ(ChooseNoiseIntervals(s, Calibration(100.0, 4.0), Diagnosis::Verdict::Ok).scale, 1.0);
  s.kappa_estimate = KappaEstimate::Noise;  // the chains sampled at it already
  EXPECT_EQ(ChooseNoiseIntervals(s, Calibration(4.0, 4.0), Diagnosis::Verdict::Ok).from, "chains");
  s.kappa_estimate = KappaEstimate::Auto;
  s.kappa = 12.0;
  EXPECT_EQ(ChooseNoiseIntervals(s, Calibration(12.0, 4.0), Diagnosis::Verdict::Ok).from, "fixed");
  const LikelihoodSettings defaults;
  EXPECT_EQ(ChooseNoiseIntervals(defaults, {{"kappa", 50.0}}, Diagnosis::Verdict::Ok).scale, 1.0);
  EXPECT_EQ(ChooseNoiseIntervals(defaults, nullptr, Diagnosis::Verdict::Ok).scale, 1.0);
  // Never wider than the chains': a noise κ above the sandwich's leaves them.
  EXPECT_EQ(ChooseNoiseIntervals(defaults, Calibration(3.0, 6.0), Diagnosis::Verdict::Ok).scale, 1.0);
}

TEST(NoiseIntervals, SummariesMoveTowardTheMap) {
  opt::SamplerSummary summary;
  opt::ParameterSummary p;
  p.map = 1.0, p.mean = 1.1, p.q025 = 0.5, p.q975 = 1.5, p.sd = 0.3, p.laplace_sd = 0.4, p.rhat = 1.2, p.ess = 80;
  summary.parameters = {p};
  ScaleIntervals(0.5, {}, &summary);  // uniform priors, a spread the curvature explains
  const opt::ParameterSummary& q = summary.parameters[0];
  EXPECT_DOUBLE_EQ(q.map, 1.0);
  EXPECT_DOUBLE_EQ(q.mean, 1.05);
  EXPECT_DOUBLE_EQ(q.q025, 0.75);
  EXPECT_DOUBLE_EQ(q.q975, 1.25);
  EXPECT_DOUBLE_EQ(q.sd, 0.15);
  EXPECT_DOUBLE_EQ(q.laplace_sd, 0.2);
  EXPECT_DOUBLE_EQ(q.rhat, 1.2);  // the chains' mixing is theirs
  EXPECT_DOUBLE_EQ(q.ess, 80);
}

TEST(NoiseIntervals, ANormalPriorsShareOfThePrecisionStays) {
  // Posterior sd 0.5 under a normal prior of sd 1: precision 4 = 1 (prior) + 3 (likelihood).
  // At a quarter of κ the likelihood's is 12: sd 1/√13, not 0.25.
  opt::SamplerSummary summary;
  opt::ParameterSummary p;
  p.map = 0.0, p.mean = 0.0, p.q025 = -1.0, p.q975 = 1.0, p.sd = 0.5, p.laplace_sd = 0.5;
  opt::ParameterSummary flat = p;
  opt::ParameterSummary prior_only = p;
  prior_only.sd = prior_only.laplace_sd = 1.0;  // as wide as its prior: the photographs say nothing
  summary.parameters = {p, flat, prior_only};
  ScaleIntervals(0.5, {1.0, std::numeric_limits<double>::infinity(), 1.0}, &summary);
  EXPECT_NEAR(summary.parameters[0].sd, 1.0 / std::sqrt(13.0), 1e-12);
  EXPECT_NEAR(summary.parameters[0].q975, 2.0 / std::sqrt(13.0), 1e-12);
  EXPECT_DOUBLE_EQ(summary.parameters[1].sd, 0.25);
  EXPECT_DOUBLE_EQ(summary.parameters[2].sd, 1.0);
  EXPECT_DOUBLE_EQ(summary.parameters[2].q025, -1.0);
}

TEST(NoiseIntervals, SpreadBeyondTheCurvaturesIsNotShrunk) {
  // The chains spread 0.5 where the curvature at the mode says 0.3: a plateau holds the extra
  // variance 0.25 − 0.09 = 0.16, which a smaller κ does not narrow; the Gaussian 0.09 shrinks
  // to 0.09/4.
  const double uniform = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(SpreadFactor(0.5, 0.5, uniform, 0.3), std::sqrt(0.16 + 0.0225) / 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(SpreadFactor(0.5, 0.2, uniform, 0.3), 0.5);  // narrower than the curvature's: all of it
  EXPECT_DOUBLE_EQ(SpreadFactor(0.5, 0.2, uniform, std::nan("")), 0.5);
  EXPECT_DOUBLE_EQ(SpreadFactor(1.0, 0.5, uniform, 0.3), 1.0);
  opt::SamplerSummary summary;
  opt::ParameterSummary p;
  p.map = 0.0, p.mean = 0.1, p.q025 = -1.0, p.q975 = 1.0, p.sd = 0.5, p.laplace_sd = 0.3;
  summary.parameters = {p};
  ScaleIntervals(0.5, {}, &summary);
  EXPECT_NEAR(summary.parameters[0].sd, std::sqrt(0.1825), 1e-12);
  EXPECT_NEAR(summary.parameters[0].q975, std::sqrt(0.1825) / 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(summary.parameters[0].laplace_sd, 0.15);
}

TEST(NoiseIntervals, WrittenToMapJson) {
  NoiseIntervals i;
  i.kappa = 100.0, i.from = "sandwich", i.why = "the diagnosis finds model error";
  const nlohmann::json j = ToJson(i);
  EXPECT_EQ(j["from"], "sandwich");
  EXPECT_EQ(j["kappa"], 100.0);
  EXPECT_EQ(j["why"], "the diagnosis finds model error");
  EXPECT_FALSE(ToJson(NoiseIntervals{4.0, 0.2, "noise", ""}).contains("why"));
}

}  // namespace
}  // namespace vkr::recon
