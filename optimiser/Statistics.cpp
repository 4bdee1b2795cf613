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

// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation (relative error 1e-9), then one
// Halley step on erfc, which takes it to double precision.
double InverseNormalCdf(double p) {
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  double x;
  if (p < kLow) {
    const double q = std::sqrt(-2 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p <= 1 - kLow) {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  } else {
    const double q = std::sqrt(-2 * std::log(1 - p));
    x = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  }
  const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - p;
  const double u = e * std::sqrt(2 * M_PI) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

// The normal scores of the pooled ranks (ties get their average rank), chain by chain.
std::vector<std::vector<double>> RankNormalize(const std::vector<std::vector<double>>& chains) {
  const size_t n = CommonLength(chains);
  const size_t total = n * chains.size();
  std::vector<std::pair<double, size_t>> pooled;
  pooled.reserve(total);
  for (size_t m = 0; m < chains.size(); ++m)
    for (size_t i = 0; i < n; ++i) pooled.emplace_back(chains[m][i], m * n + i);
  std::sort(pooled.begin(), pooled.end());
  std::vector<std::vector<double>> z(chains.size(), std::vector<double>(n));
  for (size_t first = 0; first < total;) {
    size_t last = first;
    while (last + 1 < total && pooled[last + 1].first == pooled[first].first) ++last;
    const double rank = 0.5 * double(first + last) + 1.0;  // 1-based, averaged over ties
    const double score = InverseNormalCdf((rank - 0.375) / (double(total) + 0.25));
    for (size_t k = first; k <= last; ++k) z[pooled[k].second / n][pooled[k].second % n] = score;
    first = last + 1;
  }
  return z;
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

double RankNormalizedSplitRhat(const std::vector<std::vector<double>>& chains) {
  if (CommonLength(chains) < 4) return kUndefined;
  std::vector<double> all;
  for (const auto& c : chains) all.insert(all.end(), c.begin(), c.end());
  const double median = Quantile(all, 0.5);
  std::vector<std::vector<double>> folded = chains;
  for (auto& c : folded)
    for (double& x : c) x = std::abs(x - median);
  const double bulk = SplitRhat(RankNormalize(chains));
  const double tail = SplitRhat(RankNormalize(folded));
  if (std::isnan(bulk) || std::isnan(tail)) return std::isnan(bulk) ? tail : bulk;
  return std::max(bulk, tail);
}

double BulkEffectiveSampleSize(const std::vector<std::vector<double>>& chains) {
  const size_t n = CommonLength(chains);
  if (n < 8) return kUndefined;
  const size_t half = n / 2;
  std::vector<std::vector<double>> split;
  for (const auto& c : RankNormalize(chains)) {
    split.emplace_back(c.begin(), c.begin() + long(half));
    split.emplace_back(c.end() - long(half), c.end());  // odd n: the middle draw left out
  }
  return EffectiveSampleSize(split);
}

}  // namespace vkr::opt
