#pragma once
// What the photographs show that the scene leaves out (docs/internals/LIKELIHOOD.md, "Clutter"): an
// annex, a chimney, a person, a parked car. The robust composite already bounds what one
// such view costs a texel, but not what a hypothesis gains by hiding it — growing surface
// over the ground an annex stands on, or in front of the views it spoils, removes those
// views from the comparison. So at the mode a run settles on, the views that are outliers
// of the composite are drawn back into their photographs, and where they form regions (not
// the thin lines that misregistered edges leave) those pixels are masked from then on, like
// a user's mask (ReferenceImages.h). A mask belongs to the photograph, not to the surface:
// whatever hypothesis samples a masked pixel, it is not evidence.

#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
namespace vkr {

class SurfaceLikelihood;

struct ClutterOptions {
  // A view whose squared deviation from the consensus exceeds this many times K (the
  // loss's saturation, LikelihoodModel::outlier_chi2) is an outlier.
  double outlier_factor = 1.0;
  int majority_radius = 3;  // pixels: outliers that fill most of a (2r+1)² window are a region
  int grow = 2;             // pixels added around a region (its blurred border)
};

struct ClutterMasks {
  std::vector<Image> masks;   // per camera, its image's size: rgb 1 = compare, 0 = clutter (alpha 1)
  std::vector<double> share;  // per camera: the share of the pixels the model covers that are masked
};

// At hypothesis ψ, with the likelihood's noise model and colour correction, ignoring the
// clutter masks it may already have (level 0; the likelihood's level is kept).
ClutterMasks FindClutter(vk::Device& device, SurfaceLikelihood& likelihood, const std::vector<double>& psi,
                         const ClutterOptions& options = {});

}  // namespace vkr
