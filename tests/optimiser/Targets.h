#pragma once
// Analytic targets for the sampler tests, and a target that records how it is called.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "optimiser/Parameter.h"
#include "optimiser/Sampler.h"
#include "optimiser/Statistics.h"
#include "optimiser/Target.h"

namespace vkr::opt::test {

inline ParameterSpec Uniform(const std::string& name, double lo, double hi,
                             std::optional<double> init = std::nullopt) {
  ParameterSpec p;
  p.name = name;
  p.prior = PriorKind::Uniform;
  p.a = lo;
  p.b = hi;
  p.init = init;
  return p;
}

// log N(x; μ, Σ) up to a constant, with Σ = D R D: sds `sd`, correlation matrix R.
struct Gaussian {
  Eigen::VectorXd mean;
  Eigen::MatrixXd precision;
  Gaussian(Eigen::VectorXd mu, const Eigen::MatrixXd& covariance)
      : mean(std::move(mu)), precision(covariance.inverse()) {}
  double operator()(const std::vector<double>& psi) const {
    const Eigen::Map<const Eigen::VectorXd> x(psi.data(), Eigen::Index(psi.size()));
    const Eigen::VectorXd r = x - mean;
    return -0.5 * r.dot(precision * r);
  }
};

// Wraps a function; checks and records every call: its batch size, and that every
// hypothesis passed lies inside the priors' support.
class RecordingTarget : public Target {
 public:
  RecordingTarget(std::function<double(const std::vector<double>&, int)> f, int max_batch,
                  int levels, std::vector<ParameterSpec> parameters)
      : f_(std::move(f)), max_batch_(max_batch), levels_(levels), parameters_(std::move(parameters)) {}

  int max_batch() const override { return max_batch_; }
  int levels() const override { return levels_; }
  void SetLevel(int level) override {
    EXPECT_GE(level, 0);
    EXPECT_LT(level, levels_);
    level_ = level;
    level_history.push_back(level);
  }
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override {
    batch_sizes.push_back(int(batch.size()));
    EXPECT_LE(int(batch.size()), max_batch_);
    std::vector<double> out;
    for (const auto& psi : batch) {
      EXPECT_TRUE(std::isfinite(LogPrior(parameters_, psi))) << "a hypothesis outside the prior";
      out.push_back(f_(psi, level_));
    }
    return out;
  }

  std::vector<int> batch_sizes;    // one entry per call
  std::vector<int> level_history;  // every SetLevel

 private:
  std::function<double(const std::vector<double>&, int)> f_;
  int max_batch_, levels_, level_ = 0;
  std::vector<ParameterSpec> parameters_;
};

// Estimates of one known number over seeds, each with its stated standard error: how many
// fell within k stated errors of the truth, and the mean stated error against the spread.
struct SeedSpread {
  double truth = 0.0, k = 2.0;
  std::vector<double> estimates, errors;
  int within = 0;
  void Add(double estimate, double error) {
    estimates.push_back(estimate);
    errors.push_back(error);
    within += std::abs(estimate - truth) <= k * error;
  }
  double MeanError() const { return Mean(errors); }
  double Spread() const { return StandardDeviation(estimates); }
};

// Bitwise equality of doubles (NaN equal to NaN of the same bits).
inline bool Same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline bool SameChain(const std::vector<Sample>& a, const std::vector<Sample>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const Sample& x = a[i];
    const Sample& y = b[i];
    if (x.iteration != y.iteration || x.chain != y.chain || x.level != y.level ||
        x.accepted != y.accepted || x.swapped != y.swapped || !Same(x.temperature, y.temperature) ||
        !Same(x.log_prior, y.log_prior) || !Same(x.log_likelihood, y.log_likelihood) ||
        x.psi.size() != y.psi.size())
      return false;
    for (size_t k = 0; k < x.psi.size(); ++k)
      if (!Same(x.psi[k], y.psi[k])) return false;
  }
  return true;
}

}  // namespace vkr::opt::test
