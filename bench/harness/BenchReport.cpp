// The outputs of `vkrecon bench`: the --json contract, the human table and the PNG plots.

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "engine/image/Image.h"
#include "engine/image/LinePlot.h"
#include "bench/harness/Bench.h"

namespace fs = std::filesystem;

namespace vkr {
namespace {

using J = nlohmann::ordered_json;

// Finite numbers as they are, the rest as null (JSON has no NaN).
J Finite(double x) { return std::isfinite(x) ? J(x) : J(nullptr); }

J RowJson(const BenchRow& r) {
  J j;
  j["name"] = r.name;
  j["batch"] = r.batch;
  j["hypotheses_per_s"] = r.skipped.empty() ? Finite(r.hypotheses_per_s) : J(nullptr);
  J passes = J::object();
  for (const auto& [pass, ms] : r.passes_ms) passes[pass] = Finite(ms);
  j["passes_ms"] = passes;
  j["sweep"] = r.sweep;
  j["kind"] = r.kind;
  j["x"] = Finite(r.x);
  if (!r.skipped.empty()) j["skipped"] = r.skipped;
  j["wall_ms"] = Finite(r.wall_ms);
  j["cpu_ms"] = Finite(r.cpu_ms);
  j["gpu_ms"] = Finite(r.gpu_ms);
  j["turns"] = r.turns;
  j["repeats"] = r.repeats;
  j["view_textures_per_s"] = Finite(r.view_textures_per_s);
  J shares = J::object();
  for (const auto& [pass, share] : r.share_of_ceiling) shares[pass] = Finite(share);
  j["share_of_ceiling"] = shares;
  j["triangles"] = r.triangles;
  j["backfacing_triangles"] = r.backfacing_triangles;
  j["clipped_triangles"] = r.clipped_triangles;
  j["cameras"] = r.cameras;
  j["width"] = r.width;
  j["height"] = r.height;
  j["atlas"] = r.atlas;
  j["level"] = r.level;
  j["surface_texels"] = r.surface_texels;
  j["device_bytes"] = r.device_bytes;
  j["rss_bytes"] = r.rss_bytes;
  return j;
}

std::string Format(const char* format, double x) {
  char text[64];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

std::string Mib(uint64_t bytes) { return Format("%.1f MiB", double(bytes) / double(1 << 20)); }

// The sweeps that get plots, and how their x axis is drawn.
struct PlotAxis {
  const char* sweep;
  double (*x)(double);
};
double Identity(double x) { return x; }
double Log10(double x) { return std::log10(x); }
double Log2(double x) { return std::log2(x); }
constexpr PlotAxis kAxes[] = {
    {"triangles", Log10}, {"backfacing", Identity}, {"near_clip", Identity},
    {"cameras", Identity}, {"atlas", Log2}, {"batch", Log2},
};

}  // namespace

std::string BenchJson(const BenchReport& report) {
  J j;
  j["device"] = report.device;
  j["rows"] = J::array();
  for (const BenchRow& r : report.rows) j["rows"].push_back(RowJson(r));
  j["device_type"] = report.device_type;
  j["quick"] = report.quick;
  if (!report.only.empty()) j["only"] = report.only;
  j["ceilings"] = {{"copy_bytes_per_s", Finite(report.ceilings.copy_bytes_per_s)},
                   {"copy_buffer_bytes", report.ceilings.copy_bytes},
                   {"fill_fragments_per_s", Finite(report.ceilings.fill_fragments_per_s)},
                   {"fill_side", report.ceilings.fill_side},
                   {"fill_draws", report.ceilings.fill_draws},
                   {"fill_format", "R16G16B16A16_SFLOAT"},
                   {"reduction_texels_per_s", Finite(report.ceilings.reduction_texels_per_s)}};
  j["memory"] = {{"peak_rss_bytes", report.peak_rss_bytes}, {"peak_device_bytes", report.peak_device_bytes}};
  if (report.soak) {
    const BenchSoak& s = *report.soak;
    J samples = J::array();
    for (const BenchSoakSample& x : s.samples)
      samples.push_back({{"evaluations", x.evaluations}, {"rss_bytes", x.rss_bytes}, {"device_bytes", x.device_bytes}});
    j["soak"] = {{"configuration", s.configuration}, {"batch", s.batch}, {"evaluations", s.evaluations},
                 {"hypotheses_per_s", Finite(s.hypotheses_per_s)}, {"flat", s.flat}, {"samples", samples}};
  }
  const BenchBars bars = EvaluateBars(report);
  J jb = J::object();
  if (bars.house_hypotheses_per_s)
    jb["house_hypotheses_per_s"] = {{"value", *bars.house_hypotheses_per_s}, {"bar", kHouseHypothesesPerSBar},
                                    {"met", *bars.house_hypotheses_per_s >= kHouseHypothesesPerSBar}};
  if (bars.batch16_over_batch1)
    jb["batch16_over_batch1"] = {{"value", *bars.batch16_over_batch1}, {"bar", kBatchRatioBar},
                                 {"met", *bars.batch16_over_batch1 >= kBatchRatioBar}};
  j["bars"] = jb;
  j["seconds"] = report.seconds;
  return j.dump(2) + "\n";
}

std::string FormatBenchTable(const BenchReport& report) {
  std::string out;
  char line[512];
  out += "device: " + report.device + " (" + report.device_type + ")" +
         (report.quick ? "  [--quick: small configurations, not the bars']" : "") + "\n\n";
  // One column per pass any row reports, in the order of a hypothesis's passes.
  std::vector<std::string> passes;
  for (const char* known : {"depth", "view_texture", "interior", "composite", "warp", "compare", "reduce"})
    for (const BenchRow& r : report.rows)
      if (r.passes_ms.count(known)) {
        passes.push_back(known);
        break;
      }
  for (const BenchRow& r : report.rows)
    for (const auto& [pass, ms] : r.passes_ms)
      if (std::find(passes.begin(), passes.end(), pass) == passes.end()) passes.push_back(pass);
  auto width = [](const std::string& pass) { return int(std::max<size_t>(8, pass.size())); };
  std::snprintf(line, sizeof line, "%-16s %4s %8s %8s %8s %8s", "row", "K", "hyp/s", "wall_ms", "cpu_ms", "gpu_ms");
  out += line;
  for (const std::string& p : passes) out += " " + std::string(size_t(width(p)) - p.size(), ' ') + p;
  std::snprintf(line, sizeof line, " %10s %9s %10s\n", "view_tex/s", "share v/c", "device");
  out += line;
  auto share = [](const BenchRow& r, const char* name) {
    const auto it = r.share_of_ceiling.find(name);
    return it == r.share_of_ceiling.end() ? std::string("-") : Format("%.0f%%", 100.0 * it->second);
  };
  for (const BenchRow& r : report.rows) {
    if (!r.skipped.empty()) {
      std::snprintf(line, sizeof line, "%-16s %4d  skipped: %s\n", r.name.c_str(), r.batch, r.skipped.c_str());
      out += line;
      continue;
    }
    std::snprintf(line, sizeof line, "%-16s %4d %8.2f %8.2f %8.2f %8.2f", r.name.c_str(), r.batch,
                  r.hypotheses_per_s, r.wall_ms, r.cpu_ms, r.gpu_ms);
    out += line;
    for (const std::string& p : passes) {
      const auto it = r.passes_ms.find(p);
      std::snprintf(line, sizeof line, " %*s", width(p), it == r.passes_ms.end() ? "-" : Format("%.2f", it->second).c_str());
      out += line;
    }
    const std::string views = r.view_textures_per_s > 0 ? Format("%.0f", r.view_textures_per_s) : "-";
    const std::string shares = share(r, "view_texture") + "/" + share(r, "composite");
    std::snprintf(line, sizeof line, " %10s %9s %10s\n", views.c_str(), shares.c_str(), Mib(r.device_bytes).c_str());
    out += line;
  }
  out += "\n(medians over the turns; per hypothesis: wall_ms wall clock, cpu_ms process CPU time (all threads),\n"
         " passes GPU ms; share v/c: view-texture pass against the fill ceiling / composite against the copy ceiling)\n\n";
  const Ceilings& c = report.ceilings;
  out += "ceiling compute copy   " + Format("%.2f GB/s", c.copy_bytes_per_s * 1e-9) + " (read + write, " +
         Mib(c.copy_bytes) + " buffer)\n";
  out += "ceiling fill           " + Format("%.0f Mfragments/s", c.fill_fragments_per_s * 1e-6) + " (RGBA16F " +
         std::to_string(c.fill_side) + "², " + std::to_string(c.fill_draws) + " draws)\n";
  out += "probe: composite's reduction alone " +
         Format("%.1f Mtexels/s", c.reduction_texels_per_s * 1e-6) + "\n";
  out += "peak host RSS          " + Mib(report.peak_rss_bytes) + "\n";
  out += "peak device memory     " + Mib(report.peak_device_bytes) + " (at once: a sweep's likelihoods live together)\n";
  if (report.soak) {
    const BenchSoak& s = *report.soak;
    out += "soak                   " + std::to_string(s.evaluations) + " evaluations (" + s.configuration + "), " +
           Format("%.1f hypotheses/s", s.hypotheses_per_s) + "\n";
    out += "soak memory            RSS " + Mib(s.samples.front().rss_bytes) + " → " + Mib(s.samples.back().rss_bytes) +
           ", device " + Mib(s.samples.front().device_bytes) + " → " + Mib(s.samples.back().device_bytes) + ": " +
           (s.flat ? "flat" : "GROWING") + "\n";
  }
  const BenchBars bars = EvaluateBars(report);
  if (bars.house_hypotheses_per_s)
    out += Format("bar house ≥ %.0f hyp/s   ", kHouseHypothesesPerSBar) + Format("%.1f", *bars.house_hypotheses_per_s) +
           (*bars.house_hypotheses_per_s >= kHouseHypothesesPerSBar ? ": met" : ": NOT met") + "\n";
  if (bars.batch16_over_batch1)
    out += Format("bar K=16 ≥ %.1f × K=1   ", kBatchRatioBar) + Format("%.3f", *bars.batch16_over_batch1) +
           (*bars.batch16_over_batch1 >= kBatchRatioBar ? ": met" : ": NOT met") + "\n";
  out += Format("run time               %.0f s\n", report.seconds);
  return out;
}

std::vector<fs::path> WriteBenchPlots(const BenchReport& report, const fs::path& dir) {
  std::vector<fs::path> files;
  for (const PlotAxis& axis : kAxes) {
    std::vector<double> x, hyps, views;
    for (const BenchRow& r : report.rows) {
      if (r.sweep != axis.sweep || !r.skipped.empty()) continue;
      x.push_back(axis.x(r.x));
      hyps.push_back(r.hypotheses_per_s);
      views.push_back(r.view_textures_per_s);
    }
    if (x.size() < 2) continue;
    fs::create_directories(dir);
    for (const auto& [suffix, y] : {std::pair<const char*, const std::vector<double>*>{"hyps", &hyps}, {"view", &views}}) {
      const fs::path file = dir / (std::string(axis.sweep) + "_" + suffix + ".png");
      WritePng(file, PlotLine(x, *y).image);
      files.push_back(file);
    }
  }
  return files;
}

}  // namespace vkr
