#pragma once
// The texture atlas: every face of every node gets a rectangular chart, sized in
// proportion to the face's world-space extent at the initial parameters (times a density of
// its own where the scene asks for likelihood.charts "pixels"), and the layout does not
// change during a run (docs/internals/LIKELIHOOD.md, "Charts").

#include <Eigen/Core>
#include <vector>

#include "engine/geometry/Mesh.h"
#include "engine/image/Image.h"

namespace vkr {

// A chart's place in the atlas, in texels; the face's face_uv ∈ [0,1]² maps linearly onto
// [x, x+w]×[y, y+h]. A gutter of texels surrounds every chart so bilinear filtering never
// mixes two faces.
struct Chart {
  int node = 0, face = 0;
  float x = 0, y = 0, w = 0, h = 0;
  double texels_per_metre = 0.0;  // this chart's scale: one full-resolution texel is 1/this metres
};

struct AtlasLayout {
  int size = 0;                        // atlas is size × size texels
  std::vector<Chart> charts;           // one per (node, face) with a primitive, in (node, face) order
  double texels_per_metre = 0.0;       // the scale of a chart of density 1 (all of them without densities)
  int gutter = 2;                      // texels kept free around every chart (PackAtlas)

  // Atlas UV (in [0,1]²) of a face_uv inside chart `c`.
  Eigen::Vector2f AtlasUv(const Chart& c, const Eigen::Vector2f& face_uv) const;
};

// Packs the faces of `meshes` (one per node, empty for nodes without a primitive) whose
// world matrices at the initial parameters are `world_from_node`. Chart sides are
// proportional to the faces' world extents along face_uv's u and v times the face's entry
// of `density` (one per face in (node, face) order, > 0; empty: 1 for every face), at least
// a few texels, scaled as large as fits into size² with `gutter` texels around each chart.
AtlasLayout PackAtlas(const std::vector<Mesh>& meshes,
                      const std::vector<Eigen::Matrix4d>& world_from_node, int size,
                      int gutter = 2, const std::vector<double>& density = {});

// Paints each node's albedo image into its charts (texels outside every chart stay 0,
// alpha 0; texels inside get alpha 1), then bleeds chart borders into their gutters.
// `albedo[n]` empty means mid grey. The result is in the encoded colour space.
// Alpha: 1 for texels covered by a face, 0.5 for gutter texels filled by the bleeding
// (layout.gutter rounds of averaging 4-neighbours), 0 for texels no chart reaches.
Image BakeAlbedoAtlas(const AtlasLayout& layout, const std::vector<Mesh>& meshes,
                      const std::vector<Image>& albedo);

}  // namespace vkr
