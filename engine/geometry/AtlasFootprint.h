#pragma once
// `"atlas": "auto"` and `"levels": "auto"` (docs/guide/SCENE_FORMAT.md, "likelihood"): the atlas
// is sized from what the cameras see of the surface, so a scene written without settings
// gets the resolution its photographs support rather than a fixed 1024² that costs hours on
// a CPU device and holds detail no view resolves.
//
// The rule: every face of the scene at its initial values needs as many texels as the
// pixels it covers in the camera that sees it largest (front-facing, in front of the camera,
// clipped to the image), divided by kPixelsPerTexel; the atlas side is the power of two
// nearest to √(that sum / kPackingShare), within [64, 2048]. Levels: as many halvings as
// keep the coarsest atlas at least 64 texels wide, at most 3.

#include <vector>

#include "engine/geometry/Mesh.h"
#include "engine/scene/Scene.h"

namespace vkr {

// One texel per 2 × 2 pixels: the bundled assets, reconstructed at 640 × 480 with 256² atlases
// (docs/internals/NOISE_STUDY.md), land at 256 by this rule. A finer atlas samples the views' own
// interpolation, a coarser one averages away the edges that locate the surface.
constexpr double kPixelsPerTexel = 4.0;
// Share of the atlas the packer fills with charts (Atlas.h adds gutters and shelf waste).
constexpr double kPackingShare = 0.5;
constexpr int kMinAutoAtlas = 64, kMaxAutoAtlas = 2048;

// Pixels of each face (in (node, face) order) in the view that sees it largest, at `psi`:
// the part in front of the camera, projected and clipped to the image (occlusion ignored).
std::vector<double> FacePixels(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi);
// What the sizing rule above sums at the initial values: the same, but counting nothing of
// a triangle with a corner behind a camera and clipping by bounding box, as when its
// constants were fitted.
double SurfaceFootprintPixels(const Scene& scene, const std::vector<Mesh>& meshes);

// ChartSizing::Pixels (likelihood.charts "pixels"): each face's density for PackAtlas (Atlas.h), such that its
// texels are in proportion to its FacePixels at `psi` — √(pixels / area) texels per metre,
// up to the common scale the packer fits. A face that covers few pixels at `psi` (seen
// edge-on, hidden behind a camera) is kept at no less than a quarter of the density that
// spreads all the pixels evenly over all the surface, so that a hypothesis turning it
// towards a camera still finds texels there.
std::vector<double> ChartDensities(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi);

// The rule above for a footprint of `pixels`.
int AutoAtlasSide(double pixels);
int AutoLevels(int atlas_side);

}  // namespace vkr
