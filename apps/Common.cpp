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
