#include <csignal>
#include <iostream>

#include "apps/Commands.h"
#include "apps/Reconstruct.h"

namespace vkr::app {

int RunRun(int argc, char** argv) {
  CLI::App app(
      "Reconstruct: sample the scene's parameters against its photographs (Metropolis-Hastings "
      "with annealing and replica exchange over the coarse levels, then settling at the mode, where "
      "the noise model is calibrated (sigma \"auto\", texel correlation), then sampling, then gradient "
      "refinement) and write OUT/map.json (MAP, posterior mean, sd, 95 % interval, ESS, R-hat, the "
      "calibration), chain.csv, composite.exr/.png, model.glb (textured; opens in Blender) and "
      "reprojections/. The state is saved every few seconds: an interrupted run continues with "
      "--resume. map.json's diagnosis is ok only when the residuals look like noise on every node and "
      "photograph and the chains agree; otherwise it names what disagrees (also on stderr). Exit 1 when "
      "the fit does not explain the images at all. By default (sampler.iterations \"auto\") sampling goes "
      "on until every parameter's rank-normalised R-hat <= 1.01 and bulk-ESS >= 400, or the time limit; "
      "the progress line shows both. Sampler options go in the "
      "scene's \"sampler\" block or --set sampler.NAME=VALUE (optimiser/SamplerOptions.h).",
      "run");
  SceneArgs scene;
  ReconstructOptions options;
  std::string out;
  AddSceneArgs(app, scene);
  app.add_option("-o,--output", out, "output folder")->required();
  app.add_flag("--resume", options.resume, "continue the run saved in OUT/checkpoint.json (none there: start the run, with a warning)");
  app.add_flag("-q,--quiet", options.quiet, "no progress bar");
  app.add_option("--checkpoint-seconds", options.checkpoint_seconds, "seconds between checkpoints (default 5)");
  app.add_option("--time-limit", options.time_limit,
                 "seconds the sampling may take before it ends where it is (0: none; default sampler.time_limit: "
                 "240 with iterations \"auto\", none with a fixed count); the refinement and outputs follow")
      ->check(CLI::Range(0.0, 1e9));
  app.add_option("--temperatures", options.temperatures,
                 "tempered replicas per chain (default sampler.batch / sampler.chains)");
  if (auto status = Parse(app, argc, argv)) return *status;
  options.scene_file = scene.scene;
  options.overrides = ParseOverrides(scene.sets);
  options.output_dir = out;
  auto device = OpenDevice(scene.device);
  std::signal(SIGINT, [](int) { RequestStop(); });
  const ReconstructResult result = Reconstruct(options, *device);
  if (!result.completed) {
    std::cerr << "vkrecon run: interrupted; continue with: vkrecon run " << scene.scene << " -o " << out
              << " --resume\n";
    return FinishWithDevice(*device, 1);
  }
  for (const std::string& note : result.notes) std::cerr << "vkrecon run: note: " << note << "\n";
  if (!options.quiet) std::cerr << "vkrecon run: wrote " << out << "/ (report.html, map.json, chain.csv, composite.exr, model.glb, reprojections/, overlays/)\n";
  if (result.failed) {
    std::cerr << "vkrecon run: error: the result is not trustworthy (see the notes above and map.json's diagnosis)\n";
    return FinishWithDevice(*device, 1);
  }
  if (!result.diagnosis_ok)
    std::cerr << "vkrecon run: warning: the diagnosis is not ok (see the notes above and map.json's diagnosis): "
                 "read the intervals with care\n";
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
