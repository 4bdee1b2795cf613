#pragma once
// The sandwich's curvature adjustment, in Chandler & Bate's (2007) vertical form: where the
// magnitude adjustment divides the log-likelihood by one κ, this one scales each step away
// from the mode ψ* by a factor that depends on its direction, δ = ψ − ψ*:
//   ℓ_adj(ψ) = ℓ(ψ*)/κ + r(δ) (ℓ(ψ) − ℓ(ψ*)),   r(δ) = δᵀAδ / δᵀHδ,   A = H J⁻¹ H,
// so the curvature at the mode becomes A and the posterior's covariance the sandwich
// H⁻¹ J H⁻¹ in every direction, not on average over them. ℓ itself is evaluated at ψ, as
// the sampler proposed it: its roughness at small scales (8-bit views, rasterisation) is
// divided by r as the magnitude adjustment divides it by κ (the horizontal form evaluates ℓ
// at ψ* + C(ψ − ψ*), where that roughness stays whole). The level at the mode is the
// magnitude adjustment's, so log evidences and the scores of modes keep their meaning.
// docs/internals/LIKELIHOOD.md, "Honest intervals".

#include <vector>

namespace vkr {

// A = H J⁻¹ H (d × d, row-major) from H⁻¹ and J (both d × d, row-major), with the eigenvalues
// of H⁻¹J floored at 1: no direction becomes narrower than the raw likelihood says. Empty
// where H or J cannot be factored (the caller keeps the magnitude adjustment).
std::vector<double> AdjustedCurvature(const std::vector<double>& inverse_h, const std::vector<double>& j);

// r(δ) = δᵀAδ / δᵀHδ for ψ; 1 at the centre (where ℓ(ψ) − ℓ(ψ*) is 0 anyway).
double CurvatureRatio(const std::vector<double>& adjusted, const std::vector<double>& raw,
                      const std::vector<double>& centre, const std::vector<double>& psi);

// The raw log-likelihood's inverse curvature from the adjusted target's covariance Σ
// measured at the mode: Σ A H⁻¹ (symmetrised), which is H⁻¹ when Σ = A⁻¹ and follows a
// change of scale in every direction (a new σ) as the magnitude adjustment's κΣ does.
std::vector<double> RawInverseCurvature(const std::vector<double>& covariance, const std::vector<double>& adjusted,
                                        const std::vector<double>& raw);

}  // namespace vkr
