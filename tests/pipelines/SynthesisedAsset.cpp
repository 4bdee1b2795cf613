#include "tests/pipelines/SynthesisedAsset.h"

#include "pipelines/rendering/ViewRendering.h"

namespace vkr::test {

void SynthesiseAssetImages(vk::Device& device, const std::string& asset, double noise, const TempDir& dir,
                           const std::string& scene) {
  const std::filesystem::path root = std::filesystem::path(VKRECON_SOURCE_DIR) / "assets" / asset;
  SynthOptions synth;
  synth.scene_file = root / scene;
  synth.at_file = root / "truth.json";
  synth.output_dir = dir.path();
  synth.noise_sigma = noise;
  synth.seed = 7;
  synth.scale = 0.25;
  synth.atlas = 1024;
  SynthesiseImages(synth, device);
}

Scene SynthesisedScene(vk::Device& device, const std::string& asset, double noise, const TempDir& dir,
                       std::vector<double>* truth) {
  const std::filesystem::path root = std::filesystem::path(VKRECON_SOURCE_DIR) / "assets" / asset;
  SynthesiseAssetImages(device, asset, noise, dir);
  Scene scene = LoadScene(root / "scene.json", {{"cameras", (dir / "cameras.json").string()},
                                                {"images", dir.path().string()}});
  *truth = scene.ValuesFromFile(root / "truth.json");
  return scene;
}

}  // namespace vkr::test
