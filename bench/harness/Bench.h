#pragma once
// `vkrecon bench` (thesis appendix A) as typed functions the command line and the tests both
// call. A run measures the device's own ceilings (BenchCeilings.h), then times likelihood
// evaluations row by row — synthetic sweeps of one factor at a time (triangles, back-facing
// share, near-plane clipping, cameras, atlas size, batch size K) and the four bundled assets
// with each likelihood kind — and ends with a soak that watches host and device memory over
// many evaluations. Every row carries GPU milliseconds per pass (timestamps), wall-clock time
// and each pass's share of the ceiling that bounds it.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/vk/Device.h"
#include "bench/harness/BenchCeilings.h"

namespace vkr {

struct BenchOptions {
  // Small images (¼ size), small atlases, short sweeps, a short soak, small ceilings: for
  // CI and tests. Its numbers are not the configurations the bars name.
  bool quick = false;
  // Empty: everything. Otherwise one row ("house", "cameras/8"), one sweep ("triangles",
  // "backfacing", "near_clip", "cameras", "atlas", "batch", "assets"), "ceilings" (only the
  // ceilings) or "soak". BenchRowNames lists them.
  std::string only;
  // The folder holding the bundled assets (box/, house/, stairs/, poster/).
  std::filesystem::path assets_dir;
  // Scratch folder for scenes and reference images; empty: a fresh folder under the system
  // temp folder, removed when the run ends.
  std::filesystem::path work_dir;
  // The rows of one sweep are timed in turns, round after round, so that load from other
  // programs falls on all of them alike. In a turn a row evaluates its batch of K again and
  // again for at least `turn_seconds` (at least once). Each row gets at least `min_turns`
  // turns and `min_seconds` of timed work, and no turn starts past `max_row_seconds` of timed
  // work or after `max_turns`. Figures are medians over the turns. Five turns, not three:
  // with three, one burst of load on this shared machine could take two of a row's turns
  // and move its median by 15 % (a batch sweep read K=16/K=1 = 0.85 so, and 1.03–1.16 in
  // the repeats minutes later).
  double turn_seconds = 0.5;
  int min_turns = 5;
  double min_seconds = 1.0;
  int max_turns = 30;
  double max_row_seconds = 20.0;
  // The soak: this many evaluations, host RSS and device bytes sampled every `soak_every`.
  int soak_evaluations = 10000;
  int soak_every = 1000;

  bool IsValid(std::string* why) const;
  // The defaults of a --quick run (quick = true, fewer repeats, a short soak).
  static BenchOptions Quick();
};

struct BenchRow {
  std::string name;   // "house", "triangles/1008", "house/image", "house/level1", …
  std::string sweep;  // "triangles", "backfacing", "near_clip", "cameras", "atlas", "batch", "assets"
  std::string kind = "surface";  // likelihood kind
  double x = 0.0;     // the swept value (triangles, share, cameras, atlas side, K; 0 for assets)
  // Why the row has no numbers (e.g. a likelihood kind not built yet); empty when it ran.
  std::string skipped;

  int batch = 0;    // K: hypotheses per Evaluate() (one GPU submission)
  int turns = 0;    // timed turns (see BenchOptions)
  int repeats = 0;  // timed Evaluate() calls over all turns
  double hypotheses_per_s = 0.0;  // median over the turns of hypotheses / wall seconds
  double wall_ms = 0.0;           // wall-clock ms per hypothesis (median), host work and read-back included
  // Process CPU ms per hypothesis (median; all threads, lavapipe's included). Unlike wall
  // time it barely moves when other programs share the cores; on a CPU device with C idle
  // cores, wall_ms ≥ cpu_ms / C.
  double cpu_ms = 0.0;
  std::map<std::string, double> passes_ms;  // GPU ms per pass per hypothesis (median), as the likelihood names them
  double gpu_ms = 0.0;                      // their sum
  // GPU rate of the view-specific texture pass: cameras · 1000 / passes_ms["view_texture"].
  double view_textures_per_s = 0.0;
  // Per pass: its rate over the ceiling that bounds it (see BenchRow's work model in Bench.cpp):
  // depth, view_texture and interior against the fill ceiling, composite against the copy ceiling.
  std::map<std::string, double> share_of_ceiling;

  // The configuration.
  int triangles = 0, cameras = 0, width = 0, height = 0, atlas = 0, level = 0;
  int backfacing_triangles = 0;  // facing away from every camera
  int clipped_triangles = 0;     // crossing the near plane, per camera
  uint64_t surface_texels = 0;   // atlas texels on the surface (at the row's level)

  uint64_t device_bytes = 0;  // Device::allocated_bytes() that building the likelihood added
  uint64_t rss_bytes = 0;     // host resident set after the row
};

struct BenchSoakSample {
  int evaluations = 0;
  uint64_t rss_bytes = 0;
  uint64_t device_bytes = 0;
};

struct BenchSoak {
  std::string configuration;  // what was evaluated, in words
  int batch = 0;
  int evaluations = 0;
  double hypotheses_per_s = 0.0;  // over the whole soak
  std::vector<BenchSoakSample> samples;  // the first after one warm-up batch
  // Memory stayed flat: the last RSS ≤ the first × 1.05 + 4 MiB and device bytes unchanged.
  bool flat = false;
};

struct BenchReport {
  std::string device;       // the Vulkan device's name
  std::string device_type;  // "CPU", "discrete GPU", …
  bool quick = false;
  std::string only;
  Ceilings ceilings;
  std::vector<BenchRow> rows;
  std::optional<BenchSoak> soak;
  uint64_t peak_rss_bytes = 0;     // VmHWM at the end of the run
  // The most Device::allocated_bytes() at once: all likelihoods of one sweep live together.
  uint64_t peak_device_bytes = 0;
  double seconds = 0.0;            // the whole run, wall clock
};

// Every NAME that --only accepts under these options: sweeps, rows, "ceilings", "soak".
std::vector<std::string> BenchRowNames(const BenchOptions& options);

// Throws InputError naming --only when options.only names nothing BenchRowNames lists.
void CheckOnly(const BenchOptions& options);

// One line of progress per step (to stderr in the command line).
using BenchProgress = std::function<void(const std::string& line)>;

// Runs the benchmark. Throws InputError for options.only naming nothing and for unreadable
// assets; a row whose likelihood cannot be built (InputError from MakeLikelihood) is kept
// with `skipped` set; any other failure throws.
BenchReport RunBenchmarks(const BenchOptions& options, vk::Device& device, const BenchProgress& progress = {});

// The `--json` contract (docs/reference/CLI.md, `vkrecon bench`): {"device", "rows": [{"name",
// "batch", "hypotheses_per_s", "passes_ms", …}], …} plus ceilings, soak, memory and bars.
std::string BenchJson(const BenchReport& report);
// An aligned table of the rows, then ceilings, memory, soak and bars.
std::string FormatBenchTable(const BenchReport& report);
// PNG line plots (engine/image/LinePlot.h) into `dir`: per sweep, hypotheses/s
// (`<sweep>_hyps.png`) and view-specific textures/s (`<sweep>_view.png`) against the swept
// value (log₁₀ triangles, log₂ atlas side, log₂ K). Returns the files written.
std::vector<std::filesystem::path> WriteBenchPlots(const BenchReport& report, const std::filesystem::path& dir);

// The bars of bench/RESULTS.md ("Bars"), evaluated on a report; none for a --quick report,
// whose configurations are not the bars'. Until 2026-11-24 they were 30 hypotheses/s and
// 0.9.
constexpr double kHouseHypothesesPerSBar = 60.0;
constexpr double kBatchRatioBar = 1.0;
struct BenchBars {
  std::optional<double> house_hypotheses_per_s;  // the `house` row; bar: kHouseHypothesesPerSBar
  std::optional<double> batch16_over_batch1;     // hypotheses/s at K=16 over K=1; bar: kBatchRatioBar
};
BenchBars EvaluateBars(const BenchReport& report);

}  // namespace vkr
