#pragma once
// Photographs of the bundled box asset as real cameras take them, made by `synth` at the
// truth (quarter size, 160×120, 9 cameras): through a lens and read back through a COLMAP
// model, and/or with an occluder that the model leaves out, masked by `--mask-nodes`.

#include <optional>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

struct RealCameraShot {
  std::optional<LensDistortion> lens;  // every camera's; written as a COLMAP model
  bool pole = false;                   // a textured pole stands beside the box, masked
  double noise = 0.0;                  // sd on the 0–255 scale
};

// Synthesises `shot` into `dir`/images (+ `dir`/masks with a pole) and loads the box
// asset's scene (which has no pole) reading them: through `dir`/images/sparse (COLMAP)
// with a lens, else through synth's cameras.json. `masks` false points the scene's masks at
// an empty folder. `truth` receives the asset's truth.
Scene ShootBox(vk::Device& device, const RealCameraShot& shot, const TempDir& dir, bool masks,
               std::vector<double>* truth);

// The box scene reading `dir`'s images again (after ShootBox), with or without masks.
Scene ReloadBox(const RealCameraShot& shot, const TempDir& dir, bool masks);

// The lens of the asset bar: OpenCV k1 = −0.12, k2 = 0.03 (barrel).
LensDistortion BarrelLens();
// A pincushion lens (k1 = +0.1): the corners of the undistorted image lie outside the
// photograph, so it has an invalid border.
LensDistortion PincushionLens();

}  // namespace vkr::test
