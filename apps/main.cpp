// vkrecon: reconstruct 3D geometry from calibrated photographs by inverse rendering.
// One binary, a table of subcommands (docs/reference/CLI.md).

#include <cstring>
#include <iostream>
#include <string>

#include "apps/Commands.h"
#include "engine/common/InputError.h"

namespace {

struct Subcommand {
  const char* name;
  int (*run)(int, char**);
  const char* summary;
};

constexpr Subcommand kSubcommands[] = {
    {"init", vkr::app::RunInit, "a COLMAP sparse model to a Z-up scene folder with a starter scene"},
    {"preview", vkr::app::RunPreview, "a scene's wireframe over its photographs, with sliders: check it before a run"},
    {"run", vkr::app::RunRun, "reconstruct: sample the parameters against the photographs"},
    {"compare", vkr::app::RunCompare, "which of several scenes the photographs support: log evidence, Bayes factors"},
    {"fit", vkr::app::RunFit, "MAP only: search the parameters' mode with an NLopt method (no intervals)"},
    {"report", vkr::app::RunReport, "write a run's report.html again from its output folder"},
    {"synth", vkr::app::RunSynth, "render reference images of a textured scene at given parameters"},
    {"render", vkr::app::RunRender, "render novel views (linear float RGBA OpenEXR)"},
    {"likelihood", vkr::app::RunLikelihood, "evaluate, sweep, dump or profile the likelihood at given parameters"},
    {"bench", vkr::app::RunBench, "GPU throughput benchmark (thesis appendix A)"},
    {"devices", vkr::app::RunDevices, "list Vulkan devices"},
};

void PrintUsage(std::ostream& out) {
  out << "vkrecon — reconstruct 3D geometry from calibrated photographs by inverse rendering\n\n"
         "usage: vkrecon <command> [options]   (vkrecon <command> --help for its options)\n\n"
         "commands:\n";
  for (const Subcommand& s : kSubcommands)
    out << "  " << s.name << std::string(12 - std::strlen(s.name), ' ') << s.summary << "\n";
  out << "\nexit status: 0 success, 2 bad input (one line naming file, field and problem), "
         "1 other errors\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintUsage(std::cerr);
    return 2;
  }
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    PrintUsage(std::cout);
    return 0;
  }
  if (command == "--version") {
    std::cout << "vkrecon 0.1.0\n";
    return 0;
  }
  for (const Subcommand& s : kSubcommands) {
    if (command != s.name) continue;
    try {
      return s.run(argc - 1, argv + 1);
    } catch (const vkr::InputError& e) {
      std::cerr << "vkrecon " << command << ": " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "vkrecon " << command << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "vkrecon: unknown command '" << command << "' (try vkrecon --help)\n";
  return 2;
}
