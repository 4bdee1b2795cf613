// Scores one hypothesis of a scene through the installed library, as `vkrecon likelihood
// SCENE --at AT [--set PATH=VALUE …]` does, and prints the total log likelihood.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "engine/vk/Device.h"
#include "pipelines/likelihood/LikelihoodTool.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: consumer SCENE AT [PATH=VALUE ...]\n");
    return 2;
  }
  try {
    vkr::LikelihoodToolOptions options;
    options.scene_file = argv[1];
    options.at_file = argv[2];
    options.overrides = vkr::ParseOverrides(std::vector<std::string>(argv + 3, argv + argc));
    vkr::vk::Device device;  // the best device, as the command line picks it
    const vkr::LikelihoodReport report = vkr::EvaluateAt(options, device);
    std::printf("%.17g\n", report.evaluation.total());
    return device.validation_messages().empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
