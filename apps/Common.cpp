#include <filesystem>
#include <iostream>

#include "apps/Commands.h"
#include "engine/common/InputError.h"

namespace vkr::app {

std::optional<int> Parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    std::cerr << "vkrecon " << app.get_name() << ": " << e.what() << " (see --help)\n";
    return 2;
  }
}

void AddSceneArgs(CLI::App& app, SceneArgs& args) {
  app.add_option("scene", args.scene, "scene file (JSON, see README)")->required();
  app.add_option("--set", args.sets,
                 "override a scene-file field by its dotted path, e.g. --set likelihood.sigma=4 "
                 "(repeatable)");
  app.add_option("--device", args.device,
                 "Vulkan device index from `vkrecon devices` (default: VKRECON_DEVICE, else the "
                 "best GPU, else lavapipe)");
}

std::vector<SceneOverride> ParseOverrides(const std::vector<std::string>& sets) {
  std::vector<SceneOverride> out;
  for (const std::string& s : sets) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("", "--set", "expected PATH=VALUE, got '" + s + "'");
    SceneOverride o{s.substr(0, eq), s.substr(eq + 1)};
    // A path typed on the command line is relative to where the user is, not to the scene
    // file: make the scene's path fields absolute before the loader resolves them.
    const std::string& key = o.path;
    const bool path_field = key == "images" || key == "cameras" || key == "masks" || key == "cameras.colmap" ||
                            key.ends_with(".albedo") || key.ends_with(".mesh");
    if (path_field && !o.value.empty() && o.value.front() != '{' && o.value.front() != '[' &&
        o.value.front() != '"' && std::filesystem::path(o.value).is_relative())
      o.value = std::filesystem::absolute(o.value).string();
    out.push_back(o);
  }
  return out;
}

std::unique_ptr<vk::Device> OpenDevice(int index) {
  vk::DeviceCreateInfo info;
  info.device_index = index;
  return std::make_unique<vk::Device>(info);
}

int FinishWithDevice(const vk::Device& device, int status) {
  const auto messages = device.validation_messages();
  if (!messages.empty()) {
    std::cerr << "vkrecon: error: the Vulkan validation layer reported " << messages.size()
              << " message(s) (printed above)\n";
    return 1;
  }
  return status;
}

}  // namespace vkr::app
