#include <iomanip>
#include <iostream>

#include "apps/Commands.h"

namespace vkr::app {

int RunDevices(int argc, char** argv) {
  CLI::App app("List the Vulkan devices vkrecon can use; pick one with --device N or "
               "VKRECON_DEVICE=N.", "devices");
  if (auto status = Parse(app, argc, argv)) return *status;
  const auto devices = vk::ListDevices();
  if (devices.empty()) {
    std::cout << "no Vulkan devices (install mesa-vulkan-drivers for the CPU device lavapipe)\n";
    return 1;
  }
  for (const auto& d : devices) {
    std::cout << d.index << ": " << d.name << " (" << d.type << ", Vulkan " << d.api_version
              << ", " << d.driver << ", " << std::fixed << std::setprecision(1)
              << d.device_local_bytes / double(1 << 30) << " GiB)";
    if (!d.usable) std::cout << " — not usable: " << d.why_not;
    std::cout << "\n";
  }
  return 0;
}

}  // namespace vkr::app
