#pragma once
// κ from the noise alone (docs/internals/LIKELIHOOD.md, "Honest intervals"). The surface
// likelihood treats every atlas texel as an independent sample, but a texel's colour is a
// photograph resampled: where the atlas holds more texels than a view has pixels, one
// pixel's noise reaches several neighbouring texels, and the log-likelihood counts it that
// many times. For noise correlated between texels with correlation ρ(lag), the score's
// variance is the curvature times Σ_lag ρ(lag) (its spatial structure being smooth over the
// lags that matter), so that sum is the κ that makes the intervals match the noise.
//
// The block sandwich (NoiseCalibration.h) measures the per-texel score's whole variability,
// and on photographs the scene explains exactly that is dominated by its deterministic part
// (texels switching views and visibility as the surface moves), which cancels at the mode:
// κ 60–87 on noise-free renders, where the errors call for 2–5. This estimate looks at the
// residuals themselves: each view's deviation from the consensus, standardised by the noise
// model, correlated with itself at small lags in the atlas.

#include <vector>

#include "engine/image/Image.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/model/Photometric.h"

namespace vkr {

struct SurfaceDump;

struct NoiseCorrelationEstimate {
  double kappa = 1.0;           // Σ ρ over the lags |dx|, |dy| ≤ radius, floored at 1
  int radius = 0;               // texels
  double samples = 0.0;         // residuals (view × texel × channel) that entered it
  std::vector<double> rings;    // per Chebyshev distance 0…radius: the mean ρ at that distance
};

// Per view, its standardised residuals (rgb: one per channel; a: 1 where the view counts).
// ρ(lag) pools every view and channel over the pairs of texels both counted; κ = Σ ρ over
// the (2·radius + 1)² lags, floored at 1 (noise cannot be anticorrelated on average).
NoiseCorrelationEstimate ResidualCorrelation(const std::vector<Image>& residuals, int radius);

// Camera `view`'s standardised residual at texel (x, y) of a dump, per channel, into `e`:
// (corrected colour − consensus) / the noise model's sd. Returns e² (summed over the
// channels), or a negative number where the view does not see the texel or no other view does.
double StandardisedResidual(const SurfaceDump& dump, int view, int x, int y, const LikelihoodModel& model,
                            const PhotometricCorrection& photometric, double e[3]);

// The standardised residuals of one evaluation, per camera: (corrected colour − consensus) /
// the noise model's sd, where the view sees a texel that at least one other view sees too,
// and is not an outlier of the composite there (the robust loss caps those; clutter masks
// have removed what they cover already).
std::vector<Image> StandardisedResiduals(const SurfaceDump& dump, const LikelihoodModel& model,
                                         const PhotometricCorrection& photometric);

// The lags that resampling correlates: bilinear reads of views with up to ~3 texels per pixel.
inline constexpr int kNoiseCorrelationRadius = 6;

}  // namespace vkr
