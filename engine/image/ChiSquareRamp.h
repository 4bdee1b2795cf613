#pragma once
// The one colour scale for "how far beyond the noise": a χ² per degree of freedom through
// dark blue (0) → green (1, what noise alone gives) → yellow (2) → red (≥ 4). Used by the
// likelihood's deviation dumps and by the residual images of a reconstruction.

namespace vkr {

// Encoded RGB of χ²/dof `v` (clamped to [0, 4]).
void ChiSquareRamp(double v, float rgb[3]);

}  // namespace vkr
