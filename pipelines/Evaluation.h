#pragma once
// What a likelihood reduces one hypothesis to, and how the host turns those few scalars
// into a log-likelihood (DESIGN.md, "The likelihoods", step 4; thesis §7.4).
//
// Per atlas texel t that lies on the surface and outside every other primitive, with n_t
// views seeing it (weight w_i ∈ (0, 1], colours c_i ∈ [0,1]³):
//   mean      μ_t = Σ w_i c_i / Σ w_i
//   deviation s_t = Σ w_i ‖c_i − μ_t‖²
//   dof       d_t = 3 (Σ w_i − Σ w_i² / Σ w_i)     (equal weights: 3 (n_t − 1))
// A weight is a reliability: an oblique or distant view, whose pixel integrates more surface
// than one texel, counts less (§6.3), and so does a view whose image is steep where the
// texel lands, since a projection uncertain by δ pixels (calibration, rasterisation,
// anti-aliasing) adds about (δ·|∇I|)² of colour error: w_i = w_geometry / (1 + (δ|∇I|/σ)²).
// d_t is the expectation of s_t / σ² when every view carries noise σ, whatever the
// weights, so the χ² correction below stays calibrated: with d_t = 3(n_t − 1) and weights
// below 1, S/σ² would fall short of N and every visible texel would look like a reward.
// A texel's contribution is capped at `robust_cap` per degree of freedom, so a few
// outliers (specularities, anti-aliased silhouettes) cannot dominate.

#include <cstdint>
#include <string>

namespace vkr {

// The scalars a GPU reduction produces for one hypothesis (also what the CPU reference
// computes). Colours are on the [0,1] scale.
struct ReducedScalars {
  double sum_squares = 0.0;   // Σ_t min(s_t / σ², cap · d_t) · σ² over texels with n_t ≥ 2
  double dof = 0.0;           // Σ_t d_t (effective degrees of freedom)
  uint32_t seen_multi = 0;    // exterior texels seen by ≥ 2 views
  uint32_t seen_once = 0;     // exterior texels seen by exactly 1 view
  uint32_t seen_none = 0;     // exterior texels seen by no view
  uint32_t interior = 0;      // texels inside (or on the boundary of) another primitive
};

struct LikelihoodModel {
  double sigma = 8.0;          // noise sd on the 0–255 scale
  bool chi2_correction = true; // §7.4: compare S/σ² with its expectation N
  double robust_cap = 9.0;     // per-dof cap of a texel's s_t/σ² (∞ disables)
  // §7.1: log-prior penalty per exterior texel no view sees, in units of one degree of
  // freedom's expected contribution (so 1.5 ≈ a texel seen by two views that disagree
  // by one σ). Surface hidden from every camera is not free.
  double unseen_penalty = 1.0;
};

struct Evaluation {
  ReducedScalars scalars;
  double log_likelihood = 0.0;     // with or without the χ² correction, per the model
  double log_occlusion_prior = 0.0;
  // log_likelihood + log_occlusion_prior: what the sampler adds to the parameter prior.
  double total() const { return log_likelihood + log_occlusion_prior; }
};

// S/σ²/N at σ (0–255 scale): 1 when the views disagree exactly as much as noise σ makes
// them; NaN without degrees of freedom.
double Chi2PerDof(const ReducedScalars& scalars, double sigma_255);

// −½ (S/σ² − N) with the correction, −½ S/σ² without; σ converted from the 0–255 scale.
Evaluation Score(const ReducedScalars& scalars, const LikelihoodModel& model);

}  // namespace vkr
