#pragma once
// `vkrecon synth` and `vkrecon render` as typed functions the command line and the tests
// both call: a scene at parameters Ψ, drawn with the novel-view pass.

#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"

namespace vkr {

struct SynthOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::filesystem::path at_file;     // parameter values ({"name": value})
  std::filesystem::path output_dir;  // receives one PNG per camera and cameras.json
  double noise_sigma = 0.0;          // Gaussian noise sd on the 0–255 scale (§4.5.1)
  uint64_t seed = 1;                 // noise seed
  double scale = 1.0;                // image size factor (K scales with it); tests use small images
  int atlas = 2048;                  // albedo atlas side: sharper than a run's, it is the "truth"
  // Photograph-like rendering; each unset field comes from the scene's `synth` block.
  std::optional<bool> sun;                   // light with a sun (and cast shadows), or not
  std::optional<double> sun_azimuth, sun_elevation, ambient;
  std::optional<double> exposure;            // spread of the cameras' exposures (Exposure.h)
  std::optional<int> supersample;            // samples per pixel along each axis
  // A lens given to every camera (replacing its own), written to cameras.json; the images are
  // rendered through it (LensWarp.h). Tests and studies make distorted photographs this way.
  std::optional<LensDistortion> distortion;
  // Nodes whose visible pixels are masked out: writes masks/<image name>.png beside the
  // output folder (where LoadScene looks for a scene whose `images` is that folder).
  std::vector<std::string> mask_nodes;
  // Also write the cameras as a COLMAP text model in output_dir/sparse/.
  bool colmap = false;
};

struct SynthSummary {
  std::vector<std::filesystem::path> images;
  std::filesystem::path cameras_file;
  std::filesystem::path exposure_file;  // exposure.json, when the exposures differ
  std::vector<std::filesystem::path> masks;  // with mask_nodes
  std::filesystem::path colmap_dir;          // with colmap
};

SynthSummary SynthesiseImages(const SynthOptions& options, vk::Device& device);

struct RenderOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::optional<std::filesystem::path> at_file;  // default: the scene's initial values
  // An atlas texture (composite.exr of a run). Without one the albedo textures are baked
  // into an atlas of side `atlas`.
  std::optional<std::filesystem::path> texture;
  int atlas = 2048;
  std::vector<std::string> cameras;  // scene camera names; empty: all (unless orbit)
  int orbit = 0;                     // > 0: a ring of this many views around the scene
  double scale = 1.0;                // image size factor
  std::filesystem::path output;      // VIEW.exr, or a folder
  bool png = false;                  // also write PNG previews
};

std::vector<std::filesystem::path> RenderViews(const RenderOptions& options, vk::Device& device);

// `n` cameras on a horizontal ring around the scene's objects, with the intrinsics of the
// first scene camera, at the scene cameras' mean distance and height, all looking at the
// centre of the bounding box of the non-plane geometry.
std::vector<Camera> OrbitCameras(const Scene& scene, const std::vector<double>& psi,
                                 const SceneGeometry& geometry, int n);

// Renders `cameras` of the scene at Ψ, its surface textured with `atlas` (laid out as
// `geometry.atlas`): the synthetic images of a reconstruction, through each camera's lens
// (LensWarp.h), so that they line up with its photograph. Alpha 0 off the surface.
std::vector<Image> RenderWithAtlas(vk::Device& device, const Scene& scene, const std::vector<double>& psi,
                                   const SceneGeometry& geometry, const Image& atlas,
                                   const std::vector<Camera>& cameras);

// The world bounding box of the scene's surface at Ψ, and of its objects (every node but
// planes; empty when there are none): the ground would pull an orbit's centre to its middle.
struct SceneBounds {
  Eigen::AlignedBox3d everything, objects;
};
SceneBounds WorldBounds(const Scene& scene, const std::vector<double>& psi, const SceneGeometry& geometry);

// A camera scaled to another image size: K' = diag(sx, sy, 1)·K under the [0,W] convention.
Camera ScaleCamera(const Camera& camera, double scale);

}  // namespace vkr
