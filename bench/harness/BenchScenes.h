#pragma once
// The scenes `vkrecon bench` times (thesis appendix A): small synthetic scenes written in
// code — a scene file, a glTF mesh, an albedo texture, cameras — with reference images
// made by SynthesiseImages, and the bundled assets re-synthesised at the size a row needs.
// Everything lands in a scratch folder; nothing here times anything.

#include <filesystem>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"

namespace vkr {

// What one synthetic scene is made of.
struct SyntheticSceneSpec {
  enum class Shape {
    // A tessellated open cylinder (diameter 1 m, height 1 m), `triangles` ≈ 2 · segments ·
    // rings, seen by a ring of cameras: triangle count and camera count sweeps.
    Cylinder,
    // A 2 m × 2 m grid of cells in the ground plane seen from above; a `share` of its cells
    // face down, away from every camera: back-facing sweep.
    BackFacingGrid,
    // 256 strips, 10 m long, on the ground in front of a row of cameras; a `share` of them
    // start behind the cameras, so both their triangles cross every camera's near plane
    // (§5.5.1); every strip covers the same atlas area: near-plane clipping sweep.
    NearClipStrips,
  };
  Shape shape = Shape::Cylinder;
  int triangles = 1000;  // Cylinder only
  double share = 0.0;    // BackFacingGrid, NearClipStrips: in [0, 1]
  int cameras = 6;
  int width = 640, height = 480;  // reference image size
  int atlas = 512;                // likelihood.atlas of the scene
  int levels = 3;
};

// A scene ready for a likelihood: its file, the overrides that point it at its reference
// images, and the hypothesis the images were made at.
struct BenchScene {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::filesystem::path at_file;  // {"name": value}: the truth of the reference images
  int triangles = 0;              // in the whole scene
  int backfacing_triangles = 0;   // facing away from every camera
  int clipped_triangles = 0;      // crossing the near plane, per camera
  int cameras = 0;
  int width = 0, height = 0;      // reference image size
  int atlas = 0;
};

// Writes the scene into `dir` (created) and synthesises its reference images into
// `dir`/images at the spec's size.
BenchScene MakeSyntheticScene(const SyntheticSceneSpec& spec, const std::filesystem::path& dir,
                              vk::Device& device);

// A bundled asset (`asset_dir` holds scene.json and truth.json) with reference images made
// at its truth into `dir`/images, their size scaled by `scale` (1 = the assets' 640×480), and
// only its first `max_cameras` cameras (0 = all) kept. `atlas` > 0 overrides likelihood.atlas.
BenchScene PrepareAsset(const std::filesystem::path& asset_dir, const std::filesystem::path& dir,
                        double scale, int max_cameras, int atlas, vk::Device& device);

// The triangle counts of the cylinder sweep's tessellations (segments × rings × 2); any
// other count is rounded to a nearby tessellation.
int CylinderTriangles(int requested);

}  // namespace vkr
