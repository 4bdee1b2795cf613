#pragma once
// Image pyramids for coarse-to-fine likelihoods (thesis §7.3;
// docs/internals/LIKELIHOOD.md, "Prefiltering"; docs/internals/SAMPLER.md, stage 2): coarse
// levels smooth the plateaus of the likelihood, so a run starts on them.
//
// Geometry of a level. Level l has size PyramidLevelSize(n, l) = ceil(n / 2^l) per axis,
// and its pixel (i, j) covers the base-image pixels 2^l·i … 2^l·(i+1) − 1 (likewise j):
// under the [0,W]×[0,H] pixel convention (pixel centres at +0.5, docs/guide/SCENE_FORMAT.md,
// "cameras"), a point at base-image coordinate x lies at x / 2^l in level l. A camera's intrinsics
// for level l are therefore S·K with S = diag(2^-l, 2^-l, 1) — no half-pixel offset. When n is not
// a multiple of 2^l the last row/column of a level reaches past the base image; it holds the
// clamped edge, like a GPU sampler with CLAMP_TO_EDGE.

#include <vector>

#include "engine/image/Image.h"

namespace vkr {

// Size of one axis at pyramid level `level` (>= 0) for a base of `n` pixels: ceil(n/2^level),
// and never below 1.
int PyramidLevelSize(int n, int level);

// `levels` images (levels >= 1; std::invalid_argument otherwise, and for an empty base).
// Level 0 is a copy of `base`; each further level is the previous one blurred and halved:
// a separable 6-tap binomial filter [1 5 10 10 5 1]/32 (σ ≈ 1.1 texels of the finer level,
// enough to suppress aliasing) centred between fine texels 2i and 2i+1, so the coarse texel
// centre lands exactly where S·K above puts it. An odd-length filter centred on texel 2i
// (the textbook [1 4 6 4 1]/16 + "take every other texel") would shift every coarse level
// by a quarter of its texel against S·K. All four channels are filtered alike, edges
// clamped; a constant image stays constant and the mean is kept up to edge effects.
std::vector<Image> BuildPyramid(const Image& base, int levels);

// One step of BuildPyramid: blur and halve (size ceil(w/2) × ceil(h/2)).
Image Downsample2x(const Image& fine);

// Box filter by an integer factor f: size floor(w/f) × floor(h/f) (at least 1), each pixel the
// mean of the f × f it covers (edges clamped where the image is smaller than f). The
// remainder at the right and bottom is cropped, so a point at x lies at x / f, as above.
Image BoxShrink(const Image& image, int factor);

// Replaces alpha with the image's gradient magnitude, quantised to 8 bits:
// min(1, sqrt(⅓ Σ_c (∂I_c/∂x)² + (∂I_c/∂y)²)) with central differences (one-sided at the
// border), in colour units per pixel. The likelihood's noise model turns it into colour
// uncertainty: a projection off by δ pixels changes the colour by about δ·|∇I|.
void StoreGradientInAlpha(Image& image);

}  // namespace vkr
