#pragma once
// `vkrecon likelihood` as typed functions the command line and the tests both call: one
// evaluation of a hypothesis (optionally dumping every intermediate texture and timing the
// passes), and a sweep of one parameter with the others held (thesis Figs 7.10–7.16).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Device.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/likelihood/Likelihood.h"

namespace vkr {

// How the tool sets a likelihood up beyond the scene's own "likelihood" settings.
struct LikelihoodSetup {
  int max_batch = 1;            // hypotheses per Evaluate()
  bool chi2_correction = true;  // §7.4; off shows the raw −½ S/σ²
  bool profile = false;         // GPU timestamps around every pass
};

// The likelihood the scene's "likelihood" block names (LikelihoodSettings::kind), built from its settings
// (SurfaceLikelihoodOptions::FromScene for "surface") and `setup`. Throws InputError for a
// kind that cannot be built and for settings the likelihood rejects.
std::unique_ptr<Likelihood> MakeLikelihood(vk::Device& device, const Scene& scene,
                                           const LikelihoodSetup& setup);

struct LikelihoodToolOptions {
  std::filesystem::path scene_file;
  std::vector<SceneOverride> overrides;
  std::filesystem::path at_file;  // the hypothesis, {"name": value, …}; every parameter
  int level = 0;                  // pyramid level (0 = full resolution)
  bool chi2_correction = true;
  // EvaluateAt: also write every intermediate image here (see DumpEvaluation).
  std::optional<std::filesystem::path> dump_dir;
  // EvaluateAt: also time `profile_repeats` evaluations of a batch of `batch` copies of the
  // hypothesis, after one warm-up (the first submission compiles pipelines).
  bool profile = false;
  int profile_repeats = 5;
  // Hypotheses per submission, for the profile and the sweep: `vkrecon likelihood` passes the
  // scene's sampler.batch, as a run would evaluate them.
  int batch = 1;
};

struct PassProfile {
  int batch = 0;    // hypotheses per submission
  int repeats = 0;  // timed submissions
  std::map<std::string, double> gpu_ms;  // per pass per hypothesis, mean over the repeats
  double hypotheses_per_s = 0.0;         // wall clock, submission to read-back included
};

struct LikelihoodReport {
  std::string kind;  // "surface" | "image"
  int level = 0;
  double sigma = 0.0;  // noise sd on the 0–255 scale
  bool chi2_correction = true;
  Evaluation evaluation;
  // sum_squares / σ² / dof: about 1 for a correct hypothesis under the noise model; NaN
  // when no texel is seen twice.
  double chi2_per_dof = 0.0;
  std::vector<std::filesystem::path> dump_files;  // with dump_dir
  nlohmann::json photometric;  // the per-camera colour correction fitted at the hypothesis (null: none)
  std::optional<PassProfile> profile;             // with profile
};

// Evaluates the hypothesis of `at_file` once (and dumps / profiles when asked).
// Bad input (scene, --at, a level outside [0, levels)) throws InputError.
LikelihoodReport EvaluateAt(const LikelihoodToolOptions& options, vk::Device& device);

// The report as a small two-column table (name, value), one line per field.
std::string FormatReport(const LikelihoodReport& report);

// `--sweep NAME=LO:HI:N`: N ≥ 2 values LO + k(HI−LO)/(N−1) of one parameter.
struct SweepSpec {
  std::string parameter;
  double lo = 0.0, hi = 1.0;
  int steps = 2;
  std::vector<double> Values() const;  // the last is HI exactly
};
// Parses NAME=LO:HI:N; throws InputError naming --sweep when malformed, N < 2 or LO ≥ HI.
SweepSpec ParseSweep(const std::string& text);

struct SweepRow {
  double value = 0.0;
  Evaluation evaluation;  // loglik = evaluation.total()
};

struct SweepResult {
  SweepSpec spec;
  double at_value = 0.0;  // the --at value of the swept parameter (the plot's marker)
  int batch = 0;          // hypotheses per Evaluate()
  std::vector<SweepRow> rows;
};

// Called after each batch with the number of hypotheses evaluated so far and the total.
using SweepProgress = std::function<void(int done, int total)>;

// Evaluates the sweep in batches of min(sampler.batch, N), one Evaluate() each, the other
// parameters at the --at values. The swept parameter must exist and LO, HI lie inside its
// prior and bounds (else InputError naming --sweep).
SweepResult Sweep(const LikelihoodToolOptions& options, const SweepSpec& spec, vk::Device& device,
                  const SweepProgress& progress = {});

// CSV, classic locale, shortest round-trip numbers: header
// value,loglik,log_likelihood,log_occlusion_prior,sum_squares,dof,seen_multi,seen_once,seen_none,interior
void WriteSweepCsv(std::ostream& out, const SweepResult& sweep);
// loglik against the value, with a vertical marker at the --at value.
Image PlotSweep(const SweepResult& sweep);

// Writes a dump into `dir` (created): <name>.exr per image (colour as linear light like
// `render`; deviation data with the numbers as they are, no transfer curve) and <name>.png
// previews (deviation through DeviationRamp). Returns the files written.
std::vector<std::filesystem::path> WriteDump(const LikelihoodDump& dump, const std::filesystem::path& dir);

// Deviation preview: per texel χ²/dof = r/g through a ramp dark blue (0) → green (1, what
// noise alone gives) → yellow (2) → red (≥ 4). Texels seen by fewer than two views are dark
// grey, interior texels mid grey, off-surface texels black.
Image DeviationRamp(const Image& deviation);

}  // namespace vkr
