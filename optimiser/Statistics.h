#pragma once
// Chain statistics for the posterior summary: quantiles, effective sample size and R̂.
// A "chains" argument holds one vector of draws per chain, all of the same length (a
// programmer error otherwise: std::invalid_argument). Undefined results (too few draws, no
// variance) are NaN, not exceptions.

#include <vector>

namespace vkr::opt {

double Mean(const std::vector<double>& values);
// Sample standard deviation (n − 1 denominator); NaN for fewer than two values.
double StandardDeviation(const std::vector<double>& values);
// Quantile p ∈ [0, 1] by linear interpolation between order statistics (R's type 7:
// position p·(n − 1) in the sorted values); NaN when empty.
double Quantile(std::vector<double> values, double p);

// Split-R̂ (Gelman et al., BDA3 §11.4): every chain is cut into halves (the middle draw of
// an odd length dropped) and R̂ = √(var⁺ / W) over the 2M half-chains of n draws, with W the
// mean within-half variance and var⁺ = (n − 1)/n · W + B/n, B/n the variance of the
// half-chain means. ≈ 1 when the chains agree, ≫ 1 when they sample different places.
// NaN for fewer than 4 draws per chain or W = 0.
double SplitRhat(const std::vector<std::vector<double>>& chains);

// Effective sample size of M chains of N draws together, as Stan computes it (reference
// manual, "Effective sample size"; Vehtari et al. 2021 without rank normalisation):
// autocorrelations ρ_t = 1 − (W − mean_m acov_m(t)) / var⁺ combine the within-chain
// autocovariances with the between-chain variance; the sum τ = −1 + 2 Σ_k (ρ_2k + ρ_2k+1)
// is truncated at Geyer's initial positive sequence and made monotone (Geyer's initial
// monotone sequence estimator), and ESS = M·N / τ, capped at M·N·log10(M·N).
// NaN for fewer than 4 draws per chain or zero variance.
double EffectiveSampleSize(const std::vector<std::vector<double>>& chains);

// Rank-normalised split-R̂ (Vehtari, Gelman, Simpson, Carpenter & Bürkner 2021): the draws
// of all chains are replaced by the normal scores of their pooled ranks, z = Φ⁻¹((r − 3/8)/
// (S + 1/4)), so heavy tails and a chain stuck far out cannot hide behind or inflate a
// variance; R̂ is the larger of SplitRhat on those scores (bulk) and on the scores of the
// draws' distance from the pooled median (folded: chains with different spreads). The
// paper's threshold for "converged" is 1.01. NaN as SplitRhat.
double RankNormalizedSplitRhat(const std::vector<std::vector<double>>& chains);

// Bulk effective sample size (ibid.): EffectiveSampleSize of the rank-normalised draws with
// every chain split in halves, so a trend within a chain lowers it. The paper asks for at
// least 100 per chain (400 for four chains) before trusting R̂ or a quantile. NaN as
// EffectiveSampleSize.
double BulkEffectiveSampleSize(const std::vector<std::vector<double>>& chains);

}  // namespace vkr::opt
