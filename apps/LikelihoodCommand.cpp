#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <system_error>

#include "apps/Commands.h"
#include "engine/common/InputError.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "recon/SearchSetup.h"

namespace fs = std::filesystem;

namespace vkr::app {
namespace {

// Opens a file for writing, creating its folder; a path that cannot be written is bad input.
std::ofstream OpenOutput(const fs::path& file, const char* option) {
  std::error_code ec;
  if (file.has_parent_path()) fs::create_directories(file.parent_path(), ec);
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string(), "", std::string("cannot write the ") + option + " file");
  return out;
}

// The sweep plot goes where --plot says; else beside a CSV file (FILE.png); else nowhere.
std::optional<fs::path> PlotPath(const std::string& plot, const std::string& csv) {
  if (!plot.empty()) return fs::path(plot);
  if (csv.empty()) return std::nullopt;
  fs::path png = fs::path(csv).replace_extension(".png");
  if (png == fs::path(csv)) png += ".png";
  return png;
}

}  // namespace

int RunLikelihood(int argc, char** argv) {
  CLI::App app(
      "Evaluate the likelihood of the scene's reference images at the parameter values P: one "
      "evaluation (a table on stdout), a sweep of one parameter (CSV + plot), every intermediate "
      "texture (--dump) or GPU time per pass (--profile).",
      "likelihood");
  SceneArgs scene;
  LikelihoodToolOptions options;
  std::string at, sweep, out, plot, dump;
  bool no_correction = false, quiet = false;
  AddSceneArgs(app, scene);
  app.add_option("--at", at, "parameter values, a JSON file {\"name\": value, ...}")->required();
  auto* sweep_option = app.add_option(
      "--sweep", sweep,
      "NAME=LO:HI:N: evaluate N >= 2 values LO + k(HI-LO)/(N-1) of parameter NAME, the others at "
      "--at; CSV on stdout (or -o) with header value,loglik,log_likelihood,log_occlusion_prior,"
      "sum_squares,dof,seen_multi,seen_once,seen_none,interior,log_edges,edge_length");
  app.add_option("-o,--output", out, "--sweep: write the CSV to FILE (and the plot to FILE with .png)")
      ->needs(sweep_option);
  app.add_option("--plot", plot,
                 "--sweep: write the plot (loglik against the value, marker at the --at value) to "
                 "this PNG (default: beside -o FILE; none when the CSV goes to stdout)")
      ->needs(sweep_option);
  app.add_option("--dump", dump,
                 "write view_<camera>.exr, composite.exr, deviation.exr (+ PNG previews) and "
                 "evaluation.json to this folder")
      ->excludes(sweep_option);
  app.add_flag("--profile", options.profile,
               "time sampler.batch copies of the hypothesis per submission: GPU ms per pass per "
               "hypothesis and hypotheses/s")
      ->excludes(sweep_option);
  app.add_option("--level", options.level, "pyramid level, 0 = full resolution (default 0)");
  app.add_flag("--no-correction", no_correction,
               "drop the chi-square sample-size correction (thesis 7.4): log L = -S/(2 sigma^2)");
  app.add_flag("-q,--quiet", quiet, "print nothing but results and errors");
  if (auto status = Parse(app, argc, argv)) return *status;

  options.scene_file = scene.scene;
  options.overrides = ParseOverrides(scene.sets);
  options.at_file = at;
  options.chi2_correction = !no_correction;
  if (!dump.empty()) options.dump_dir = fs::path(dump);
  {
    LoadOptions load;
    load.require_images = false;  // checked once, when the likelihood loads them
    options.batch = recon::SamplerOptionsOf(LoadScene(options.scene_file, options.overrides, load)).batch;
  }
  std::optional<SweepSpec> spec;
  if (!sweep.empty()) spec = ParseSweep(sweep);  // before the device: bad input fails fast

  auto device = OpenDevice(scene.device);
  if (!spec) {
    const LikelihoodReport report = EvaluateAt(options, *device);
    std::cout << FormatReport(report) << std::flush;
    if (!quiet) {
      if (options.dump_dir)
        std::cerr << "vkrecon likelihood: wrote " << report.dump_files.size() << " files to "
                  << options.dump_dir->string() << "\n";
      std::cerr << "vkrecon likelihood: " << report.kind << " likelihood at level " << report.level
                << " (" << device->name() << ")\n";
    }
    return FinishWithDevice(*device, 0);
  }

  const auto start = std::chrono::steady_clock::now();
  bool first_batch = true;
  const SweepProgress progress = [&](int done, int total) {
    const bool single_batch = first_batch && done == total;
    first_batch = false;
    if (quiet || single_batch) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[160];
    std::snprintf(line, sizeof line, "vkrecon likelihood: sweep %s: %d/%d hypotheses (%.1f s)\n",
                  spec->parameter.c_str(), done, total, s);
    std::cerr << line;
  };
  const SweepResult result = Sweep(options, *spec, *device, progress);
  if (out.empty()) {
    WriteSweepCsv(std::cout, result);
    std::cout << std::flush;
  } else {
    std::ofstream csv = OpenOutput(out, "-o");
    WriteSweepCsv(csv, result);
    if (!csv.flush()) throw std::runtime_error("cannot write " + out);
  }
  const std::optional<fs::path> png = PlotPath(plot, out);
  if (png) {
    std::error_code ec;
    if (png->has_parent_path()) fs::create_directories(png->parent_path(), ec);
    WritePng(*png, PlotSweep(result));
  }
  if (!quiet) {
    std::cerr << "vkrecon likelihood: " << result.rows.size() << " values of " << spec->parameter
              << " in batches of " << result.batch;
    if (!out.empty()) std::cerr << ", wrote " << out;
    if (png) std::cerr << (out.empty() ? ", wrote " : " and ") << png->string();
    std::cerr << " (" << device->name() << ")\n";
  }
  return FinishWithDevice(*device, 0);
}

}  // namespace vkr::app
