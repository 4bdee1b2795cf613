#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iostream>

#include "apps/Commands.h"
#include "engine/common/InputError.h"
#include "recon/Ranks.h"
#include "recon/Reconstruct.h"
#include "recon/SceneList.h"
#include "recon/SearchSetup.h"

namespace vkr::app {

using recon::Ranks;
using recon::ReconstructOptions;
using recon::ReconstructSummary;

namespace {

// Set by SIGINT; the run's should_stop reads it, checkpoints and stops after the frame.
std::atomic<bool> g_interrupted{false};
void Interrupt(int) { g_interrupted = true; }

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

// The exit status and the closing lines of rank 0 (or the one process).
int FinishRun(const ReconstructOptions& options, const std::string& scene, const std::string& out,
              const ReconstructSummary& summary, const vk::Device& device, const std::string& resume_command = "");

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
  const std::vector<SceneOverride> overrides = ParseOverrides(scene.sets);
  options.output_dir = out;
  options.should_stop = [] { return g_interrupted.load(); };
  const Ranks& ranks = Ranks::World();
  options.ranks = &ranks;
  if (recon::IsSceneList(scene.scene)) {
    const std::vector<recon::ListedScene> scenes = recon::ReadSceneList(scene.scene);
    auto device = OpenDevice(RankDevice(scene.device, ranks));
    std::signal(SIGINT, Interrupt);
    return FinishWithDevice(*device, recon::ReconstructList(scenes, overrides, options, ranks, *device));
  }
  if (!ranks.distributed()) {
    auto device = OpenDevice(scene.device);
    options.scene = std::make_shared<const Scene>(recon::LoadSearchScene(scene.scene, overrides));
    std::signal(SIGINT, Interrupt);
    ReconstructSummary summary;
    recon::Reconstruct(options, *device, &summary);
    return FinishRun(options, scene.scene, out, summary, *device);
  }
  // One of several MPI ranks (docs/guide/SCALE_OUT.md). A rank that fails must end the whole job:
  // the others would wait for it forever in the next exchange.
  const std::string resume = "mpirun -n " + std::to_string(ranks.size()) + " vkrecon run " + scene.scene + " -o " + out + " --resume";
  try {
    auto device = OpenDevice(RankDevice(scene.device, ranks));
    options.scene = std::make_shared<const Scene>(recon::LoadSearchScene(scene.scene, overrides));
    std::signal(SIGINT, Interrupt);
    if (ranks.rank() == 0) {
      g_terminated_message = "\nvkrecon run: the MPI job was ended (a rank failed or was killed; mpirun names it): no "
                             "result was written; the last checkpoint is in " + out + "/checkpoint.json; continue with the same command and --resume: " +
                             resume + "\n";
      std::signal(SIGTERM, OnTerminate);
    }
    ReconstructSummary summary;
    recon::Reconstruct(options, *device, &summary);
    if (ranks.rank() != 0) return FinishWithDevice(*device, 0);
    return FinishRun(options, scene.scene, out, summary, *device, resume);
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

int FinishRun(const ReconstructOptions& options, const std::string& scene, const std::string& out,
              const ReconstructSummary& summary, const vk::Device& device, const std::string& resume_command) {
  if (!summary.completed()) {
    std::cerr << "vkrecon run: interrupted; continue with: "
              << (resume_command.empty() ? "vkrecon run " + scene + " -o " + out + " --resume" : resume_command) << "\n";
    return FinishWithDevice(device, 1);
  }
  for (const std::string& note : summary.diagnosis.notes) std::cerr << "vkrecon run: note: " << note << "\n";
  if (!options.quiet) std::cerr << "vkrecon run: wrote " << out << "/ (report.html, map.json, chain.csv, composite.exr, model.glb, reprojections/, overlays/)\n";
  if (summary.failed()) {
    std::cerr << "vkrecon run: error: the result is not trustworthy (see the notes above and map.json's diagnosis)\n";
    return FinishWithDevice(device, 1);
  }
  if (!summary.diagnosis.ok())
    std::cerr << "vkrecon run: warning: the diagnosis is not ok (see the notes above and map.json's diagnosis): "
                 "read the intervals with care\n";
  return FinishWithDevice(device, 0);
}

}  // namespace
}  // namespace vkr::app
