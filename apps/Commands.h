#pragma once
// The subcommands of `vkrecon`. Each Run* parses its own arguments and calls a typed library
// function; exit codes (docs/reference/CLI.md): 0 success, 2 bad input, 1 anything else.

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"

namespace vkr::app {

int RunDevices(int argc, char** argv);
int RunSynth(int argc, char** argv);
int RunRender(int argc, char** argv);
int RunLikelihood(int argc, char** argv);
int RunBench(int argc, char** argv);
int RunRun(int argc, char** argv);
int RunFit(int argc, char** argv);
int RunReport(int argc, char** argv);
int RunInit(int argc, char** argv);
int RunCompare(int argc, char** argv);
int RunPreview(int argc, char** argv);

// Parses argv; returns an exit status when the command should stop now (--help: 0 after
// printing help; a bad option: 2 after one line naming it), nothing to go on.
std::optional<int> Parse(CLI::App& app, int argc, char** argv);

// Options every subcommand that reads a scene shares.
struct SceneArgs {
  std::string scene;
  std::vector<std::string> sets;  // PATH=VALUE
  int device = -1;
};
void AddSceneArgs(CLI::App& app, SceneArgs& args);

// Opens the Vulkan device (--device / VKRECON_DEVICE). Commands name it in their summary
// line rather than up front, so a bad-input error stays the only line on stderr.
std::unique_ptr<vk::Device> OpenDevice(int index);
// Fails (exit 1) when the validation layer reported anything during the command.
int FinishWithDevice(const vk::Device& device, int status);

}  // namespace vkr::app
