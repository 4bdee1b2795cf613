#include "tests/pipelines/RealCameraScenes.h"

#include <nlohmann/json.hpp>

#include "pipelines/rendering/ViewRendering.h"

namespace vkr::test {
namespace {

namespace fs = std::filesystem;
const fs::path kBox = fs::path(VKRECON_SOURCE_DIR) / "assets/box";

// The box asset's scene plus a pole (a cylinder in the house's roof texture) standing beside
// the box at the truth, in front of it for some cameras: what synth renders.
fs::path WritePoleScene(const TempDir& dir) {
  nlohmann::ordered_json scene = nlohmann::ordered_json::parse(ReadText(kBox / "scene.json"));
  for (auto& node : scene["nodes"]) node["albedo"] = (kBox / node["albedo"].get<std::string>()).string();
  scene["cameras"] = (kBox / "cameras.json").string();
  scene["nodes"].push_back({{"name", "pole"},
                            {"primitive", "cylinder"},
                            {"albedo", (kBox / "../house/textures/roof.png").lexically_normal().string()},
                            {"transforms", {{{"translate", {0.55, 0.35, 0}}}, {{"scale", {0.2, 0.2, 1.1}}}}}});
  const fs::path file = dir / "pole.json";
  WriteText(file, scene.dump(1));
  return file;
}

}  // namespace

LensDistortion BarrelLens() { return LensDistortion{DistortionModel::OpenCV, {-0.12, 0.03, 0, 0}}; }
LensDistortion PincushionLens() { return LensDistortion{DistortionModel::OpenCV, {0.1, 0, 0, 0}}; }

Scene ReloadBox(const RealCameraShot& shot, const TempDir& dir, bool masks) {
  fs::create_directories(dir / "no_masks");
  const fs::path images = dir / "images";
  const std::string cameras = shot.lens ? R"({"colmap": ")" + (images / "sparse").string() + R"("})"
                                        : (images / "cameras.json").string();
  return LoadScene(kBox / "scene.json", {{"cameras", cameras},
                                         {"images", images.string()},
                                         {"masks", (dir / (masks ? "masks" : "no_masks")).string()}});
}

Scene ShootBox(vk::Device& device, const RealCameraShot& shot, const TempDir& dir, bool masks,
               std::vector<double>* truth) {
  SynthOptions synth;
  synth.scene_file = shot.pole ? WritePoleScene(dir) : kBox / "scene.json";
  synth.at_file = kBox / "truth.json";
  synth.output_dir = dir / "images";
  synth.noise_sigma = shot.noise;
  synth.seed = 7;
  synth.scale = 0.25;
  synth.atlas = 1024;
  synth.distortion = shot.lens;
  synth.colmap = shot.lens.has_value();
  if (shot.pole) synth.mask_nodes = {"pole"};
  SynthesiseImages(synth, device);
  fs::create_directories(dir / "masks");  // masks/ beside images/ (synth writes there with a pole)
  Scene scene = ReloadBox(shot, dir, masks);
  *truth = scene.ValuesFromFile(kBox / "truth.json");
  return scene;
}

}  // namespace vkr::test
