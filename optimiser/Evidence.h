#pragma once
// The log evidence log Z = log ∫ L(ψ) π(ψ) dψ from a ladder of power posteriors
// p_β(ψ) ∝ L(ψ)^β π(ψ), β_0 = 0 < β_1 < … < β_K = 1 (docs/internals/EVIDENCE.md). π is the
// prior of the ParameterSpec list normalised over its support: a ladder that starts at the
// prior measures Z_1 / Z_0, so an unnormalised constant (bounds that truncate a normal
// prior) cancels.
//
// Two estimators of the same number from the same draws:
//   - stepping stone (Xie, Lewis, Fan, Kuo & Chen 2011): log Z = Σ_k log r_k,
//     r_k = E_{β_k}[L^{β_{k+1} − β_k}], each mean taken with log-sum-exp;
//   - thermodynamic integration (Gelman & Meng 1998; Friel & Pettitt 2008):
//     log Z = ∫_0^1 E_β[log L] dβ by the trapezoid rule, corrected with the slopes
//     d E_β[log L] / dβ = Var_β[log L] (Friel, Hurn & Wyse 2014), which makes the rule exact
//     for cubics; the correction's size is the discretisation error the plain trapezoid has.
// Monte Carlo errors from each estimator's linearisation, one term per ladder iteration
// summed over the rungs, so autocorrelation within a rung and the correlation that replica
// exchange puts between rungs both count (SeriesStandardError).

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace vkr::opt {

struct EvidenceEstimate {
  double log_z_ss = 0.0, se_ss = 0.0;  // stepping stone and its Monte Carlo standard error
  // Thermodynamic integration: the corrected trapezoid and its Monte Carlo standard error;
  // the plain trapezoid; discretisation = |log_z_ti − log_z_ti_trapezoid|, what the grid
  // of β costs the plain rule (the corrected rule's own error is smaller).
  double log_z_ti = 0.0, se_ti = 0.0;
  double log_z_ti_trapezoid = 0.0;
  double discretisation = 0.0;
  // Per rung, β ascending: E_β[log L], Var_β[log L], and the stepping-stone log r_k
  // (rungs 0 … K − 1); per neighbour pair the swap acceptance (filled by the sampler, empty
  // for draws given from outside), and per rung its acceptance (the same).
  std::vector<double> beta, mean_log_likelihood, var_log_likelihood, log_ratio, swap_acceptance, acceptance;
  int draws = 0;    // per rung
  // Effective draws behind se_ss: the variance of its linearisation over se_ss². Below ~100
  // the errors are themselves uncertain, and short (docs/internals/EVIDENCE.md).
  double ess = 0.0;
  // Whether the two estimators agree within √(se_ss² + se_ti²)·3 + discretisation.
  bool Agree() const;
};

// {"log_z_ss", "se_ss", "log_z_ti", "se_ti", "log_z_ti_trapezoid", "discretisation",
//  "agree", "draws", "ess", "rungs": [{"beta", "mean_log_likelihood",
//  "var_log_likelihood", "log_ratio"?, "acceptance"?, "swap_acceptance"?}]}, swap_acceptance
//  with the rung above; undefined numbers are null.
nlohmann::json ToJson(const EvidenceEstimate& estimate);
std::string BriefReport(const EvidenceEstimate& estimate);

// The ladder β_k = (k/K)^(1/α), k = 0 … K: quantiles of a Beta(α, 1), the spacing of
// Xie et al. 2011 (α = 0.3); rungs crowd near the prior, where E_β[log L] changes fastest.
std::vector<double> EvidenceLadder(int intervals, double alpha = 0.3);

// log_likelihoods[k][t]: the log-likelihood of rung k's state at ladder iteration t, after
// burn-in; every rung the same number of draws (≥ 4), β strictly ascending from 0 to 1
// (std::invalid_argument otherwise). A rung with a non-finite value, or a ladder too
// short for batch means, gives NaN standard errors; the estimates are still returned.
EvidenceEstimate EstimateEvidence(const std::vector<double>& beta,
                                  const std::vector<std::vector<double>>& log_likelihoods);

// Standard error of the mean of an autocorrelated series: the larger of batch means (below)
// and sd/√ESS with Statistics.h's EffectiveSampleSize (Geyer's initial monotone sequence).
// Either alone fell short of the spread over seeds on the closed-form targets when the
// ladder's autocorrelation is long against the run (docs/internals/EVIDENCE.md); NaN for
// fewer than 4 values, Geyer's alone from 4 to 15.
double SeriesStandardError(const std::vector<double>& series);

// Standard error of the mean of an autocorrelated series by non-overlapping batch means:
// ⌊√n⌋ batches of ⌊n / ⌊√n⌋⌋ draws, the earliest draws left out when n does not divide.
// NaN for fewer than 16 values. `batches` (optional) receives the batch count.
double BatchMeansStandardError(const std::vector<double>& series, int* batches = nullptr);

}  // namespace vkr::opt
