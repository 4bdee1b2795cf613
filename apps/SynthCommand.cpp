#include <iostream>

#include "apps/Commands.h"
#include "engine/scene/LensDistortion.h"
#include "pipelines/rendering/ViewRendering.h"

namespace vkr::app {

int RunSynth(int argc, char** argv) {
  CLI::App app(
      "Render reference images of a textured scene at parameter values P, one PNG per camera, plus "
      "the cameras.json they match. By default each node shows its albedo texture as it is; the "
      "scene's \"synth\" block or the options below make them look like photographs: a sun with "
      "cast shadows, an exposure that differs from camera to camera (written to exposure.json), "
      "anti-aliasing.",
      "synth");
  SceneArgs scene;
  SynthOptions options;
  std::string at, out;
  AddSceneArgs(app, scene);
  app.add_option("--at", at, "parameter values, a JSON file {\"name\": value, ...}")->required();
  app.add_option("-o,--output", out, "output folder")->required();
  app.add_option("--noise", options.noise_sigma,
                 "Gaussian noise sd on the 0-255 scale added to every channel (default 0)");
  app.add_option("--seed", options.seed, "noise seed (default 1)");
  app.add_option("--scale", options.scale,
                 "image size factor; K scales with it (default 1, tests use 0.25)");
  app.add_option("--atlas", options.atlas, "side of the albedo atlas in texels (default 2048)");
  std::vector<double> sun;
  app.add_option("--sun", sun,
                 "light with a sun at AZIMUTH,ELEVATION degrees (azimuth from +x towards +y) and its "
                 "cast shadows, plus ambient sky light")
      ->expected(2)->delimiter(',');
  bool unlit = false;
  app.add_flag("--unlit", unlit, "no sun even if the scene's synth block has one: the albedo as it is");
  double ambient = -1.0;
  app.add_option("--ambient", ambient, "share of the light from the sky, on every face (default 0.3)");
  double exposure = -1.0;
  app.add_option("--exposure", exposure,
                 "spread s of each camera's exposure: gain 1±s, white balance ±s/5, offset ±43s (0-255), "
                 "gamma e^±0.64s (0.35 is what auto-exposure does; default 0, identical cameras)");
  int supersample = 0;
  app.add_option("--supersample", supersample, "samples per pixel along each axis, 1-8 (anti-aliasing; default 1)");
  std::string distortion;
  app.add_option("--distortion", distortion,
                 "give every camera this lens, MODEL[:NAME=VALUE,...] with COLMAP's model and coefficient "
                 "names, e.g. OPENCV:k1=-0.12,k2=0.03 (coefficients not named are 0); written to cameras.json");
  app.add_option("--mask-nodes", options.mask_nodes,
                 "NAME[,NAME...]: also write masks/<image name>.png beside the output folder, 0 where these "
                 "nodes are the visible surface, 255 elsewhere");
  app.add_flag("--colmap", options.colmap, "also write the cameras as a COLMAP text model in OUTPUT/sparse/");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "print nothing but errors");
  if (auto status = Parse(app, argc, argv)) return *status;

  options.scene_file = scene.scene;
  options.overrides = ParseOverrides(scene.sets);
  options.at_file = at;
  options.output_dir = out;
  if (!sun.empty()) {
    options.sun = true;
    options.sun_azimuth = sun[0];
    options.sun_elevation = sun[1];
  }
  if (unlit) options.sun = false;
  if (ambient >= 0.0) options.ambient = ambient;
  if (exposure >= 0.0) options.exposure = exposure;
  if (supersample > 0) options.supersample = supersample;
  if (!distortion.empty()) options.distortion = ParseDistortionSpec(distortion, "--distortion");
  auto device = OpenDevice(scene.device);
  const SynthSummary summary = SynthesiseImages(options, *device);
  if (!quiet)
    std::cerr << "vkrecon synth: wrote " << summary.images.size() << " images and "
              << summary.cameras_file.string()
              << (summary.masks.empty() ? "" : ", " + std::to_string(summary.masks.size()) + " masks in " +
                                                   summary.masks.front().parent_path().string())
              << (summary.colmap_dir.empty() ? "" : ", a COLMAP model in " + summary.colmap_dir.string()) << " ("
              << device->name() << ")\n";
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
