#pragma once
// The noise model's nuisance parameters, estimated at the mode a run settles on
// (docs/internals/LIKELIHOOD.md, "Honest intervals"). Three things make the textbook likelihood
// wrong or overconfident on photographs:
//   - the photographs' exposure and white balance differ: the per-camera colour correction
//     (Photometric.h) is refitted at the mode;
//   - σ and δ: the configured noise may not be the images' (`"sigma": "auto"` estimates
//     both: the noise per channel is σ² + δ²|∇I|² (Evaluation.h), and at the mode the
//     deviations must be exactly as large as expected, χ = N, both over all texels and
//     over the textured ones, weighted by the share of their noise the texture makes).
//     This balances the χ² correction, which is calibrated only when χ ≈ N, and it keeps
//     the textured surface (relief, fine detail the atlas cannot hold) from setting the
//     noise of plain surface, where a misplaced edge would then look like noise;
//   - κ: neighbouring atlas texels are not independent samples (bilinear and mip-filtered
//     reads share pixels, and whatever the model does not explain — resampling, shading,
//     blur, calibration — is smooth across the surface), so the curvature H of the
//     log-likelihood overstates the evidence. The block sandwich (Huber–White) estimator
//     measures the real variability of the score: J = Σ_b G_b G_bᵀ, G_b the gradient of
//     the log-likelihood summed over a block of texels, from per-texel deviations at
//     ψ ± one sd of each parameter (SandwichOverBlocks: blocks of a given side, or with
//     "auto" the side that gives the largest κ). The robust covariance is H⁻¹ J H⁻¹; the log-likelihood
//     is divided by κ = tr(H⁻¹J)/d (a magnitude adjustment), so the posterior the chains
//     sample has that covariance on average over directions. κ does not depend on σ (J
//     scales as σ⁻⁴, H as σ⁻²): intervals follow the deviations actually found.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipelines/likelihood/Likelihood.h"

namespace vkr {

// H⁻¹J has eigenvalues of at least about 1 when texels are positively correlated, as
// neighbouring texels are; one below this means the curvature H measured at the mode was
// too large (the likelihood is rough at one posterior sd: 8-bit views, rasterisation) and
// κ too small. ToJson says so ("curvature_doubtful") and the run's diagnosis then doubts the
// intervals.
constexpr double kMinSandwichEigenvalue = 1.0;

struct NoiseCalibration {
  double sigma = 8.0;            // noise sd on the 0–255 scale, used after calibration
  double position_sd = 0.5;      // δ, pixels: the noise's texture term
  bool sigma_estimated = false;  // σ and δ estimated (`sigma: auto`) rather than given
  double kappa = 1.0;            // the log-likelihood is divided by it
  double kappa_min = 1.0, kappa_max = 1.0;  // eigenvalue range of H⁻¹J (a report)
  int blocks = 0;                // blocks of texels that carried a gradient
  int block = 8;                 // texels per side of those blocks (SandwichOverBlocks)
  double chi2_per_dof = 0.0;     // S/σ²/N at the mode with the σ above
  // κ from the noise alone (NoiseCorrelation.h): Σ ρ of the residuals at small lags, and ρ
  // per ring of lags; what `likelihood.kappa: "noise"` divides by. Measured with the sandwich
  // (a curvature given), so a run reports it whichever κ it samples with.
  double kappa_noise = 1.0;
  std::vector<double> noise_rings;
  // The curvature adjustment (SandwichAdjustment.h), when asked for and J could be measured:
  // A = H J⁻¹ H and H (d × d row-major; empty: the magnitude adjustment alone), the mode ψ*
  // they are centred on, and the log-likelihood + occlusion prior there, undivided.
  std::vector<double> adjusted_curvature, raw_curvature, adjustment_centre;
  double centre_total = 0.0;
  bool CurvatureAdjusted() const { return !adjusted_curvature.empty(); }
  nlohmann::json photometric;    // the per-camera colour correction (Photometric.h), or null
  // What the photographs show that the scene leaves out, masked from then on (ClutterMasks.h;
  // not in ToJson: images travel as files, recon/LikelihoodTarget.h keeps them).
  ClutterMasks clutter;

  bool CurvatureDoubtful() const { return kappa_min < kMinSandwichEigenvalue; }
};

// Blocks too small for the residuals' correlation count one correlated region as many
// independent ones: J, and with it κ, comes out too small by about the number of blocks per
// region. Where the scene leaves something out (an annex, a relief, a lighting the model
// lacks) the residuals are correlated over whole faces, far beyond the 2–3 texels that
// resampling correlates. Larger blocks are unbiased but noisier (fewer of them). "auto" (the
// default of `likelihood.sandwich_blocks`) takes the largest κ over these sides among those
// that still leave enough blocks, erring toward width: on house_annex over three seeds 13 of
// 21 truths held against 5 of 21 over 8×8 blocks, while the clean bundled assets' intervals
// widen too, some far beyond their errors (docs/internals/LIKELIHOOD.md, "Honest intervals").
inline constexpr int kSandwichBlockSides[] = {8, 16, 32, 64};
inline constexpr int kSandwichBlocksAuto = 0;

struct BlockSandwich {
  double kappa = 1.0;                       // tr(H⁻¹J)/d
  double kappa_min = 1.0, kappa_max = 1.0;  // eigenvalue range of H⁻¹J
  int blocks = 0;                           // blocks that carried a gradient
  int block = 8;                            // texels per side
  std::vector<double> j;                    // J over those blocks (d × d row-major)
};

// `gradient`: per parameter, per texel (row-major, `width` wide) the score ∂ log L_t/∂ψ_i;
// `inverse_h`: H⁻¹ (d × d row-major). The block sandwich over blocks of `side` texels; for
// kSandwichBlocksAuto, at each of kSandwichBlockSides with at least 2d blocks (the
// smallest side) or 4d (the others), and the largest κ of them. κ = 1 when the first side
// tried leaves fewer than 2d blocks; nullopt when the sizes disagree. `summed`: blocks of
// the score already summed (d values each; the edge term's per camera and edge), added to
// J and to the count at every side.
std::optional<BlockSandwich> SandwichOverBlocks(const std::vector<std::vector<double>>& gradient, int width,
                                               const std::vector<double>& inverse_h,
                                               int side = kSandwichBlocksAuto,
                                               const std::vector<std::vector<double>>& summed = {});

nlohmann::json ToJson(const NoiseCalibration& calibration);
NoiseCalibration NoiseCalibrationFromJson(const nlohmann::json& json);  // throws std::invalid_argument
// The κ of a calibration as ToJson wrote it (a run's summary), 1 where there is none: what
// divides the log-likelihood to score a point as that run did.
double KappaFromJson(const nlohmann::json& calibration);

// At ψ (level 0): the colour correction; σ and δ by fixed-point iteration of the two moment
// conditions when `estimate_sigma` (left set in the likelihood), σ floored at
// `sigma_floor`; the clutter masks (when `mask_clutter`: found anew, the last ones cleared
// first, so that calibrating again at ψ finds the same), then σ and δ again without it;
// then κ. The floor matters on noise-free images: there 8-bit quantisation
// and the views' different resampling set the deviations (σ̂ ≈ 0.7 on `house`), the robust
// loss then turns every edge into an outlier, and hiding surface pays — at σ = 0.7 a house
// 8 % too large outscored the truth; from σ = 2 on the truth wins clearly. `covariance` (d × d row-major) is the
// inverse curvature of log L / `current_kappa` at ψ with the σ the likelihood had; an empty
// one, or a likelihood whose dumps carry no deviation image (image-space kind), leaves κ = 1
// (and κ from the noise, measured only with the sandwich).
// `curvature_adjustment`: the sandwich's curvature adjustment as well, centred on ψ
// (`covariance` must then be the raw log-likelihood's: `current_kappa` 1).
NoiseCalibration CalibrateNoise(Likelihood& likelihood, const std::vector<double>& psi,
                                const std::vector<double>& covariance, double current_kappa,
                                bool estimate_sigma, bool mask_clutter, int sandwich_blocks = kSandwichBlocksAuto,
                                double sigma_floor = 2.0, bool curvature_adjustment = false);

}  // namespace vkr
