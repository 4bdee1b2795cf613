#pragma once
// The sign scene of the two hidden-surface tests (VisibilityBiasTest, ImageLikelihoodBiasTest;
// thesis §4.6, §7.4): a textured sign on textured ground before five 160×120 cameras, its
// one parameter `tilt` (90°: facing the cameras, the truth; −90°: facing away).

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

// Writes the scene and its reference images (noise σ = 16, seed 3, at tilt = 90°) into
// `dir` and loads it.
Scene SignScene(vk::Device& device, const TempDir& dir);

}  // namespace vkr::test
