// `vkrecon bench`: parses its options and calls RunBenchmarks (bench/harness/Bench.h).
#include <unistd.h>

#include <cstdlib>
#include <iostream>

#include "apps/Commands.h"
#include "bench/harness/Bench.h"
#include "bench/peers/PeersBench.h"
#include "engine/common/InputError.h"

namespace fs = std::filesystem;

namespace vkr::app {
namespace {

// --assets, else VKRECON_ASSETS, else ./assets, else the assets/ folder of the source tree
// the binary was built in (build*/apps/vkrecon → assets/) or installed with it.
fs::path FindAssets(const std::string& given) {
  if (!given.empty()) return given;
  if (const char* env = std::getenv("VKRECON_ASSETS")) return env;
  std::vector<fs::path> candidates = {fs::current_path() / "assets"};
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  for (int up = 0; !ec && up < 4 && exe.has_parent_path(); ++up) {
    exe = exe.parent_path();
    candidates.push_back(exe / "assets");
    candidates.push_back(exe / "share" / "vkrecon" / "assets");  // installed: PREFIX/bin/vkrecon
  }
  for (const fs::path& c : candidates)
    if (fs::exists(c / "house" / "scene.json")) return c;
  return candidates.front();
}

// `--only peers` (bench/peers/PeersBench.h): the MAP searches of `run` and NLopt compared, a Markdown
// table on stdout (or --json).
int RunPeersBench(bool quick, bool json, bool quiet, const fs::path& assets, const std::string& work, bool resume,
                  int device_index) {
  PeersOptions options = quick ? PeersOptions::Quick() : PeersOptions();
  options.assets_dir = assets;
  options.work_dir = work;
  options.resume = resume;
  CheckPeersOptions(options);  // bad input fails before the device opens
  auto device = OpenDevice(device_index);
  const PeersProgress progress = [&](const std::string& line) {
    if (!quiet) std::cerr << "vkrecon bench peers: " << line << "\n";
  };
  const PeersReport report = RunPeers(options, *device, progress);  // it says which device
  std::cout << (json ? PeersJson(report).dump(2) + "\n" : PeersTable(report)) << std::flush;
  progress("took " + std::to_string(int(report.wall_s)) + " s");
  return FinishWithDevice(*device, 0);
}

}  // namespace

int RunBench(int argc, char** argv) {
  CLI::App app(
      "Throughput of the likelihoods (thesis appendix A): sweeps of triangles, back-facing share, "
      "near-plane clipping, cameras, atlas size and batch size K, the four bundled assets with each "
      "likelihood kind, the device's own ceilings (compute copy, fill), memory and a soak. A table on "
      "stdout (or --json), progress on stderr.",
      "bench");
  bool json = false, quick = false, quiet = false, resume = false;
  std::string only, plots, assets, work;
  int device_index = -1, soak = 0;
  app.add_flag("--json", json,
               "print {\"device\", \"rows\": [{\"name\", \"batch\", \"hypotheses_per_s\", \"passes_ms\", ...}], "
               "\"ceilings\", \"memory\", \"soak\", \"bars\"} instead of the table");
  app.add_option("--only", only,
                 "run one row (house, cameras/8, triangles/1008, ...) or one sweep (triangles, backfacing, "
                 "near_clip, cameras, atlas, batch, assets), or only the ceilings or the soak; `peers` compares "
                 "`run` with NLopt's methods at finding the MAP (4 assets x 5 seeds at sigma 16, ~40 min; "
                 "--quick: box and poster, 1 seed, small images)");
  app.add_flag("--quick", quick, "small images, atlases and sweeps, a short soak: for CI and tests");
  app.add_option("--plots", plots, "write PNG plots of every sweep into this folder");
  app.add_option("--assets", assets,
                 "folder of the bundled assets (default: VKRECON_ASSETS, ./assets, or the source tree's)");
  app.add_option("--work", work, "keep the generated scenes and images in this folder (default: a temp folder)");
  app.add_flag("--resume", resume,
               "with --only peers and --work: keep the (asset, seed) groups already in WORK/peers.json, measured with "
               "the same settings on the same device, and run the rest");
  app.add_option("--soak", soak, "evaluations of the soak (default 10000; 400 with --quick)");
  app.add_option("--device", device_index, "Vulkan device index from `vkrecon devices`");
  app.add_flag("-q,--quiet", quiet, "no progress on stderr");
  if (auto status = Parse(app, argc, argv)) return *status;

  if (only == "peers") return RunPeersBench(quick, json, quiet, FindAssets(assets), work, resume, device_index);
  if (resume) throw InputError("", "--resume", "only `--only peers` goes on from its work folder; the other rows take minutes");

  BenchOptions options = quick ? BenchOptions::Quick() : BenchOptions();
  options.only = only;
  options.assets_dir = FindAssets(assets);
  options.work_dir = work;
  if (soak < 0) throw InputError("", "--soak", "must be ≥ 1");
  if (soak > 0) {
    options.soak_evaluations = soak;
    options.soak_every = std::max(1, std::min(options.soak_every, soak / 10));
  }
  CheckOnly(options);  // bad input fails before the device opens

  auto device = OpenDevice(device_index);
  const BenchProgress progress = [&](const std::string& line) {
    if (!quiet) std::cerr << "vkrecon bench: " << line << "\n";
  };
  progress("on " + device->name());
  const BenchReport report = RunBenchmarks(options, *device, progress);
  std::cout << (json ? BenchJson(report) : FormatBenchTable(report)) << std::flush;
  if (!plots.empty()) {
    const std::vector<fs::path> files = WriteBenchPlots(report, plots);
    progress("wrote " + std::to_string(files.size()) + " plots to " + plots);
  }
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
