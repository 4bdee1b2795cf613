#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>

#include "apps/Commands.h"
#include "engine/common/InputError.h"
#include "recon/Ranks.h"
#include "recon/Reconstruct.h"
#include "recon/SceneList.h"

namespace vkr::app {

using recon::Ranks;
using recon::ReconstructOptions;
using recon::ReconstructResult;

namespace {

// Under MPI without --device or VKRECON_DEVICE: the node's GPUs shared out by local rank
// (rank i on a node takes its GPU i mod GPUs); with no GPU, the default (lavapipe).
int RankDevice(int requested, const Ranks& ranks) {
  if (requested >= 0 || !ranks.distributed()) return requested;
  if (const char* env = std::getenv("VKRECON_DEVICE"); env && *env) return requested;
  std::vector<int> gpus;
  for (const vk::PhysicalDeviceInfo& d : vk::ListDevices())
    if (d.usable && d.type != "CPU") gpus.push_back(d.index);
  return gpus.empty() ? requested : gpus[size_t(ranks.local_rank()) % gpus.size()];
}

// What rank 0 says when mpirun ends the job because another rank died (it sends SIGTERM):
// the checkpoint rank 0 kept is where the run continues. Written by the handler, so built
// beforehand; write() is async-signal-safe.
std::string g_terminated_message;
void OnTerminate(int signal) {
  if (!g_terminated_message.empty())
    (void)!write(2, g_terminated_message.data(), g_terminated_message.size());
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

int RunMany(const ReconstructOptions& options, const SceneArgs& args, const std::string& out);

// The exit status and the closing lines of rank 0 (or the one process).
int FinishRun(const ReconstructOptions& options, const std::string& scene, const std::string& out,
           const ReconstructResult& result, const vk::Device& device, const std::string& resume_command = "");

}  // namespace

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
      "scene's \"sampler\" block or --set sampler.NAME=VALUE (optimiser/SamplerOptions.h). SCENE may also "
      "be a folder (each subfolder with a scene.json) or a .txt list of scenes: each runs into OUT/<name>, "
      "spread over the MPI ranks under mpirun, with a summary table (OUT/summary.csv).",
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
  if (recon::IsSceneList(scene.scene)) return RunMany(options, scene, out);
  const Ranks& ranks = Ranks::World();
  if (!ranks.distributed()) {
    auto device = OpenDevice(scene.device);
    std::signal(SIGINT, [](int) { recon::RequestStop(); });
    return FinishRun(options, scene.scene, out, recon::Reconstruct(options, *device), *device);
  }
  // One of several MPI ranks (docs/guide/SCALE_OUT.md). A rank that fails must end the whole job:
  // the others would wait for it forever in the next exchange.
  const std::string resume = "mpirun -n " + std::to_string(ranks.size()) + " vkrecon run " + scene.scene + " -o " + out + " --resume";
  try {
    auto device = OpenDevice(RankDevice(scene.device, ranks));
    std::signal(SIGINT, [](int) { recon::RequestStop(); });
    if (ranks.rank() == 0) {
      g_terminated_message = "\nvkrecon run: the MPI job was ended (a rank failed or was killed; mpirun names it): no "
                             "result was written; the last checkpoint is in " + out + "/checkpoint.json; continue with the same command and --resume: " +
                             resume + "\n";
      std::signal(SIGTERM, OnTerminate);
    }
    const ReconstructResult result = recon::Reconstruct(options, *device);
    if (ranks.rank() != 0) return FinishWithDevice(*device, 0);
    return FinishRun(options, scene.scene, out, result, *device, resume);
  } catch (const InputError& e) {
    std::cerr << "vkrecon run (rank " << ranks.rank() << " of " << ranks.size() << "): " << e.what() << "\n";
    ranks.Abort(2);
  } catch (const std::exception& e) {
    std::cerr << "vkrecon run (rank " << ranks.rank() << " of " << ranks.size() << "): error: " << e.what()
              << "\nvkrecon run: the MPI job ends; the last checkpoint is in " << out << "/checkpoint.json; continue with the same command and --resume: "
              << resume << "\n";
    ranks.Abort(1);
  }
}

namespace {

// How one scene of a list ended, as a number (it travels to rank 0 as a double).
enum class ListedOutcome { Ok, NotOk, ModelError, Interrupted, BadInput, Error };
const char* ToString(ListedOutcome o) {
  switch (o) {
    case ListedOutcome::Ok: return "ok";
    case ListedOutcome::NotOk: return "not ok (see its map.json)";
    case ListedOutcome::ModelError: return "not trustworthy";
    case ListedOutcome::Interrupted: return "interrupted (--resume)";
    case ListedOutcome::BadInput: return "bad input";
    case ListedOutcome::Error: return "error";
  }
  return "?";
}
int ExitStatus(ListedOutcome o) {
  if (o == ListedOutcome::BadInput) return 2;
  return o == ListedOutcome::Ok || o == ListedOutcome::NotOk ? 0 : 1;
}

// Many scenes (docs/guide/SCALE_OUT.md, "Many scenes"): scene i runs on rank i mod R as a process
// of its own, into OUT/<name>; rank 0 gathers how each ended and prints the table (also
// OUT/summary.csv). A scene that fails does not stop the others; the exit status is the
// worst of theirs.
int RunMany(const ReconstructOptions& options, const SceneArgs& args, const std::string& out) {
  const Ranks& ranks = Ranks::World();
  const std::vector<recon::ListedScene> scenes = recon::ReadSceneList(args.scene);
  auto device = OpenDevice(RankDevice(args.device, ranks));
  std::signal(SIGINT, [](int) { recon::RequestStop(); });
  const size_t n = scenes.size();
  std::vector<double> mine(2 * n, std::nan(""));  // per scene: outcome, seconds
  bool stopped = false;
  for (size_t i = 0; i < n; ++i) {
    if (int(i % size_t(ranks.size())) != ranks.rank()) continue;
    ListedOutcome outcome = ListedOutcome::Interrupted;
    const auto start = std::chrono::steady_clock::now();
    if (!stopped) {
      ReconstructOptions one = options;
      one.scene_file = scenes[i].file;
      one.output_dir = std::filesystem::path(out) / scenes[i].name;
      one.one_process = true;
      one.quiet = options.quiet || ranks.distributed();  // one progress line per terminal
      try {
        const ReconstructResult r = recon::Reconstruct(one, *device);
        if (!r.completed) stopped = true;
        else outcome = r.failed ? ListedOutcome::ModelError : r.diagnosis_ok ? ListedOutcome::Ok : ListedOutcome::NotOk;
        for (const std::string& note : r.notes) std::cerr << "vkrecon run: " << scenes[i].name << ": note: " << note << "\n";
      } catch (const InputError& e) {
        std::cerr << "vkrecon run: " << e.what() << "\n";
        outcome = ListedOutcome::BadInput;
      } catch (const std::exception& e) {
        std::cerr << "vkrecon run: " << scenes[i].name << ": error: " << e.what() << "\n";
        outcome = ListedOutcome::Error;
      }
    }
    mine[2 * i] = double(outcome);
    mine[2 * i + 1] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const std::vector<double> all = ranks.GatherToRoot(mine);
  if (ranks.rank() != 0) return FinishWithDevice(*device, 0);

  int worst = 0;
  std::filesystem::create_directories(out);
  std::ofstream csv(std::filesystem::path(out) / "summary.csv");
  csv << "scene,file,rank,exit_status,verdict,seconds,output\n";
  std::cerr << "vkrecon run: " << n << " scene(s) on " << ranks.size() << " rank(s):\n";
  for (size_t i = 0; i < n; ++i) {
    const size_t owner = i % size_t(ranks.size());
    const auto outcome = ListedOutcome(int(all[owner * 2 * n + 2 * i]));
    const double seconds = all[owner * 2 * n + 2 * i + 1];
    const std::string folder = (std::filesystem::path(out) / scenes[i].name).string();
    worst = std::max(worst, ExitStatus(outcome));
    char line[512];
    std::snprintf(line, sizeof line, "  %-20s rank %-3zu exit %d  %7.1f s  %-26s %s\n", scenes[i].name.c_str(), owner,
                  ExitStatus(outcome), seconds, ToString(outcome), folder.c_str());
    std::cerr << line;
    csv << scenes[i].name << "," << scenes[i].file.string() << "," << owner << "," << ExitStatus(outcome) << ","
        << ToString(outcome) << "," << seconds << "," << folder << "\n";
  }
  return FinishWithDevice(*device, worst);
}

int FinishRun(const ReconstructOptions& options, const std::string& scene, const std::string& out,
           const ReconstructResult& result, const vk::Device& device, const std::string& resume_command) {
  if (!result.completed) {
    std::cerr << "vkrecon run: interrupted; continue with: "
              << (resume_command.empty() ? "vkrecon run " + scene + " -o " + out + " --resume" : resume_command) << "\n";
    return FinishWithDevice(device, 1);
  }
  for (const std::string& note : result.notes) std::cerr << "vkrecon run: note: " << note << "\n";
  if (!options.quiet) std::cerr << "vkrecon run: wrote " << out << "/ (report.html, map.json, chain.csv, composite.exr, model.glb, reprojections/, overlays/)\n";
  if (result.failed) {
    std::cerr << "vkrecon run: error: the result is not trustworthy (see the notes above and map.json's diagnosis)\n";
    return FinishWithDevice(device, 1);
  }
  if (!result.diagnosis_ok)
    std::cerr << "vkrecon run: warning: the diagnosis is not ok (see the notes above and map.json's diagnosis): "
                 "read the intervals with care\n";
  return FinishWithDevice(device, 0);
}

}  // namespace
}  // namespace vkr::app
