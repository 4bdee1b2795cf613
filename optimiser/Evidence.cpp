#include "optimiser/Evidence.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <locale>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "optimiser/Statistics.h"

namespace vkr::opt {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json EvidenceNumber(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

// log((1/n) Σ exp(x_t)), −∞ when every x is −∞.
double LogMeanExp(const std::vector<double>& x) {
  double top = -std::numeric_limits<double>::infinity();
  for (double v : x) top = std::max(top, v);
  if (!std::isfinite(top)) return top;
  double sum = 0.0;
  for (double v : x) sum += std::exp(v - top);
  return top + std::log(sum / double(x.size()));
}

}  // namespace

double SeriesStandardError(const std::vector<double>& series) {
  const double batch_means = BatchMeansStandardError(series);
  const double ess = EffectiveSampleSize({series});
  const double geyer = std::isfinite(ess) && ess > 0.0 ? StandardDeviation(series) / std::sqrt(ess) : kNaN;
  if (std::isnan(batch_means) || std::isnan(geyer)) return std::isnan(geyer) ? batch_means : geyer;
  return std::max(batch_means, geyer);
}

bool EvidenceEstimate::Agree() const {
  const double tolerance = 3.0 * std::hypot(se_ss, se_ti) + discretisation;
  return std::abs(log_z_ss - log_z_ti) <= tolerance;  // false when anything is NaN
}

std::vector<double> EvidenceLadder(int intervals, double alpha) {
  if (intervals < 1 || !(alpha > 0.0)) throw std::invalid_argument("EvidenceLadder: intervals ≥ 1, α > 0");
  std::vector<double> beta(size_t(intervals) + 1);
  for (int k = 0; k <= intervals; ++k) beta[size_t(k)] = std::pow(double(k) / double(intervals), 1.0 / alpha);
  beta.back() = 1.0;
  return beta;
}

double BatchMeansStandardError(const std::vector<double>& series, int* batches) {
  const size_t n = series.size();
  if (batches) *batches = 0;
  if (n < 16) return kNaN;
  const size_t a = size_t(std::floor(std::sqrt(double(n))));
  const size_t b = n / a;
  const size_t skip = n - a * b;  // the earliest draws: the farthest from equilibrium
  std::vector<double> means(a, 0.0);
  for (size_t j = 0; j < a; ++j) {
    for (size_t i = 0; i < b; ++i) means[j] += series[skip + j * b + i];
    means[j] /= double(b);
  }
  double mean = 0.0;
  for (double m : means) mean += m;
  mean /= double(a);
  double ss = 0.0;
  for (double m : means) ss += (m - mean) * (m - mean);
  if (batches) *batches = int(a);
  // Var(batch mean) ≈ σ²_∞ / b, so Var(overall mean) ≈ Var(batch mean) / a.
  return std::sqrt(ss / double(a - 1) / double(a));
}

EvidenceEstimate EstimateEvidence(const std::vector<double>& beta,
                                  const std::vector<std::vector<double>>& ll) {
  const size_t rungs = beta.size();
  if (rungs < 2 || ll.size() != rungs) throw std::invalid_argument("EstimateEvidence: one draw list per β, ≥ 2 rungs");
  if (beta.front() != 0.0 || beta.back() != 1.0) throw std::invalid_argument("EstimateEvidence: β must run from 0 to 1");
  for (size_t k = 0; k + 1 < rungs; ++k)
    if (!(beta[k] < beta[k + 1])) throw std::invalid_argument("EstimateEvidence: β must ascend strictly");
  const size_t n = ll[0].size();
  if (n < 4) throw std::invalid_argument("EstimateEvidence: at least 4 draws per rung");
  for (const auto& draws : ll)
    if (draws.size() != n) throw std::invalid_argument("EstimateEvidence: every rung needs as many draws");

  EvidenceEstimate e;
  e.beta = beta;
  e.draws = int(n);
  std::vector<double> delta(rungs - 1);
  for (size_t k = 0; k + 1 < rungs; ++k) delta[k] = beta[k + 1] - beta[k];

  // Moments per rung (variance with the n denominator, as the linearisation below uses).
  for (size_t k = 0; k < rungs; ++k) {
    double mean = 0.0;
    for (double v : ll[k]) mean += v;
    mean /= double(n);
    double var = 0.0;
    for (double v : ll[k]) var += (v - mean) * (v - mean);
    e.mean_log_likelihood.push_back(mean);
    e.var_log_likelihood.push_back(var / double(n));
  }

  // Stepping stone. log r̂_k = log mean_t exp(Δ_k ℓ_{k,t}); to first order
  // log Ẑ − log Z = mean_t Σ_k (exp(Δ_k ℓ_{k,t}) / r_k − 1), a mean over ladder iterations
  // whose batch means give the error.
  e.log_z_ss = 0.0;
  std::vector<double> ss_series(n, 0.0);
  for (size_t k = 0; k + 1 < rungs; ++k) {
    std::vector<double> x(n);
    for (size_t t = 0; t < n; ++t) x[t] = delta[k] * ll[k][t];
    const double log_r = LogMeanExp(x);
    e.log_ratio.push_back(log_r);
    e.log_z_ss += log_r;
    for (size_t t = 0; t < n; ++t) ss_series[t] += std::exp(x[t] - log_r);
  }

  // Thermodynamic integration: trapezoid weights c_j on the means, and the slope correction
  // −Σ_k Δ_k²/12 (v_{k+1} − v_k), whose weights e_j fall on the variances. The estimate is
  // exactly mean_t of Σ_j c_j ℓ_{j,t} + e_j (ℓ_{j,t} − μ_j)².
  std::vector<double> ti_series(n, 0.0);
  e.log_z_ti_trapezoid = 0.0;
  e.log_z_ti = 0.0;
  for (size_t j = 0; j < rungs; ++j) {
    const double before = j > 0 ? delta[j - 1] : 0.0, after = j + 1 < rungs ? delta[j] : 0.0;
    const double c = 0.5 * (before + after), w = (after * after - before * before) / 12.0;
    const double mu = e.mean_log_likelihood[j];
    e.log_z_ti_trapezoid += c * mu;
    e.log_z_ti += c * mu + w * e.var_log_likelihood[j];
    for (size_t t = 0; t < n; ++t) ti_series[t] += c * ll[j][t] + w * (ll[j][t] - mu) * (ll[j][t] - mu);
  }
  e.discretisation = std::abs(e.log_z_ti - e.log_z_ti_trapezoid);

  e.se_ss = SeriesStandardError(ss_series);
  e.se_ti = SeriesStandardError(ti_series);
  e.ess = e.se_ss > 0.0 ? std::pow(StandardDeviation(ss_series), 2) / (e.se_ss * e.se_ss) : kNaN;
  return e;
}

nlohmann::json ToJson(const EvidenceEstimate& e) {
  nlohmann::json rungs = nlohmann::json::array();
  for (size_t k = 0; k < e.beta.size(); ++k) {
    nlohmann::json r = {{"beta", e.beta[k]},
                        {"mean_log_likelihood", EvidenceNumber(e.mean_log_likelihood.at(k))},
                        {"var_log_likelihood", EvidenceNumber(e.var_log_likelihood.at(k))}};
    if (k < e.log_ratio.size()) r["log_ratio"] = EvidenceNumber(e.log_ratio[k]);
    if (k < e.acceptance.size()) r["acceptance"] = EvidenceNumber(e.acceptance[k]);
    if (k < e.swap_acceptance.size()) r["swap_acceptance"] = EvidenceNumber(e.swap_acceptance[k]);
    rungs.push_back(std::move(r));
  }
  return {{"log_z_ss", EvidenceNumber(e.log_z_ss)},
          {"se_ss", EvidenceNumber(e.se_ss)},
          {"log_z_ti", EvidenceNumber(e.log_z_ti)},
          {"se_ti", EvidenceNumber(e.se_ti)},
          {"log_z_ti_trapezoid", EvidenceNumber(e.log_z_ti_trapezoid)},
          {"discretisation", EvidenceNumber(e.discretisation)},
          {"agree", e.Agree()},
          {"draws", e.draws},
          {"ess", EvidenceNumber(e.ess)},
          {"rungs", rungs}};
}

std::string BriefReport(const EvidenceEstimate& e) {
  std::ostringstream o;
  o.imbue(std::locale::classic());
  o << std::fixed << std::setprecision(3) << "log Z = " << e.log_z_ss << " ± " << e.se_ss
    << " (stepping stone), " << e.log_z_ti << " ± " << e.se_ti << " (thermodynamic integration; trapezoid "
    << e.log_z_ti_trapezoid << "), " << e.beta.size() << " rungs × " << e.draws << " draws (ESS " << std::setprecision(0) << e.ess << ")"
    << (e.Agree() ? "" : "; the estimators disagree");
  return o.str();
}

}  // namespace vkr::opt
