// `vkrecon preview SCENE [--at P.json] -o OUT`: parses the options and calls report::WritePreview.

#include <iostream>

#include "apps/Commands.h"
#include "engine/scene/Scene.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "pipelines/rendering/SynthSettings.h"
#include "recon/SearchSetup.h"
#include "report/Preview.h"

namespace vkr::app {

int RunPreview(int argc, char** argv) {
  CLI::App app(
      "Check a scene against its photographs before a run. Writes OUT/overlays/<camera>.png, each photograph "
      "with the scene's wireframe (yellow) at its starting values (the scene's init, else the prior's centre; or "
      "--at) and, faint blue, with each parameter at either end of its range (a uniform prior's bounds, a "
      "normal's mean ± 3 sd, cut to the bounds), drawn through the camera's lens as the renderer sees it; and "
      "OUT/preview.html, one offline page with the photographs and a slider per parameter that moves the "
      "wireframe on every photograph live (the page recomputes the scene exactly: transforms, expressions, "
      "lens), with buttons that save the values as an --at file or as the scene with them as init. Also "
      "OUT/at.json (the values drawn) and OUT/preview.json (the settings). Needs no Vulkan device. Bad input (a "
      "photograph missing, an --at file with an unknown or missing parameter, a settings block that run or synth "
      "would refuse) exits 2 with one line. "
      "docs/guide/REAL_PHOTOS.md, \"Check it before a run\".",
      "preview");
  report::PreviewOptions options;
  std::string scene, at, out;
  std::vector<std::string> sets;
  app.add_option("scene", scene, "scene file (JSON, docs/guide/SCENE_FORMAT.md)")->required();
  app.add_option("--at", at, "draw at these values ({\"name\": value, …}, every parameter) instead of the scene's init");
  app.add_option("-o,--output", out, "the folder to write (made if missing)")->required();
  app.add_option("--set", sets, "override a scene-file field by its dotted path, e.g. --set images=DIR (repeatable)");
  if (auto status = Parse(app, argc, argv)) return *status;
  options.scene_file = scene;
  options.at_file = at;
  options.output_dir = out;
  options.overrides = ParseOverrides(sets);
  {
    // Preview is where a scene is checked before a run: a settings block that `run` or
    // `synth` would refuse is bad input here too (exit 2, one line), not news after a build.
    LoadOptions load;
    load.require_images = false;  // preview names a missing photograph itself
    const Scene checked = LoadScene(options.scene_file, options.overrides, load);
    LikelihoodSettingsOf(checked);
    recon::SamplerOptionsOf(checked);
    SynthSettingsOf(checked);
  }
  std::cout << report::WritePreview(options).BriefReport();
  return 0;
}

}  // namespace vkr::app
