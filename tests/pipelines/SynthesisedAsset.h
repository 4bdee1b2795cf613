#pragma once
// A bundled asset with reference images made by `synth` at its truth (quarter size), loaded
// as a scene pointing at them: the starting point of the likelihood and output tests.

#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

// Reference images of an asset at its truth, quarter size (160×120-class), noise sd `noise`
// on the 0–255 scale, seed 7, into `dir`, with synth's cameras.json (K and pose folded at
// the truth). `scene` names the asset's file photographed: synth.json for the assets whose
// photographs show more than the model.
void SynthesiseAssetImages(vk::Device& device, const std::string& asset, double noise, const TempDir& dir,
                           const std::string& scene = "scene.json");

// The same images, and the asset loaded as a scene reading them; `truth` receives the
// asset's truth.json.
Scene SynthesisedScene(vk::Device& device, const std::string& asset, double noise, const TempDir& dir,
                       std::vector<double>* truth);

}  // namespace vkr::test
