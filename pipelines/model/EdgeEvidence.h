#pragma once
// The edge term's statistic (docs/internals/LIKELIHOOD.md, "Edges"). Where the model says an
// occluding contour or a crease lies, the photograph should change colour across it; where it
// says none lies, the colour should go on. Per sample along a visible model edge, the colour
// difference Δ between the photograph just inside and just outside (one pixel of the level
// apart) is scored as a log-likelihood ratio of "an edge is here" over "no edge is here":
//   no edge  p₀(Δ) = (1−ε) N(Δ; 0, v) + ε U   noise v per channel, or with chance ε any
//                                             difference (texture, edges the scene leaves out)
//   edge     p₁(Δ) = (1−η) U + η p₀(Δ)        any difference, or with chance η none (a
//                                             background of the surface's colour)
// U = 1 is the uniform density over differences on the [0,1] colour scale. The ratio lies in
// [log η, log((1−η+ηε)/ε)]: one sample can neither veto a hypothesis nor carry it, and a model
// edge over plain background costs about log η per pixel of its length. ε is measured per
// photograph and level (the share of neighbouring pixel pairs whose difference noise cannot
// explain), η is fixed.

#include <Eigen/Core>
#include <vector>

#include "engine/image/Image.h"

namespace vkr {

struct EdgeModel {
  // η: the chance that a true model edge shows no contrast in a photograph.
  double hidden = 0.2;
  // Bounds on ε, measured per photograph: never certain that a difference is an edge, and
  // never so textured that edges stop counting.
  double min_clutter = 0.01, max_clutter = 0.5;
};

// log p₁(Δ)/p₀(Δ) for a difference `delta` (3 channels, [0,1] scale) with noise variance
// `variance` per channel ([0,1]² scale), clutter share ε and hidden share η.
double EdgeLogRatio(const Eigen::Vector3d& delta, double variance, double clutter, double hidden);

// |Δ|² beyond which noise of variance `variance` per channel explains a difference less well
// than a uniform one does (N(Δ; 0, v) < U), and that fewer than 1 % of noise-only pairs pass:
// the edge term's notion of "a contrast".
double ContrastThreshold(double variance);

// The squared differences of neighbouring pixels (right and below; both inside `validity`
// where it is not empty) of one image, or of every n-th pixel of a large one, sorted,
// subsampled to at most `keep`: enough to tell the share of pairs beyond any threshold.
class PairContrasts {
 public:
  PairContrasts() = default;
  PairContrasts(const Image& image, const Image& validity, size_t keep = 20000);
  // The share of pairs whose |Δ|² exceeds `threshold` (0 without pairs).
  double ShareAbove(double threshold) const;
  size_t size() const { return sorted_.size(); }

 private:
  std::vector<float> sorted_;
};

// ε for one photograph at one level: the share of its neighbouring pixel pairs with a contrast
// (ContrastThreshold of the pair's noise `variance`), clamped to the model's bounds.
double ClutterShare(const PairContrasts& pairs, double variance, const EdgeModel& model);

}  // namespace vkr
