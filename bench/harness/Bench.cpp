#include "bench/harness/Bench.h"

#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <system_error>

#include "engine/common/InputError.h"
#include "bench/harness/BenchScenes.h"
#include "pipelines/likelihood/LikelihoodTool.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

std::string RowLabel(double x) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, x);
  return std::string(text, result.ptr);
}

double MedianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// CPU seconds of this process so far, every thread.
double ProcessCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// A field of /proc/self/status in bytes ("VmRSS", "VmHWM"); 0 where there is none.
uint64_t ProcStatusBytes(const std::string& field) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field + ":", 0) == 0) return std::stoull(line.substr(field.size() + 1)) * 1024;  // kB
  return 0;
}

// The configuration every synthetic sweep varies one factor of (full run; --quick shrinks it).
struct BaseConfig {
  int width = 640, height = 480;
  int cameras = 6;
  int atlas = 512;
  int triangles = 1000;
  int batch = 4;          // batching gains nothing on lavapipe (LAVAPIPE.md); K has its own sweep
  double image_scale = 1; // of the assets' 640×480
};

BaseConfig Base(bool quick) {
  BaseConfig b;
  if (quick) {
    b.width = 160;
    b.height = 120;
    b.atlas = 128;
    b.batch = 2;
    b.image_scale = 0.25;
  }
  return b;
}

// One row to run: where its scene comes from and what it varies.
struct RowPlan {
  std::string name, sweep, kind = "surface";
  double x = 0.0;
  int batch = 1;
  int level = 0;          // pyramid level evaluated (0 = full resolution)
  bool edges = false;     // with the surface likelihood's edge term (likelihood.edges)
  std::string scene_key;  // rows with the same key share one prepared scene
  std::function<BenchScene(const fs::path& dir, vk::Device& device)> prepare;
};

const char* const kAssets[] = {"box", "house", "stairs", "poster"};

std::vector<RowPlan> Plan(const BenchOptions& options) {
  const BaseConfig base = Base(options.quick);
  const bool quick = options.quick;
  std::vector<RowPlan> plan;
  auto synthetic = [&](const std::string& sweep, double x, SyntheticSceneSpec spec, int batch) {
    RowPlan row;
    row.sweep = sweep;
    row.x = x;
    row.name = sweep + "/" + RowLabel(x);
    row.batch = batch;
    row.scene_key = row.name;
    row.prepare = [spec](const fs::path& dir, vk::Device& device) { return MakeSyntheticScene(spec, dir, device); };
    plan.push_back(std::move(row));
  };
  SyntheticSceneSpec spec;
  spec.width = base.width;
  spec.height = base.height;
  spec.cameras = base.cameras;
  spec.atlas = base.atlas;
  spec.triangles = base.triangles;

  const std::vector<int> triangles = quick ? std::vector<int>{12, 1000} : std::vector<int>{12, 100, 1000, 10000, 100000};
  for (int t : triangles) {
    SyntheticSceneSpec s = spec;
    s.triangles = t;
    synthetic("triangles", CylinderTriangles(t), s, base.batch);
  }
  const std::vector<double> shares = quick ? std::vector<double>{0.0, 1.0} : std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0};
  for (double share : shares) {
    SyntheticSceneSpec s = spec;
    s.shape = SyntheticSceneSpec::Shape::BackFacingGrid;
    s.share = share;
    synthetic("backfacing", share, s, base.batch);
  }
  const std::vector<double> clipped = quick ? std::vector<double>{0.0, 1.0} : std::vector<double>{0.0, 0.25, 0.5, 1.0};
  for (double share : clipped) {
    SyntheticSceneSpec s = spec;
    s.shape = SyntheticSceneSpec::Shape::NearClipStrips;
    s.share = share;
    synthetic("near_clip", share, s, base.batch);
  }
  const std::vector<int> cameras = quick ? std::vector<int>{1, 2, 4} : std::vector<int>{1, 2, 4, 8, 16, 32};
  for (int n : cameras) {
    SyntheticSceneSpec s = spec;
    s.cameras = n;
    synthetic("cameras", n, s, base.batch);
  }
  const std::vector<int> atlases = quick ? std::vector<int>{64, 128} : std::vector<int>{256, 512, 1024, 2048};
  for (int a : atlases) {
    SyntheticSceneSpec s = spec;
    s.atlas = a;
    synthetic("atlas", a, s, base.batch);
  }

  // The assets at 640×480 (¼ with --quick); `house` with its first 6 cameras and a 512²
  // atlas, the configuration docs/internals/BENCHMARKS.md names for the `house` row and the batch
  // sweep.
  auto asset = [&](const std::string& name, int max_cameras) {
    const fs::path dir = options.assets_dir / name;
    const double scale = base.image_scale;
    const int atlas = quick ? base.atlas : 512;
    return [dir, scale, max_cameras, atlas](const fs::path& work, vk::Device& device) {
      return PrepareAsset(dir, work, scale, max_cameras, atlas, device);
    };
  };
  const std::vector<int> batches = quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 16, 64, 256};
  for (int k : batches) {
    RowPlan row;
    row.sweep = "batch";
    row.x = k;
    row.name = "batch/" + std::to_string(k);
    row.batch = k;
    row.scene_key = "asset/house";
    row.prepare = asset("house", 6);
    plan.push_back(std::move(row));
  }
  for (const char* kind : {"surface", "image"})
    for (const char* name : kAssets) {
      RowPlan row;
      row.sweep = "assets";
      row.kind = kind;
      row.name = std::string(name) + (row.kind == "surface" ? "" : "/" + row.kind);
      row.batch = 16;  // the assets' sampler.batch
      row.scene_key = std::string("asset/") + name;
      row.prepare = asset(name, std::string(name) == "house" ? 6 : 0);
      plan.push_back(std::move(row));
    }
  // The coarse levels of §7.3, which a run uses first.
  for (int level : {1, 2}) {
    RowPlan row;
    row.sweep = "assets";
    row.name = "house/level" + std::to_string(level);
    row.level = level;
    row.batch = 16;
    row.scene_key = "asset/house";
    row.prepare = asset("house", 6);
    plan.push_back(std::move(row));
  }
  // The `house` row with the edge term: what it costs (docs/internals/LIKELIHOOD.md, "Edges").
  RowPlan edges;
  edges.sweep = "assets";
  edges.name = "house/edges";
  edges.edges = true;
  edges.batch = 16;
  edges.scene_key = "asset/house";
  edges.prepare = asset("house", 6);
  plan.push_back(std::move(edges));
  return plan;
}

bool Selected(const RowPlan& row, const std::string& only) {
  return only.empty() || only == row.name || only == row.sweep;
}

// K hypotheses near the truth, as a sampler's proposals would be: each parameter moved by up
// to ±1 % of its prior's width, deterministically, staying admissible.
std::vector<std::vector<double>> Proposals(const Scene& scene, const std::vector<double>& truth, int k) {
  std::vector<std::vector<double>> batch(size_t(k), truth);
  for (int i = 0; i < k; ++i)
    for (size_t p = 0; p < truth.size(); ++p) {
      const double u = std::fmod(0.6180339887498949 * double(i * 7 + int(p) * 3 + 1), 1.0) * 2.0 - 1.0;
      const double v = truth[p] + 0.01 * scene.parameters[p].prior.Width() * u;
      if (scene.parameters[p].Admissible(v)) batch[size_t(i)][p] = v;
    }
  return batch;
}

// The work a pass does per hypothesis, in the unit of the ceiling that bounds it (fragments
// for the raster passes, bytes for the composite), and that ceiling. The depth pass clears
// and rasterises every camera's whole target; the view-specific texture pass shades every
// surface texel once per camera; the interior pass every surface texel once; the composite
// reads every texel of every view layer (RGBA16F) and of the mask (R32).
void ShareOfCeiling(BenchRow& row, const Ceilings& ceilings) {
  if (row.kind != "surface") return;  // the work model is the surface likelihood's
  const double texels = double(row.surface_texels);
  const double atlas = double(row.atlas >> row.level) * double(row.atlas >> row.level);
  const double pixels = double(row.width >> row.level) * double(row.height >> row.level);
  const std::map<std::string, std::pair<double, double>> work = {
      {"depth", {row.cameras * pixels, ceilings.fill_fragments_per_s}},
      {"view_texture", {row.cameras * texels, ceilings.fill_fragments_per_s}},
      {"interior", {texels, ceilings.fill_fragments_per_s}},
      {"composite", {atlas * (row.cameras * 8.0 + 4.0), ceilings.copy_bytes_per_s}},
  };
  for (const auto& [pass, ms] : row.passes_ms) {
    const auto it = work.find(pass);
    if (it == work.end() || !(ms > 0) || !(it->second.second > 0)) continue;
    row.share_of_ceiling[pass] = it->second.first / (ms * 1e-3) / it->second.second;
  }
}

// A row being timed: its scene and likelihood stay alive while the other rows of its sweep
// take their turns, so that load from other programs falls on every row of a sweep alike.
struct LiveRow {
  const RowPlan* plan = nullptr;
  BenchRow row;
  std::unique_ptr<Scene> scene;            // outlives the likelihood, which refers to it
  std::unique_ptr<Likelihood> likelihood;
  // At least 16 proposals; repeat r evaluates K of them from r·K on (cyclically), so rows
  // of different K average over the same hypotheses.
  std::vector<std::vector<double>> pool;
  std::vector<double> rates, walls, cpus;
  std::map<std::string, std::vector<double>> passes;
  double timed_seconds = 0.0;
};

// Builds the row's likelihood and warms it up; a likelihood that cannot be built
// (InputError) marks the row skipped.
void StartRow(LiveRow& live, const BenchScene& prepared, vk::Device& device) {
  const RowPlan& plan = *live.plan;
  BenchRow& row = live.row;
  row.name = plan.name;
  row.sweep = plan.sweep;
  row.kind = plan.kind;
  row.x = plan.x;
  row.batch = plan.batch;
  row.triangles = prepared.triangles;
  row.cameras = prepared.cameras;
  row.width = prepared.width;
  row.height = prepared.height;
  row.atlas = prepared.atlas;
  row.backfacing_triangles = prepared.backfacing_triangles;
  row.clipped_triangles = prepared.clipped_triangles;

  std::vector<SceneOverride> overrides = prepared.overrides;
  overrides.push_back({"likelihood.kind", plan.kind});
  overrides.push_back({"likelihood.edges", plan.edges ? "true" : "false"});
  live.scene = std::make_unique<Scene>(LoadScene(prepared.scene_file, overrides));
  live.pool = Proposals(*live.scene, live.scene->ValuesFromFile(prepared.at_file), std::max(16, plan.batch));
  LikelihoodSetup setup;
  setup.max_batch = plan.batch;
  setup.profile = true;
  const uint64_t before = device.allocated_bytes();
  try {
    live.likelihood = MakeLikelihood(device, *live.scene, setup);
  } catch (const InputError& e) {
    row.skipped = e.what();
    return;
  }
  row.device_bytes = device.allocated_bytes() - before;
  live.likelihood->SetLevel(plan.level);
  row.level = live.likelihood->level();
  // Warm-up: the first submission JIT-compiles the pipelines (LAVAPIPE.md); one hypothesis
  // is enough for that, and cheap at large K.
  const Evaluation first = live.likelihood->Evaluate({live.pool.front()}).at(0);
  row.surface_texels = uint64_t(first.scalars.seen_multi) + first.scalars.seen_once + first.scalars.seen_none +
                       first.scalars.interior;
}

// Whether the row wants another turn.
bool NeedsTurn(const LiveRow& live, const BenchOptions& options) {
  const int n = live.row.turns;
  if (!live.likelihood || n >= options.max_turns) return false;
  if (n > 0 && live.timed_seconds > options.max_row_seconds) return false;
  return n < options.min_turns || live.timed_seconds < options.min_seconds;
}

// One turn: Evaluate() of K hypotheses, again until the turn has lasted turn_seconds. Records
// the turn's wall clock, process CPU time and mean GPU time per pass, per hypothesis.
void TakeTurn(LiveRow& live, const BenchOptions& options) {
  const int k = live.row.batch;
  const auto t0 = Clock::now();
  const double cpu0 = ProcessCpuSeconds();
  std::map<std::string, double> gpu;
  int evaluations = 0;
  do {
    std::vector<std::vector<double>> batch;
    for (int i = 0; i < k; ++i) batch.push_back(live.pool[(size_t(live.row.repeats) * k + i) % live.pool.size()]);
    live.likelihood->Evaluate(batch);
    for (const auto& [pass, ms] : live.likelihood->LastPassTimesMs()) gpu[pass] += ms;
    ++evaluations;
    ++live.row.repeats;
  } while (Seconds(t0) < options.turn_seconds);
  const double seconds = Seconds(t0);
  const double hypotheses = double(evaluations) * k;
  live.cpus.push_back((ProcessCpuSeconds() - cpu0) * 1e3 / hypotheses);
  live.rates.push_back(hypotheses / seconds);
  live.walls.push_back(seconds * 1e3 / hypotheses);
  for (const auto& [pass, ms] : gpu) live.passes[pass].push_back(ms / evaluations);
  live.timed_seconds += seconds;
  ++live.row.turns;
}

// Medians, rates and shares of ceiling; releases the likelihood.
BenchRow FinishRow(LiveRow& live, const Ceilings& ceilings) {
  BenchRow& row = live.row;
  live.likelihood.reset();
  if (!row.skipped.empty()) return row;
  row.hypotheses_per_s = MedianOf(live.rates);
  row.wall_ms = MedianOf(live.walls);
  row.cpu_ms = MedianOf(live.cpus);
  for (const auto& [pass, ms] : live.passes) {
    row.passes_ms[pass] = MedianOf(ms);
    row.gpu_ms += row.passes_ms[pass];
  }
  if (const auto it = row.passes_ms.find("view_texture"); it != row.passes_ms.end() && it->second > 0)
    row.view_textures_per_s = row.cameras * 1e3 / it->second;
  ShareOfCeiling(row, ceilings);
  return row;
}

BenchSoak Soak(const BenchOptions& options, const fs::path& work, vk::Device& device, const BenchProgress& progress) {
  // Small enough to take about a minute here: the box at ¼ size, a 128² atlas.
  const BenchScene prepared = PrepareAsset(options.assets_dir / "box", work / "soak", 0.25, 0, 128, device);
  const Scene scene = LoadScene(prepared.scene_file, prepared.overrides);
  BenchSoak soak;
  soak.batch = 16;
  soak.configuration = "box, " + std::to_string(prepared.width) + "×" + std::to_string(prepared.height) + ", " +
                       std::to_string(prepared.cameras) + " cameras, 128² atlas, K = 16, surface likelihood";
  const std::vector<std::vector<double>> batch =
      Proposals(scene, scene.ValuesFromFile(prepared.at_file), soak.batch);
  LikelihoodSetup setup;
  setup.max_batch = soak.batch;
  std::unique_ptr<Likelihood> likelihood = MakeLikelihood(device, scene, setup);
  likelihood->Evaluate(batch);  // warm-up
  auto sample = [&](int evaluations) {
    soak.samples.push_back({evaluations, ProcStatusBytes("VmRSS"), device.allocated_bytes()});
  };
  sample(0);
  const auto start = Clock::now();
  int done = 0, next = options.soak_every;
  while (done < options.soak_evaluations) {
    const int k = std::min(soak.batch, options.soak_evaluations - done);
    likelihood->Evaluate(std::vector<std::vector<double>>(batch.begin(), batch.begin() + k));
    done += k;
    if (done >= next || done == options.soak_evaluations) {
      sample(done);
      while (next <= done) next += options.soak_every;
      if (progress) progress("soak: " + std::to_string(done) + "/" + std::to_string(options.soak_evaluations) + " evaluations");
    }
  }
  soak.evaluations = done;
  const double seconds = Seconds(start);
  soak.hypotheses_per_s = seconds > 0 ? done / seconds : 0.0;
  const BenchSoakSample& a = soak.samples.front();
  const BenchSoakSample& b = soak.samples.back();
  soak.flat = double(b.rss_bytes) <= double(a.rss_bytes) * 1.05 + 4.0 * (1 << 20) && b.device_bytes == a.device_bytes;
  return soak;
}

// A scratch folder, removed at the end unless the caller chose it.
class WorkDir {
 public:
  explicit WorkDir(const fs::path& chosen) {
    if (!chosen.empty()) {
      path_ = chosen;
    } else {
      std::random_device rd;
      path_ = fs::temp_directory_path() / ("vkrecon-bench-" + std::to_string(rd()));
      owned_ = true;
    }
    fs::create_directories(path_);
  }
  ~WorkDir() {
    std::error_code ec;
    if (owned_) fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool owned_ = false;
};

std::string DeviceType(const vk::Device& device) {
  switch (device.properties().deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

}  // namespace

bool BenchOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (min_turns < 1) return fail("min_turns must be ≥ 1");
  if (max_turns < min_turns) return fail("max_turns must be ≥ min_turns");
  if (!(turn_seconds >= 0.0) || !(min_seconds >= 0.0) || !(max_row_seconds >= 0.0))
    return fail("turn_seconds, min_seconds and max_row_seconds must be ≥ 0");
  if (soak_evaluations < 1 || soak_every < 1) return fail("the soak needs ≥ 1 evaluation and a sampling interval ≥ 1");
  return true;
}

BenchOptions BenchOptions::Quick() {
  BenchOptions o;
  o.quick = true;
  o.turn_seconds = 0.0;
  o.min_turns = 2;
  o.min_seconds = 0.0;
  o.soak_evaluations = 400;
  o.soak_every = 100;
  o.max_row_seconds = 5.0;
  return o;
}

std::vector<std::string> BenchRowNames(const BenchOptions& options) {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const RowPlan& row : Plan(options))
    for (const std::string& name : {row.sweep, row.name})
      if (seen.insert(name).second) names.push_back(name);
  names.push_back("ceilings");
  names.push_back("soak");
  return names;
}

void CheckOnly(const BenchOptions& options) {
  if (options.only.empty()) return;
  const std::vector<std::string> names = BenchRowNames(options);
  if (std::find(names.begin(), names.end(), options.only) != names.end()) return;
  std::string sweeps;
  for (const std::string& n : names)
    if (n.find('/') == std::string::npos && n != "house" && std::find(std::begin(kAssets), std::end(kAssets), n) == std::end(kAssets))
      sweeps += (sweeps.empty() ? "" : ", ") + n;
  throw InputError("", "--only", "no row or sweep named '" + options.only + "' (sweeps: " + sweeps +
                                     "; rows such as house, poster/image, triangles/1008, cameras/8)");
}

BenchReport RunBenchmarks(const BenchOptions& options, vk::Device& device, const BenchProgress& progress) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("BenchOptions: " + why);
  CheckOnly(options);
  for (const char* asset : kAssets)
    if (!fs::exists(options.assets_dir / asset / "scene.json"))
      throw InputError((options.assets_dir / asset / "scene.json").string(), "", "bundled asset not found (--assets)");

  const auto start = Clock::now();
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  BenchReport report;
  report.device = device.name();
  report.device_type = DeviceType(device);
  report.quick = options.quick;
  report.only = options.only;

  CeilingOptions ceiling_options;
  if (options.quick) {
    ceiling_options.copy_bytes = 16ull << 20;
    ceiling_options.fill_side = 512;
    ceiling_options.fill_draws = 8;
    ceiling_options.repeats = 2;
  }
  say("ceilings: compute copy of " + std::to_string(ceiling_options.copy_bytes >> 20) + " MiB, fill of " +
      std::to_string(ceiling_options.fill_side) + "² RGBA16F");
  report.ceilings = MeasureCeilings(device, ceiling_options);

  const WorkDir work(options.work_dir);
  std::vector<RowPlan> plan = Plan(options);
  plan.erase(std::remove_if(plan.begin(), plan.end(), [&](const RowPlan& r) { return !Selected(r, options.only); }),
             plan.end());
  if (options.only == "ceilings" || options.only == "soak") plan.clear();
  // Sweep by sweep: build every row's likelihood, then time the rows in turn, one
  // repetition each per round, so that a change of load hits all rows of a sweep alike.
  std::map<std::string, BenchScene> scenes;
  size_t done = 0;
  for (size_t first = 0; first < plan.size();) {
    size_t last = first;
    while (last < plan.size() && plan[last].sweep == plan[first].sweep) ++last;
    const auto sweep_start = Clock::now();
    say("sweep " + plan[first].sweep + ": preparing " + std::to_string(last - first) + " rows");
    std::vector<LiveRow> live(last - first);
    for (size_t i = first; i < last; ++i) {
      auto it = scenes.find(plan[i].scene_key);
      if (it == scenes.end()) {
        std::string folder = plan[i].scene_key;
        std::replace(folder.begin(), folder.end(), '/', '_');
        it = scenes.emplace(plan[i].scene_key, plan[i].prepare(work.path() / folder, device)).first;
      }
      live[i - first].plan = &plan[i];
      StartRow(live[i - first], it->second, device);
    }
    report.peak_device_bytes = std::max(report.peak_device_bytes, device.allocated_bytes());
    for (bool more = true; more;) {
      more = false;
      for (LiveRow& row : live)
        if (NeedsTurn(row, options)) {
          TakeTurn(row, options);
          more = true;
        }
    }
    for (LiveRow& row : live) {
      BenchRow result = FinishRow(row, report.ceilings);
      result.rss_bytes = ProcStatusBytes("VmRSS");
      char line[240];
      ++done;
      if (result.skipped.empty())
        std::snprintf(line, sizeof line, "[%zu/%zu] %s: %.1f hypotheses/s, K = %d, %d turns", done, plan.size(),
                      result.name.c_str(), result.hypotheses_per_s, result.batch, result.turns);
      else
        std::snprintf(line, sizeof line, "[%zu/%zu] %s: skipped (%s)", done, plan.size(), result.name.c_str(),
                      result.skipped.c_str());
      say(line);
      report.rows.push_back(std::move(result));
    }
    say("sweep " + plan[first].sweep + ": " + std::to_string(int(Seconds(sweep_start))) + " s");
    first = last;
  }
  if (!report.rows.empty()) {
    // A ceiling is the best the device does: measure again now, under whatever load there is
    // by the end, keep the better figure and recompute the shares against it.
    say("ceilings: once more");
    const Ceilings again = MeasureCeilings(device, ceiling_options);
    Ceilings& c = report.ceilings;
    c.copy_bytes_per_s = std::max(c.copy_bytes_per_s, again.copy_bytes_per_s);
    c.fill_fragments_per_s = std::max(c.fill_fragments_per_s, again.fill_fragments_per_s);
    c.reduction_texels_per_s = std::max(c.reduction_texels_per_s, again.reduction_texels_per_s);
    for (BenchRow& row : report.rows) {
      row.share_of_ceiling.clear();
      ShareOfCeiling(row, c);
    }
  }
  if (options.only.empty() || options.only == "soak") {
    say("soak: " + std::to_string(options.soak_evaluations) + " evaluations");
    report.soak = Soak(options, work.path(), device, say);
    for (const BenchSoakSample& s : report.soak->samples)
      report.peak_device_bytes = std::max(report.peak_device_bytes, s.device_bytes);
  }
  report.peak_rss_bytes = ProcStatusBytes("VmHWM");
  report.seconds = Seconds(start);
  return report;
}

BenchBars EvaluateBars(const BenchReport& report) {
  BenchBars bars;
  if (report.quick) return bars;
  const BenchRow *k1 = nullptr, *k16 = nullptr;
  for (const BenchRow& row : report.rows) {
    if (!row.skipped.empty()) continue;
    if (row.name == "house") bars.house_hypotheses_per_s = row.hypotheses_per_s;
    if (row.name == "batch/1") k1 = &row;
    if (row.name == "batch/16") k16 = &row;
  }
  if (k1 && k16 && k1->hypotheses_per_s > 0) bars.batch16_over_batch1 = k16->hypotheses_per_s / k1->hypotheses_per_s;
  return bars;
}

}  // namespace vkr
