// `vkrecon fit`: parses its options and calls FitMap (recon/Fit.h).
#include <iostream>

#include "apps/Commands.h"
#include "engine/common/InputError.h"
#include "recon/Fit.h"

namespace vkr::app {

int RunFit(int argc, char** argv) {
  CLI::App app(
      "MAP only: search the scene's maximum a posteriori parameters with one of NLopt's derivative-free "
      "methods on the likelihood `run` samples, coarse-to-fine over its pyramid levels (each level "
      "starts at the previous one's best; the coarse levels may spend 15 % of the budget each, level 0 "
      "the rest), from the parameters' initial values (the priors' centres unless \"init\"). Writes "
      "OUT/map.json (the MAP, its log posterior, evaluations, full-resolution equivalents, wall time; "
      "no means, sds or intervals: use `vkrecon run` for those) and OUT/at_map.json. Faster to a point "
      "than `run`, with no word on how sure it is. The local methods (bobyqa, neldermead, sbplx) stop "
      "when converged; the global ones (crs2lm, isres) spend the budget.",
      "fit");
  SceneArgs scene;
  recon::FitOptions options;
  std::string out, method = "bobyqa";
  AddSceneArgs(app, scene);
  app.add_option("-o,--output", out, "output folder")->required();
  app.add_option("--method", method, "NLopt method: " + opt::SearchMethodNames() + " (default bobyqa)");
  app.add_option("--evaluations", options.evaluations,
                 "budget in full-resolution-equivalent evaluations; one at pyramid level l counts 4^-l "
                 "(default 300)");
  app.add_option("--levels", options.levels, "pyramid levels to search, coarsest first (default 0: all the scene's)");
  app.add_option("--restarts", options.restarts,
                 "restart a local method (bobyqa, neldermead, sbplx) from its mode at full resolution up to N "
                 "times while the budget lasts, until a restart moves no parameter by 0.1 % of its prior width: "
                 "on a rasterised likelihood BOBYQA can stop short of the mode (default 3; 0: as NLopt ends it)");
  app.add_flag("-q,--quiet", options.quiet, "no progress on stderr");
  if (auto status = Parse(app, argc, argv)) return *status;
  if (!opt::FromString(method, &options.method))
    throw InputError("", "--method", "unknown method '" + method + "' (known: " + opt::SearchMethodNames() + ")");
  options.scene_file = scene.scene;
  options.overrides = ParseOverrides(scene.sets);
  options.output_dir = out;
  recon::CheckFitOptions(options);  // bad input fails before the device opens
  auto device = OpenDevice(scene.device);
  const recon::FitResult result = recon::FitMap(options, *device);
  if (!options.quiet)
    std::cerr << "vkrecon fit: wrote " << result.map_json.string() << " (" << device->name() << ")\n";
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
