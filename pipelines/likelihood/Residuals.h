#pragma once
// Where the photographs disagree with a hypothesis, node by node: a fit whose residuals
// look like noise everywhere is credible; one where a node's views disagree far beyond the
// noise, or where many views are outliers, says which part of the scene is wrong or missing
// (docs/internals/LIKELIHOOD.md, "Diagnosis"). Read from a surface-likelihood dump.

#include <filesystem>
#include <string>
#include <vector>

#include "engine/geometry/Atlas.h"
#include "engine/scene/Scene.h"
#include "engine/image/Image.h"

namespace vkr {

struct NodeResidual {
  std::string node;
  int texels = 0;          // exterior surface texels of the node's charts
  int compared = 0;        // of those, seen by ≥ 2 views
  int seen_once = 0, seen_none = 0;
  int masked = 0;          // fewer than two views compare it only because of masks
  double chi2 = 0.0;       // Σ χ_t over the compared texels
  double expected = 0.0;   // Σ d_t: what noise alone gives
  int views = 0;           // view samples of the compared texels
  int outlier_views = 0;   // of those, outliers of the robust consensus

  double Chi2PerDof() const { return expected > 0.0 ? chi2 / expected : 0.0; }
  double OutlierShare() const { return views > 0 ? double(outlier_views) / views : 0.0; }
};

// One entry per node with a primitive, in scene order, from a surface evaluation's deviation
// and noise images (SurfaceDump; of any pyramid level: the atlas layout is scaled to their
// size). Throws std::invalid_argument when their sizes differ.
std::vector<NodeResidual> NodeResiduals(const Scene& scene, const AtlasLayout& atlas, const Image& deviation,
                                        const Image& noise);

// The same over all nodes together.
NodeResidual TotalResidual(const std::vector<NodeResidual>& nodes);

// CSV, classic locale: node,texels,compared,seen_once,seen_none,masked,chi2,expected,chi2_per_dof,
// views,outlier_views,outlier_share; one row per node, then "all".
void WriteNodeResidualsCsv(const std::filesystem::path& file, const std::vector<NodeResidual>& nodes);

}  // namespace vkr
