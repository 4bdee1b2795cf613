#include <atomic>
#include <csignal>
#include <iostream>

#include "apps/Commands.h"
#include "recon/Ranks.h"
#include "recon/SceneComparison.h"

namespace vkr::app {
namespace {

std::atomic<bool> g_compare_interrupted{false};  // SIGINT: the running scene checkpoints and stops
void InterruptCompare(int) { g_compare_interrupted = true; }

}  // namespace

int RunCompare(int argc, char** argv) {
  CLI::App app(
      "Which scene do the photographs support? Runs every SCENE (a scene file or a folder with a scene.json) "
      "with the evidence ladder on (sampler.evidence_rungs, default 12) into OUT/<name>, or reads a finished "
      "run's folder (one with a map.json), and writes the table OUT/compare.md (also printed) and "
      "OUT/compare.json: log Z by stepping stone and by thermodynamic integration with their errors, the log "
      "Bayes factor against the best, the posterior probability of each scene under equal prior odds, the "
      "MAP's log likelihood, chi2/dof and a verdict, with the doubts that could change it (estimators "
      "disagree, ESS < 200, a rung pair that barely swaps: shown where the verdict would change with errors "
      "four times as large; compare.json lists them all). All scenes score one likelihood: the first scene's run (or the first finished "
      "run) calibrates sigma, delta and kappa, which the others then hold fixed (likelihood.sigma, "
      "likelihood.position_sd, likelihood.kappa); clutter masks are off (likelihood.clutter=false); each "
      "scene fits its own colour correction at its mode. Put the scene you expect to win first. The scenes must "
      "look through the same cameras at the same photographs. Under mpirun the scenes after the first share "
      "the ranks. See docs/guide/WHICH_SCENE.md.",
      "compare");
  std::vector<std::string> scenes, sets;
  std::string out;
  int device_index = -1;
  recon::CompareOptions options;
  app.add_option("scenes", scenes, "two or more scene files, scene folders or finished runs' folders")
      ->required()->expected(2, -1);
  app.add_option("-o,--output", out, "output folder: OUT/<name>/ per scene, compare.md, compare.json")->required();
  app.add_option("--set", sets, "override a scene-file field in every scene, e.g. --set sampler.iterations=2000 "
                                "(repeatable; after compare's own settings, so it may change them)");
  app.add_option("--rungs", options.rungs, "evidence ladder rungs (sampler.evidence_rungs; default 12)")
      ->check(CLI::Range(2, 1000));
  app.add_option("--device", device_index, "Vulkan device index from `vkrecon devices`");
  app.add_flag("-q,--quiet", options.base.quiet, "no progress bars");
  app.add_option("--time-limit", options.base.time_limit, "seconds each scene's sampling may take (0: none)")
      ->check(CLI::Range(0.0, 1e9));
  if (auto status = Parse(app, argc, argv)) return *status;
  for (const std::string& s : scenes) options.inputs.push_back(s);
  options.overrides = ParseOverrides(sets);
  options.base.output_dir = out;
  options.base.should_stop = [] { return g_compare_interrupted.load(); };
  const recon::Ranks& ranks = recon::Ranks::World();
  options.base.ranks = &ranks;
  auto device = OpenDevice(device_index);
  std::signal(SIGINT, InterruptCompare);
  const std::vector<recon::ComparedScene> rows = recon::CompareScenes(options, *device);
  if (ranks.rank() == 0) {
    std::cout << recon::MarkdownTable(rows);
    std::cerr << "vkrecon compare: wrote " << out << "/compare.md and compare.json\n";
  }
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
