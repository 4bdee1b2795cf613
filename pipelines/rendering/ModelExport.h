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
#include "pipelines/model/Photometric.h"

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

// One camera's reprojection: its files, and how far the model textured with the composite
// is from the photograph where it covers it.
struct Reprojection {
  std::string camera;
  std::filesystem::path file, residual_file;
  double rms_255 = 0.0;       // RMS over covered pixels and channels, 0–255 scale
  int64_t pixels = 0;         // covered by the model
  double outlier_share = 0.0; // of those, pixels whose residual exceeds 3 sds (RMS over channels) of the
                              // photograph's own robust scale
};

// The noise model the residuals are measured against, and each camera's colour correction
// (the composite holds corrected colours; the reprojection undoes a camera's correction so
// it compares with that photograph as stored).
struct ReprojectionNoise {
  double sigma_255 = 8.0;
  double position_sd = 0.5;                  // δ, pixels: noise σ² + δ²|∇I|²
  PhotometricCorrection photometric;         // empty: the identity
  std::vector<Image> clutter;                // per camera, 0 where clutter was masked (empty: none)
};

// Per camera, `DIR/<camera>.png`: reference | synthetic (the model textured with `atlas`) |
// |difference| ×4, side by side; and `DIR/<camera>_residual.png`: per pixel the residual's χ²
// per channel under `noise`, scaled so that its median is χ²₃'s (the photograph's own robust
// scale: the textured model is blurrier than a photograph), on the deviation ramp (blue 0,
// green 1, yellow 2, red ≥ 4), the photograph dimmed where the model does not reach and
// tinted magenta where it was masked as clutter (ClutterMasks.h; those pixels not counted).
std::vector<Reprojection> WriteReprojections(const std::filesystem::path& dir, vk::Device& device,
                                             const Scene& scene, const SceneGeometry& geometry,
                                             const std::vector<double>& psi, const Image& atlas,
                                             const ReprojectionNoise& noise);

}  // namespace vkr
