#pragma once
// What a reconstruction leaves behind besides numbers: the composite texture, a textured
// glTF model of the fitted primitives, and reprojections that show where the model and the
// photographs disagree (thesis Figs 4.18, 7.21).

#include <filesystem>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"

namespace vkr {

// Fills texels off every chart (alpha 0) from their covered neighbours, `iterations` texels
// deep, so bilinear filtering at chart borders does not pull in black. Covered texels keep
// their colour; alpha becomes 1 wherever a colour was written.
Image DilateAtlas(const Image& atlas, int iterations = 4);

// A binary glTF 2.0 file: one node and mesh per scene node with a primitive, vertices in
// world space at Ψ (Z-up turned into glTF's Y-up), texture coordinates into `atlas`,
// embedded as PNG, on an unlit material (KHR_materials_unlit) so viewers show the photo
// colours as they are. Opens in Blender (File › Import › glTF 2.0). Throws InputError if
// the file cannot be written.
void WriteTexturedGlb(const std::filesystem::path& file, const Scene& scene, const SceneGeometry& geometry,
                      const std::vector<double>& psi, const Image& atlas);

// One camera's reprojection: its file, and how far the model textured with the composite
// is from the photograph where it covers it (RMS over pixels and channels, 0–255 scale).
struct Reprojection {
  std::filesystem::path file;
  double rms_255 = 0.0;
  int64_t pixels = 0;  // covered by the model
};

// Per camera, `DIR/<camera>.png`: reference | synthetic (the model textured with `atlas`) |
// |difference| ×4, side by side.
std::vector<Reprojection> WriteReprojections(const std::filesystem::path& dir, vk::Device& device,
                                             const Scene& scene, const SceneGeometry& geometry,
                                             const std::vector<double>& psi, const Image& atlas);

}  // namespace vkr
