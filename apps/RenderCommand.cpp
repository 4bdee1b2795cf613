#include <iostream>

#include "apps/Commands.h"
#include "pipelines/rendering/ViewRendering.h"

namespace vkr::app {

int RunRender(int argc, char** argv) {
  CLI::App app(
      "Render novel views of a scene to linear float RGBA OpenEXR (alpha 0 off the surface): "
      "textured by an atlas (composite.exr of a run) or, without --texture, by the nodes' "
      "albedo textures.",
      "render");
  SceneArgs scene;
  RenderOptions options;
  std::string at, texture, out;
  AddSceneArgs(app, scene);
  app.add_option("--at", at, "parameter values (default: the scene's initial values)");
  app.add_option("--texture", texture, "atlas texture (EXR or PNG, square)");
  app.add_option("--atlas", options.atlas, "atlas side when baking albedo textures (default 2048)");
  app.add_option("--camera", options.cameras, "render this scene camera (repeatable; default all)");
  app.add_option("--orbit", options.orbit, "render N views on a ring around the scene instead");
  app.add_option("--scale", options.scale, "image size factor (default 1)");
  app.add_option("-o,--output", out,
                 "VIEW.exr for one view; with several, VIEW_<camera>.exr, or a folder")->required();
  app.add_flag("--png", options.png, "also write PNG previews");
  bool quiet = false;
  app.add_flag("-q,--quiet", quiet, "print nothing but errors");
  app.get_option("--camera")->excludes(app.get_option("--orbit"));
  if (auto status = Parse(app, argc, argv)) return *status;

  options.scene_file = scene.scene;
  options.overrides = ParseOverrides(scene.sets);
  if (!at.empty()) options.at_file = at;
  if (!texture.empty()) options.texture = texture;
  options.output = out;
  auto device = OpenDevice(scene.device);
  const auto files = RenderViews(options, *device);
  if (!quiet) {
    for (const auto& f : files) std::cerr << "vkrecon render: wrote " << f.string() << "\n";
    std::cerr << "vkrecon render: " << files.size() << " files (" << device->name() << ")\n";
  }
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
