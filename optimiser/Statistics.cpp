#include "optimiser/Statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vkr::opt {
namespace {

constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();

// Checks that all chains have one length and returns it.
size_t CommonLength(const std::vector<std::vector<double>>& chains) {
  if (chains.empty()) return 0;
  const size_t n = chains.front().size();
  for (const auto& c : chains)
    if (c.size() != n) throw std::invalid_argument("chain statistics: chains differ in length");
  return n;
}

// Sample variance with n − 1.
double Variance(const double* x, size_t n) {
  double mean = 0.0;
  for (size_t i = 0; i < n; ++i) mean += x[i];
  mean /= double(n);
  double ss = 0.0;
  for (size_t i = 0; i < n; ++i) ss += (x[i] - mean) * (x[i] - mean);
  return ss / double(n - 1);
}

}  // namespace

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kUndefined;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / double(values.size());
}

double StandardDeviation(const std::vector<double>& values) {
  if (values.size() < 2) return kUndefined;
  return std::sqrt(Variance(values.data(), values.size()));
}

double Quantile(std::vector<double> values, double p) {
  if (values.empty()) return kUndefined;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(p, 0.0, 1.0) * double(values.size() - 1);
  const size_t below = size_t(std::floor(position));
  const size_t above = std::min(below + 1, values.size() - 1);
  const double f = position - double(below);
  return values[below] + f * (values[above] - values[below]);
}

double SplitRhat(const std::vector<std::vector<double>>& chains) {
  const size_t length = CommonLength(chains);
  if (chains.empty() || length < 4) return kUndefined;
  const size_t n = length / 2;
  std::vector<double> means, variances;
  for (const auto& c : chains) {
    for (const double* half : {c.data(), c.data() + (length - n)}) {
      double m = 0.0;
      for (size_t i = 0; i < n; ++i) m += half[i];
      means.push_back(m / double(n));
      variances.push_back(Variance(half, n));
    }
  }
  const double w = Mean(variances);
  const double b_over_n = Variance(means.data(), means.size());
  if (!(w > 0.0) || !std::isfinite(w)) return kUndefined;
  const double var_plus = double(n - 1) / double(n) * w + b_over_n;
  return std::sqrt(var_plus / w);
}

double EffectiveSampleSize(const std::vector<std::vector<double>>& chains) {
  const size_t n = CommonLength(chains);
  const size_t m = chains.size();
  if (m == 0 || n < 4) return kUndefined;

  std::vector<double> means(m), variances(m);
  for (size_t c = 0; c < m; ++c) {
    means[c] = Mean(chains[c]);
    variances[c] = Variance(chains[c].data(), n);
  }
  const double w = Mean(variances);
  double var_plus = w * double(n - 1) / double(n);
  if (m > 1) var_plus += Variance(means.data(), m);
  if (!(var_plus > 0.0) || !std::isfinite(var_plus)) return kUndefined;

  // Mean over chains of the (biased, 1/n) autocovariance at lag t, computed on demand:
  // the sequence usually stops after a few times n/ESS lags.
  const auto mean_acov = [&](size_t t) {
    double sum = 0.0;
    for (size_t c = 0; c < m; ++c) {
      const double* x = chains[c].data();
      double s = 0.0;
      for (size_t i = 0; i + t < n; ++i) s += (x[i] - means[c]) * (x[i + t] - means[c]);
      sum += s / double(n);
    }
    return sum / double(m);
  };
  const auto rho = [&](size_t t) { return 1.0 - (w - mean_acov(t)) / var_plus; };

  // Geyer's initial positive sequence: pairs Γ_k = ρ_2k + ρ_2k+1 while positive.
  std::vector<double> r(n + 1, 0.0);
  double even = 1.0, odd = rho(1);
  r[0] = even;
  r[1] = odd;
  size_t s = 1;
  while (s + 4 < n && even + odd > 0.0) {
    even = rho(s + 1);
    odd = rho(s + 2);
    if (even + odd >= 0.0) {
      r[s + 1] = even;
      r[s + 2] = odd;
    }
    s += 2;
  }
  const size_t max_s = s;
  // Keeps the positive even term that ended the sequence: less variance in the
  // antithetic case (Stan does the same).
  if (even > 0.0) r[max_s + 1] = even;
  // Geyer's initial monotone sequence: no pair larger than the one before.
  for (size_t k = 1; k + 3 <= max_s; k += 2) {
    if (r[k + 1] + r[k + 2] > r[k - 1] + r[k]) {
      r[k + 1] = 0.5 * (r[k - 1] + r[k]);
      r[k + 2] = r[k + 1];
    }
  }
  double tau = -1.0 + r[max_s + 1];
  for (size_t k = 0; k < max_s; ++k) tau += 2.0 * r[k];
  const double total = double(m * n);
  return std::min(total / tau, total * std::log10(total));
}

}  // namespace vkr::opt
