#pragma once
// What a likelihood reduces one hypothesis to, and how the host turns those few scalars
// into a log-likelihood (thesis §7.4;
// docs/internals/LIKELIHOOD.md, "The statistic", explains every choice).
//
// The surface likelihood's model, per atlas texel t on the surface and outside every other
// primitive, seen by views i with colour c_i (photometrically corrected, c = gain·c_raw +
// offset per view and channel, Photometric.h) and weight w_i ∈ (0, 1] (§6.3: an oblique or
// distant view, whose pixel integrates more surface than one texel, counts less):
//   noise     v_i = σ²/m_i + δ²|∇I_i|² per channel: σ is a photograph pixel's noise and the
//             prefiltered sample averages m_i ≥ 1 full-resolution pixels; a projection
//             uncertain by δ pixels (calibration, resampling, relief a flat face cannot show)
//             turns into colour error through the image's local texture, so textured surface
//             does not set the noise of plain surface
//   consensus μ_t = Σ ω_i p_i c_i / Σ ω_i p_i, p_i = w_i / v_i, with Welsch weights
//             ω_i ∝ e^(−e²_i/K) refitted a few times (e²_i = ‖c_i − μ_t‖²/v_i): a view
//             far from the others' consensus (an occluder the scene lacks) stops pulling it
//   loss      χ_t = Σ w_i ρ(e²_i), ρ(e²) = K (1 − e^(−e²/K)): quadratic for small
//             deviations, at most K for an outlier view, so one view cannot dominate; and
//             at most d_t + K·mean(w_i) for the texel: views that all disagree are one event
//             (something the scene lacks covers the texel), not many
//   expected  d_t = E[χ_t] under the noise model alone (the effective degrees of freedom;
//             for K → ∞ it is 3(Σ w_i − Σ w_i p_i / Σ p_i), and 3(n_t − 1) for equal weights)
// The χ² correction compares χ_t with d_t, so surface whose views agree as well as noise
// allows is neutral, whatever the number of views that see it.

#include <cstdint>
#include <string>

namespace vkr {

// The scalars a GPU reduction produces for one hypothesis (also what the CPU reference
// computes). Colours are on the [0,1] scale.
struct ReducedScalars {
  double sum_squares = 0.0;   // S = σ² Σ_t χ_t over texels with n_t ≥ 2 (so S/σ² is the χ²)
  double dof = 0.0;           // N = Σ_t d_t, the χ²'s expectation under the noise model
  uint32_t seen_multi = 0;    // exterior texels seen by ≥ 2 views
  uint32_t seen_once = 0;     // exterior texels seen by exactly 1 view (masks aside)
  uint32_t seen_none = 0;     // exterior texels seen by no view (masks aside)
  uint32_t masked = 0;        // exterior texels fewer than two views compare only because of masks
  uint32_t interior = 0;      // texels inside (or on the boundary of) another primitive
  uint32_t views = 0;         // view samples of the texels seen by ≥ 2 views
  uint32_t outlier_views = 0; // of those, views with e² > K (their loss is mostly saturated)
  // Σ over texels exactly one view sees of that view's saturated loss w·K: what it would
  // cost were it an outlier (the occlusion prior charges it, "No free surface").
  double unverified = 0.0;
};

struct LikelihoodModel {
  double sigma = 8.0;          // σ: noise sd on the 0–255 scale
  double position_sd = 0.5;    // δ in pixels (surface likelihood; 0 turns the texture term off)
  bool chi2_correction = true; // §7.4: compare S/σ² with its expectation N
  // K, the surface likelihood's per-view χ² (3 channels) at which the loss saturates:
  // a view 3σ off in every channel (e² = 27) is mostly an outlier.
  double outlier_chi2 = 27.0;
  double robust_cap = 9.0;     // image likelihood: per-dof cap of a pixel pair's χ²
  // §7.1: log-prior penalty per exterior texel that no view sees, in units of one degree of
  // freedom's expected contribution: surface hidden from every camera is not free. (Not K,
  // like a texel one view sees: surface that other surface hides from every camera, such as
  // a ground plane behind walls, would then push the walls about; docs/internals/LIKELIHOOD.md.)
  double unseen_penalty = 1.0;
  // Factor on `unverified`: a texel only one photograph sees cannot be checked, so it is
  // charged what its view would cost as an outlier, −½·w·K: no surface gains by moving
  // where only one camera looks, since no compared texel costs more than an average view's
  // saturation beyond its expectation (docs/internals/LIKELIHOOD.md, "No free surface"). 0 turns
  // the charge off.
  double unverified_penalty = 1.0;
};

struct Evaluation {
  ReducedScalars scalars;
  double log_likelihood = 0.0;     // with or without the χ² correction, per the model
  double log_occlusion_prior = 0.0;
  // The edge term (EdgeEvidence.h), 0 where it is off: Σ over the cameras' visible model edges
  // of the log-ratio "an edge is here" over "none is", and the length it was scored over
  // (level pixels).
  double log_edges = 0.0;
  double edge_length = 0.0;
  // log_likelihood + log_edges + log_occlusion_prior: what the sampler adds to the parameter
  // prior.
  double total() const { return log_likelihood + log_edges + log_occlusion_prior; }
};

// S/σ²/N at σ (0–255 scale): 1 when the views disagree exactly as much as noise σ makes
// them; NaN without degrees of freedom.
double Chi2PerDof(const ReducedScalars& scalars, double sigma_255);

// −½ (S/σ² − N) with the correction, −½ S/σ² without; σ converted from the 0–255 scale.
Evaluation Score(const ReducedScalars& scalars, const LikelihoodModel& model);

}  // namespace vkr
