#include "recon/Reconstruct.h"

#include "recon/AtomicWrite.h"
#include "recon/Diagnosis.h"
#include "recon/DistributedTarget.h"
#include "recon/FinerAtlasPolish.h"
#include "recon/LikelihoodTarget.h"
#include "recon/Ranks.h"
#include "recon/SearchSetup.h"
#include "report/Report.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/geometry/SceneGeometry.h"
#include "optimiser/Evidence.h"
#include "optimiser/JsonIntegers.h"
#include "optimiser/Polish.h"
#include "optimiser/Sampler.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "pipelines/rendering/ModelExport.h"
#include "pipelines/likelihood/NoiseCalibration.h"
#include "pipelines/likelihood/Residuals.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace vkr::recon {
namespace {

std::atomic<bool> g_stop{false};

std::string Duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  char buf[32];
  if (seconds < 60) std::snprintf(buf, sizeof buf, "%.0fs", seconds);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  return buf;
}

// One progress line on stderr: redrawn in place on a terminal, every 10 % otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(bool quiet) : quiet_(quiet), tty_(isatty(2)), start_(Clock::now()) {}
  void Update(const opt::Progress& p) {
    if (quiet_) return;
    // With "auto" iterations the schedule's count is a lower bound: the bar fills over it,
    // then the line shows how far R̂ and ESS are from their targets instead of an ETA.
    const double done = p.iterations > 0 ? std::min(1.0, double(p.iteration) / p.iterations) : 1.0;
    const auto now = Clock::now();
    const int decile = int(done * 10);
    if (tty_ ? now - last_ < std::chrono::milliseconds(200)
             : decile == last_decile_ && now - last_ < std::chrono::seconds(30))
      return;
    last_ = now;
    last_decile_ = decile;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double eta = done > 0.01 ? elapsed * (1 - done) / done : NAN;
    const int width = 24, filled = int(done * width);
    char line[256], tail[96];
    if (std::isnan(p.max_rhat))
      std::snprintf(tail, sizeof tail, "ETA %s", p.until_converged && done >= 1.0 ? "?" : Duration(eta).c_str());
    else
      std::snprintf(tail, sizeof tail, "R-hat %.3f  ESS %.0f%s", p.max_rhat, p.min_ess,
                    p.until_converged ? " (until 1.01, 400)" : "");
    std::snprintf(line, sizeof line, "[%s%s] it %d/%s  %-10s level %d  T %.2f  best log post %.1f  acc %.2f  %s",
                  std::string(filled, '#').c_str(), std::string(width - filled, ' ').c_str(), p.iteration,
                  p.until_converged ? "auto" : std::to_string(p.iterations).c_str(), opt::ToString(p.phase), p.level,
                  p.temperature, p.best_log_posterior, p.acceptance, tail);
    std::cerr << (tty_ ? "\r" : "") << line << (tty_ ? "" : "\n") << std::flush;
  }
  void Finish() {
    if (!quiet_ && tty_) std::cerr << "\n";
  }

 private:
  bool quiet_, tty_;
  Clock::time_point start_, last_{};
  int last_decile_ = -1;
};

// The annealing's starting temperature, from the data: at T₀ the log-likelihood should vary
// across the prior by about the number of parameters, so the first iterations can roam. A
// fixed T₀ is far too cold for photographs, whose log-likelihood spans 10⁴–10⁵ nats
// across the prior at full resolution. Scored at the coarsest level, where sampling starts,
// through the (uncalibrated, κ = 1) target, so that MPI ranks share the batch.
double InitialTemperature(const Scene& scene, opt::Target& target) {
  std::mt19937_64 rng(scene.sampler.seed);
  std::vector<std::vector<double>> draws(size_t(target.max_batch()), scene.InitialValues());
  for (auto& psi : draws)
    for (size_t i = 0; i < psi.size(); ++i) {
      const Parameter& p = scene.parameters[i];
      const double u = double(rng() >> 11) * 0x1.0p-53;
      const double x = p.prior.kind == Prior::Kind::Uniform ? p.prior.a + u * (p.prior.b - p.prior.a)
                                                            : p.prior.a + p.prior.b * 2.0 * (u - 0.5) * 1.7;
      if (p.Admissible(x)) psi[i] = x;
    }
  target.SetLevel(target.levels() - 1);
  std::vector<double> values;
  for (const double v : target.Evaluate(draws))
    if (std::isfinite(v)) values.push_back(v);
  target.SetLevel(0);
  if (values.size() < 2) return 10.0;
  double mean = 0.0, var = 0.0;
  for (double v : values) mean += v / values.size();
  for (double v : values) var += (v - mean) * (v - mean) / (values.size() - 1);
  return std::clamp(std::sqrt(var) / double(scene.parameters.size()), 10.0, 1e6);
}

// The σ (0–255) the run ended with: estimated at the mode with `sigma: auto`, else the given one.
double SigmaUsed(const Scene& scene, const opt::SamplerSummary& s) {
  if (s.calibration.is_object() && s.calibration.contains("sigma")) return s.calibration["sigma"].get<double>();
  return scene.likelihood.sigma;
}

// The local search before sampling (SamplerOptions::start_search), with the running MAP
// reported as the sampler reports its own: the best at the current level.
opt::MapSearchSummary RunStartSearch(const Scene& scene, opt::Target& target, double cost, bool quiet,
                                     const std::function<void(const std::vector<double>&)>& on_best) {
  if (!(cost > 0.0)) return {};
  const auto start = Clock::now();
  int level = -1;
  double best = -INFINITY;
  const opt::MapSearchSummary s =
      opt::SearchStart(ParameterSpecs(scene), target, cost, [&](const opt::SearchEvaluation& e) {
        if (e.level != level) best = -INFINITY;
        level = e.level;
        if (!(e.log_posterior > best)) return;
        best = e.log_posterior;
        if (on_best) on_best(*e.psi);
      });
  if (!quiet)
    std::cerr << "vkrecon run: a local search (BOBYQA) from the initial values first: " << s.evaluations
              << " evaluations, " << Duration(std::chrono::duration<double>(Clock::now() - start).count())
              << "; its mode competes with the chains' at the end\n";
  return s;
}

nlohmann::json StartJson(const opt::MapSearchSummary& s) {
  return {{"method", "bobyqa"},
          {"evaluations", s.evaluations},
          {"cost", s.cost},
          {"map", s.map},
          {"log_posterior", s.map.empty() ? nlohmann::json() : nlohmann::json(s.log_posterior)},
          {"message", s.message}};
}

opt::MapSearchSummary StartFromJson(const nlohmann::json& j) {
  opt::MapSearchSummary s;
  s.ok = true;
  s.evaluations = opt::ReadInteger<int64_t>(j.at("evaluations"));
  s.cost = j.at("cost").get<double>();
  s.map = j.at("map").get<std::vector<double>>();
  if (!j.at("log_posterior").is_null()) s.log_posterior = j.at("log_posterior").get<double>();
  s.message = j.at("message").get<std::string>();
  return s;
}

// What every stage of one run shares. Under MPI every rank runs the same stages with the same
// sampler; rank 0 alone writes (checkpoints, clutter masks, outputs) and talks
// (docs/guide/SCALE_OUT.md).
struct RunContext {
  RunContext(const ReconstructOptions& options, vk::Device& device)
      : options(options),
        device(device),
        scene(LoadSearchScene(options.scene_file, options.overrides)),
        ranks(options.one_process ? Ranks::One() : Ranks::World()),
        root(ranks.rank() == 0),
        quiet(options.quiet || !root),
        checkpoint_file(options.output_dir / "checkpoint.json"),
        start_file(options.output_dir / "start_search.json"),
        // Per invocation: a resumed run gets the whole limit again.
        time_limit(options.time_limit >= 0.0 ? options.time_limit : scene.sampler.TimeLimit()) {}

  const ReconstructOptions& options;
  vk::Device& device;
  const Scene scene;
  const Ranks& ranks;
  const bool root, quiet;
  const fs::path checkpoint_file;
  // The local search before sampling (SamplerOptions::start_search), kept beside the
  // checkpoint: a resumed run compares the same mode at the end.
  const fs::path start_file;
  const double time_limit;  // seconds of sampling; 0: none
};

// The scene's sampler block over the defaults, with the command line's --temperatures.
opt::SamplerOptions SamplerOptionsFor(const RunContext& run, int levels) {
  const Scene& scene = run.scene;
  opt::SamplerOptions sampler_options;
  sampler_options.coarse_levels = levels;
  sampler_options.temperatures = std::max(1, scene.sampler.batch / scene.sampler.chains);
  {
    std::string why;
    const nlohmann::json extra = nlohmann::json::parse(scene.sampler.options_json);
    if (!opt::FromJson(extra, &sampler_options, &why))  // why names sampler.FIELD when it can
      throw InputError(scene.file.string(), why.rfind("sampler.", 0) == 0 ? "" : "sampler", why);
  }
  sampler_options.iterations = scene.sampler.iterations;
  // "iterations": "auto" is until_converged over the default schedule; a block that sets
  // until_converged itself lays out its own schedule with the number it gives.
  sampler_options.until_converged = sampler_options.until_converged || scene.sampler.iterations_auto;
  sampler_options.max_iterations = std::max(sampler_options.max_iterations, sampler_options.iterations);
  sampler_options.chains = scene.sampler.chains;
  sampler_options.seed = scene.sampler.seed;
  if (run.options.temperatures > 0) sampler_options.temperatures = run.options.temperatures;
  return sampler_options;
}

// The checkpoint's text with --resume, on every rank; empty: start the run.
// A run stopped before it wrote its first checkpoint (while starting, loading photographs)
// left nothing to continue: resuming it is starting it, which gives the same result. Said
// even with --quiet, in case OUT was mistyped.
// Rank 0 reads the checkpoint and hands it to the others, so all decide alike (a rank that
// looked for the file after rank 0 had written its first one would resume while rank 0
// starts) and OUT need not be visible from every node for this.
std::string ReadCheckpoint(const RunContext& run) {
  std::string checkpoint_text;
  if (run.root && run.options.resume && fs::exists(run.checkpoint_file)) {
    std::ifstream in(run.checkpoint_file, std::ios::binary);
    if (!in) throw InputError(run.checkpoint_file.string(), "", "cannot read the checkpoint");
    checkpoint_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (checkpoint_text.empty()) checkpoint_text = " ";  // empty means "none" below; parsing says what is wrong
  }
  if (run.options.resume) run.ranks.Broadcast(&checkpoint_text);
  if (run.options.resume && checkpoint_text.empty() && run.root)
    std::cerr << "vkrecon run: warning: " << run.checkpoint_file.string()
              << " does not exist (the run stopped before its first checkpoint, or OUT is not the run's "
                 "folder): starting the run from the beginning\n";
  return checkpoint_text;
}

// The local search a resumed run made before its first checkpoint (none when it made none).
opt::MapSearchSummary ReadStartSearch(const RunContext& run) {
  opt::MapSearchSummary start;
  std::string start_text;
  if (run.root && fs::exists(run.start_file)) {
    std::ifstream in(run.start_file, std::ios::binary);
    start_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  run.ranks.Broadcast(&start_text);
  if (!start_text.empty()) {
    try {
      start = StartFromJson(nlohmann::json::parse(start_text));
    } catch (const std::exception& e) {
      throw InputError(run.start_file.string(), "", std::string("cannot resume: ") + e.what());
    }
  }
  return start;
}

// The sampler as the checkpoint left it; InputError when it is not this scene's.
std::unique_ptr<opt::Sampler> ResumeSampler(const RunContext& run, const std::string& checkpoint_text,
                                            opt::Target& target) {
  std::unique_ptr<opt::Sampler> sampler;
  try {
    const nlohmann::json state = nlohmann::json::parse(checkpoint_text);
    sampler = std::make_unique<opt::Sampler>(state, target);
  } catch (const std::exception& e) {
    throw InputError(run.checkpoint_file.string(), "", std::string("cannot resume: ") + e.what());
  }
  const auto& names = sampler->parameters();
  for (size_t i = 0; i < names.size() || i < run.scene.parameters.size(); ++i)
    if (i >= names.size() || i >= run.scene.parameters.size() || names[i].name != run.scene.parameters[i].name)
      throw InputError(run.checkpoint_file.string(), "parameters", "the checkpoint is of another scene");
  return sampler;
}

// A new run: checks, the local search from the initial values (into `start`), the
// annealing's first temperature, and the first checkpoint.
std::unique_ptr<opt::Sampler> StartSampler(const RunContext& run, opt::SamplerOptions sampler_options,
                                           opt::Target& target, Likelihood& likelihood,
                                           opt::MapSearchSummary* start) {
  std::string why;
  if (!opt::ValidateProblem(sampler_options, ParameterSpecs(run.scene), target, &why))
    throw InputError(run.scene.file.string(), "sampler", why);
  PreflightVisibility(run.scene, likelihood);
  // Before the first checkpoint, so that any run that resumes has its mode to compare.
  *start = RunStartSearch(run.scene, target, sampler_options.start_search, run.quiet, run.options.observer.best);
  if (run.root && !start->map.empty()) WriteAtomically(run.start_file, StartJson(*start).dump(2) + "\n");
  sampler_options.initial_temperature = InitialTemperature(run.scene, target);
  auto sampler = std::make_unique<opt::Sampler>(sampler_options, ParameterSpecs(run.scene), target);
  // From here on a resume continues this run rather than starting it again (the initial
  // temperature above is drawn from the photographs: not worth redoing).
  if (run.root) WriteAtomically(run.checkpoint_file, sampler->Checkpoint().dump());
  return sampler;
}

// The sampler's frames, with the progress bar, the time limit, SIGINT and the checkpoints.
opt::SamplerSummary Sample(const RunContext& run, opt::Sampler& sampler, DistributedTarget& target) {
  ProgressBar bar(run.quiet);
  auto last_checkpoint = Clock::now();
  const auto sampling_start = Clock::now();
  bool said_time_limit = false;
  opt::SamplerCallbacks callbacks;
  callbacks.on_frame = [&](const opt::Progress& p) {
    bar.Update(p);
    if (run.options.observer.best && !p.best_psi.empty()) run.options.observer.best(p.best_psi);
    opt::FrameRequest r;
    if (run.time_limit > 0.0 && p.phase == opt::Phase::Sampling &&
        Clock::now() - sampling_start > std::chrono::duration<double>(run.time_limit)) {
      r.finish_sampling = true;
      if (!said_time_limit && !run.quiet)
        std::cerr << "\nvkrecon run: the time limit (" << Duration(run.time_limit)
                  << ") is up: sampling ends once the burn-in (with iterations \"auto\": the schedule) is over\n";
      said_time_limit = true;
    }
    r.stop = g_stop.load();
    if (run.ranks.distributed()) {
      // What changes the sampler's course (a stop, the time limit) is rank 0's decision, so
      // that every rank's sampler stays the same: one byte per frame.
      const auto start = Clock::now();
      unsigned char decision = (r.stop ? 1 : 0) | (r.finish_sampling ? 2 : 0);
      run.ranks.Broadcast(&decision, 1);
      r.stop = decision & 1;
      r.finish_sampling = decision & 2;
      target.times().control += std::chrono::duration<double>(Clock::now() - start).count();
      ++target.times().control_messages;
    }
    r.checkpoint = run.root && (r.stop || Clock::now() - last_checkpoint >
                                              std::chrono::duration<double>(run.options.checkpoint_seconds));
    return r;
  };
  callbacks.on_checkpoint = [&](const nlohmann::json& state) {
    WriteAtomically(run.checkpoint_file, state.dump());
    last_checkpoint = Clock::now();
  };
  opt::SamplerSummary summary;
  opt::Run(sampler, &summary, callbacks);
  bar.Finish();
  return summary;
}

// What a completed run does to its MAP before the outputs, on every rank alike.
struct Refinement {
  // The local search's mode against the chains' MAP, each scored with the colour correction
  // and clutter masks a calibration at it would find (Target::ScoreModes).
  opt::ModeComparison start_compared;
  opt::PolishSummary polish;
};

// The local search's mode adopted where it scores higher, then the MAP polished by BOBYQA
// (optimiser/Polish.h): every rank runs the same search, as it ran the same sampler. Not in
// the checkpoint: a resumed finished run polishes again, alike.
Refinement Refine(const RunContext& run, const opt::Sampler& sampler, opt::Target& target,
                  const opt::MapSearchSummary& start, opt::SamplerSummary* summary) {
  Refinement refined;
  if (summary->termination != opt::Termination::Completed) return refined;
  const RunObserver& observer = run.options.observer;
  if (!start.map.empty()) {
    refined.start_compared = opt::AdoptIfHigher(sampler.parameters(), target, start.map, summary);
    if (refined.start_compared.adopted && observer.best) observer.best(summary->map);
    if (refined.start_compared.adopted && !run.quiet)
      std::cerr << "vkrecon run: the local search's mode scores "
                << refined.start_compared.candidate - refined.start_compared.chains
                << " nats above the chains' MAP: it becomes the MAP\n";
  }
  double best = summary->map_log_posterior;
  refined.polish = opt::PolishMap(sampler.parameters(), target, sampler.options().polish_evaluations, summary,
                                  [&](const opt::SearchEvaluation& e) {
                                    if (!(e.log_posterior > best)) return;
                                    best = e.log_posterior;
                                    if (observer.best) observer.best(*e.psi);
                                  });
  if (!run.quiet && refined.polish.evaluations > 0)
    std::cerr << "vkrecon run: polished the MAP with BOBYQA: " << refined.polish.evaluations << " evaluations, +"
              << refined.polish.improvement << " nats\n";
  return refined;
}

// Rank 0 under MPI: OUT/scale_out.json, beside map.json, not in it (map.json is bit-identical
// to a one-process run's), and one line on what the exchange cost.
void WriteScaleOut(const RunContext& run, const nlohmann::json& exchange) {
  WriteAtomically(run.options.output_dir / "scale_out.json", exchange.dump(2) + "\n");
  if (!run.options.quiet)
    std::cerr << "vkrecon run: " << run.ranks.size() << " MPI ranks: per call "
              << exchange["evaluate_s"].get<double>() * 1e3 << " ms scoring, "
              << exchange["exchange_s"].get<double>() * 1e3 << " ms exchanging ("
              << exchange["share"].get<double>() * 100 << " % with the frame requests), "
              << exchange["wait_s"].get<double>() * 1e3 << " ms waiting for the slowest rank (scale_out.json)\n";
}

// The MAP climbs on at twice the atlas's side (FinerAtlasPolish.h), and is adopted when it
// ran. Not in the checkpoint either: deterministic, so a resumed finished run polishes
// alike. Its evaluations count as level −1 (four of level 0's) for the observer.
FinerAtlasPolish PolishFinerAndAdopt(const RunContext& run, const opt::Sampler& sampler,
                                     opt::SamplerSummary* summary) {
  const RunObserver& observer = run.options.observer;
  const FinerAtlasPolish finer = PolishAtFinerAtlas(
      run.device, run.scene, run.options.overrides, *summary, sampler.options().finer_atlas_polish, run.quiet,
      [&](size_t n) {
        if (observer.evaluated) observer.evaluated(-1, n);
      });
  if (finer.ran) {
    AdoptPolishedMap(finer, run.scene, summary);
    summary->evaluations += finer.evaluations;
    if (observer.best) observer.best(summary->map);
  }
  return finer;
}

// The surface likelihood the outputs are rendered with: full resolution, one hypothesis, the
// run's calibrated σ, position sd and colour correction (its composite is the model's
// texture whichever likelihood sampled).
std::unique_ptr<SurfaceLikelihood> OutputLikelihood(const RunContext& run, const opt::SamplerSummary& summary,
                                                    SurfaceLikelihoodOptions* surface) {
  *surface = SurfaceLikelihoodOptions::FromScene(run.scene);
  surface->max_batch = 1;
  surface->model.sigma = SigmaUsed(run.scene, summary);
  if (summary.calibration.is_object()) {
    const NoiseCalibration calibration = NoiseCalibrationFromJson(summary.calibration);
    surface->model.position_sd = calibration.position_sd;
  }
  auto outputs = std::make_unique<SurfaceLikelihood>(run.device, run.scene, *surface);
  if (summary.calibration.is_object() && !summary.calibration["photometric"].is_null())
    outputs->SetPhotometric(PhotometricFromJson(summary.calibration["photometric"], int(run.scene.cameras.size())));
  return outputs;
}

// The final clutter masks: loaded from the checkpoint's files, written as the outputs'
// OUT/clutter/<camera>.png and set on `outputs`.
struct ClutterOutputs {
  std::vector<Image> masks;
  std::vector<double> share;
  nlohmann::json files = nlohmann::json::array();  // the outputs' names, clutter/<camera>.png
};

ClutterOutputs WriteClutter(const RunContext& run, const nlohmann::json& calibration, SurfaceLikelihood& outputs) {
  ClutterOutputs clutter;
  if (!calibration.is_object() || !calibration.contains("clutter")) return clutter;
  const fs::path& out = run.options.output_dir;
  fs::create_directories(out / "clutter");
  for (const auto& file : calibration["clutter"]["files"]) {
    clutter.masks.push_back(LoadImage(out / file.get<std::string>()));
    const std::string output = "clutter/" + run.scene.cameras[clutter.masks.size() - 1].name + ".png";
    WritePngAtomically(out / output, clutter.masks.back());
    clutter.files.push_back(output);
  }
  clutter.share = calibration["clutter"]["share"].get<std::vector<double>>();
  outputs.SetClutterMasks(clutter.masks);
  return clutter;
}

// The checkpoint's masks other than the final ones (the outputs', the checkpoint's) will
// never be read again.
void RemoveUnusedMasks(const RunContext& run, const nlohmann::json& calibration,
                       const nlohmann::json& chains_calibration) {
  auto lists = [](const nlohmann::json& calibration, const std::string& name) {
    return calibration.is_object() && calibration.contains("clutter") &&
           std::count(calibration["clutter"]["files"].begin(), calibration["clutter"]["files"].end(), name) > 0;
  };
  const fs::path masks = run.options.output_dir / kCheckpointMasks;
  if (!fs::is_directory(masks)) return;
  for (const auto& entry : fs::directory_iterator(masks)) {
    const std::string name = std::string(kCheckpointMasks) + "/" + entry.path().filename().string();
    if (!lists(calibration, name) && !lists(chains_calibration, name)) fs::remove(entry.path());
  }
}

// The outputs at the MAP that show the model: composite.exr/.png, model.glb and
// reprojections/, then the diagnosis of what they show. With the polish at the finer atlas,
// the MAP's log posterior is the one the run's calibrated likelihood gives it.
struct ModelOutputs {
  SceneGeometry geometry;
  Diagnosis diagnosis;
};

ModelOutputs WriteModel(const RunContext& run, const opt::Sampler& sampler, SurfaceLikelihood& outputs,
                        const SurfaceLikelihoodOptions& surface, const ClutterOutputs& clutter,
                        const FinerAtlasPolish& finer, opt::SamplerSummary* summary) {
  const fs::path& out = run.options.output_dir;
  Evaluation at_map;
  const SurfaceDump dump = outputs.EvaluateAndDump(summary->map, &at_map);
  if (finer.ran) {  // the adopted MAP as the run's (calibrated) likelihood scores it
    summary->map_log_prior = opt::LogPrior(sampler.parameters(), summary->map);
    summary->map_log_likelihood = at_map.total() / KappaFromJson(summary->calibration);
    summary->map_log_posterior = summary->map_log_prior + summary->map_log_likelihood;
  }
  const Image composite = DilateAtlas(dump.composite);
  WriteExr(out / "composite.exr", composite);
  WritePng(out / "composite.png", composite);
  SceneGeometry geometry = BuildSceneGeometry(run.scene, run.scene.InitialValues(), surface.atlas);
  WriteTexturedGlb(out / "model.glb", run.scene, geometry, summary->map, composite);
  ReprojectionNoise noise;
  noise.sigma_255 = surface.model.sigma;
  noise.position_sd = surface.model.position_sd;
  noise.photometric = outputs.photometric();
  noise.clutter = clutter.masks;
  const std::vector<Reprojection> reprojections =
      WriteReprojections(out / "reprojections", run.device, run.scene, geometry, summary->map, composite, noise);
  Diagnosis diagnosis =
      Diagnose(run.scene, at_map, surface.model.sigma, *summary,
               NodeResiduals(run.scene, geometry.atlas, dump.deviation, dump.noise), reprojections, clutter.share,
               &finer);
  return {std::move(geometry), std::move(diagnosis)};
}

// map.json's "settings": what the run used, so that it can be repeated.
nlohmann::json SettingsJson(const RunContext& run, const opt::Sampler& sampler) {
  const Scene& scene = run.scene;
  nlohmann::json settings = {
      {"scene", fs::absolute(run.options.scene_file).string()},
      {"overrides", nlohmann::json::array()},
      {"device", run.device.name()},
      {"likelihood", {{"kind", scene.likelihood.kind},
                      {"sigma", scene.likelihood.sigma_auto ? nlohmann::json("auto")
                                                            : nlohmann::json(scene.likelihood.sigma)},
                      {"weights", scene.likelihood.weights}, {"atlas", scene.likelihood.atlas},
                      {"levels", scene.likelihood.levels},
                      {"charts", scene.likelihood.charts},
                      {"photometric", scene.likelihood.photometric},
                      {"clutter", scene.likelihood.clutter},
                      {"sandwich_blocks", scene.likelihood.sandwich_blocks == 0
                                              ? nlohmann::json("auto")
                                              : nlohmann::json(scene.likelihood.sandwich_blocks)},
                      {"partners", scene.likelihood.partners},
                      {"partner_ranking", scene.likelihood.partner_ranking}}},
      {"sampler", opt::ToJson(sampler.options())},
      {"time_limit", run.time_limit}};
  for (const SceneOverride& o : run.options.overrides) settings["overrides"].push_back(o.path + "=" + o.value);
  return settings;
}

// OUT/map.json's content: the sampler's summary and what the run did around it.
nlohmann::json RunMapJson(const RunContext& run, const opt::Sampler& sampler, const opt::SamplerSummary& summary,
                          const opt::MapSearchSummary& start, const Refinement& refined,
                          const FinerAtlasPolish& finer, const ClutterOutputs& clutter, const Diagnosis& diagnosis) {
  nlohmann::json map = opt::MapJson(summary);
  map["start_search"] = StartJson(start);
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  // Both as they were compared: each with the nuisances fitted at it (ScoreModes).
  map["start_search"]["log_posterior_at_end"] = finite(refined.start_compared.candidate);
  map["start_search"]["chains_log_posterior_at_end"] = finite(refined.start_compared.chains);
  map["start_search"]["adopted"] = refined.start_compared.adopted;
  const opt::PolishSummary& polish = refined.polish;
  map["polish"] = {{"method", "bobyqa"}, {"evaluations", polish.evaluations}, {"improved", polish.improved},
                   {"improvement", polish.improvement}, {"message", polish.message}};
  map["finer_atlas_polish"] = ToJson(finer, summary);
  if (!clutter.files.empty()) map["calibration"]["clutter"]["files"] = clutter.files;
  map["settings"] = SettingsJson(run, sampler);
  map["diagnosis"] = diagnosis.json;
  return map;
}

// OUT/chain.csv, and the posterior draws for ArviZ and other CmdStan-CSV readers in
// OUT/chains/stan-<chain>.csv (README, "vkrecon run").
void WriteChains(const RunContext& run, const opt::Sampler& sampler, const opt::SamplerSummary& summary) {
  const fs::path& out = run.options.output_dir;
  {
    std::ostringstream csv;
    csv.imbue(std::locale::classic());
    opt::WriteChainCsv(csv, summary.chain, sampler.parameters());
    WriteAtomically(out / "chain.csv", csv.str());
  }
  fs::create_directories(out / "chains");
  for (int c = 0; c < summary.posterior_chains; ++c) {
    std::ostringstream stan;
    opt::WriteStanCsv(stan, summary, sampler.parameters(), c, sampler.options().seed);
    WriteAtomically(out / "chains" / ("stan-" + std::to_string(c + 1) + ".csv"), stan.str());
  }
}

// Rank 0, after a completed run: everything at the MAP, map.json last and then the report.
void WriteOutputs(const RunContext& run, const opt::Sampler& sampler, const opt::MapSearchSummary& start,
                  const Refinement& refined, const nlohmann::json& chains_calibration, opt::SamplerSummary* summary,
                  ReconstructResult* result) {
  const FinerAtlasPolish finer = PolishFinerAndAdopt(run, sampler, summary);
  result->map = summary->map;
  SurfaceLikelihoodOptions surface;
  const std::unique_ptr<SurfaceLikelihood> outputs = OutputLikelihood(run, *summary, &surface);
  const ClutterOutputs clutter = WriteClutter(run, summary->calibration, *outputs);
  RemoveUnusedMasks(run, summary->calibration, chains_calibration);
  const ModelOutputs model = WriteModel(run, sampler, *outputs, surface, clutter, finer, summary);
  result->notes = model.diagnosis.notes;
  result->diagnosis_ok = model.diagnosis.ok();
  result->failed = model.diagnosis.verdict == Diagnosis::Verdict::Failed;

  const nlohmann::json map = RunMapJson(run, sampler, *summary, start, refined, finer, clutter, model.diagnosis);
  run.scene.WriteValues(run.options.output_dir / "at_map.json", summary->map);  // for render --at
  WriteChains(run, sampler, *summary);
  // Last, so that a map.json is the mark of a finished run: a run killed while writing its
  // outputs shows none, and its checkpoint writes them all again on --resume.
  result->map_json = run.options.output_dir / "map.json";
  WriteAtomically(result->map_json, map.dump(2) + "\n");
  // overlays/, report.html (docs/guide/REPORT.md)
  report::WriteRunReport(run.options.output_dir, run.scene, model.geometry, summary->map);
  if (!run.quiet) std::cerr << summary->BriefReport() << "\n";
  // With sampler.evidence_rungs: the log evidence (docs/internals/EVIDENCE.md), also in map.json.
  if (!run.quiet && summary->evidence) std::cerr << opt::BriefReport(*summary->evidence) << "\n";
}

}  // namespace

void RequestStop() { g_stop = true; }

ReconstructResult Reconstruct(const ReconstructOptions& options, vk::Device& device) {
  const RunContext run(options, device);
  if (run.root) fs::create_directories(options.output_dir);

  std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device, run.scene, run.scene.sampler.batch);
  LikelihoodTarget local_target(*likelihood, run.scene, run.scene.likelihood.sigma_auto,
                                run.scene.likelihood.clutter, options.output_dir, run.root, options.observer.evaluated);
  DistributedTarget target(local_target, run.ranks);
  const opt::SamplerOptions sampler_options = SamplerOptionsFor(run, likelihood->levels());

  const std::string checkpoint_text = ReadCheckpoint(run);
  opt::MapSearchSummary start;
  std::unique_ptr<opt::Sampler> sampler;
  if (!checkpoint_text.empty()) {
    start = ReadStartSearch(run);
    sampler = ResumeSampler(run, checkpoint_text, target);
  } else {
    sampler = StartSampler(run, sampler_options, target, *likelihood, &start);
  }

  opt::SamplerSummary summary = Sample(run, *sampler, target);
  summary.evaluations += start.evaluations;  // every evaluation the run made, the local search's too
  // The checkpoint keeps the chains' calibration, which an adoption replaces in the summary
  // (the nuisances refitted at the adopted mode): a resumed finished run reloads its masks.
  const nlohmann::json chains_calibration = summary.calibration;
  const Refinement refined = Refine(run, *sampler, target, start, &summary);
  const nlohmann::json exchange =
      run.ranks.distributed() ? ExchangeCost(target.times(), run.ranks, run.scene.sampler.batch) : nlohmann::json();

  ReconstructResult result;
  if (summary.termination == opt::Termination::Failed) throw std::runtime_error("sampler failed: " + summary.message);
  if (!run.root) {  // rank 0 writes everything; the MPI job ends when it has
    result.completed = summary.termination == opt::Termination::Completed;
    result.diagnosis_ok = true;
    result.map = summary.map;
    return result;
  }
  if (run.ranks.distributed()) WriteScaleOut(run, exchange);
  if (summary.termination == opt::Termination::Stopped) {
    WriteAtomically(run.checkpoint_file, sampler->Checkpoint().dump());
    return result;  // interrupted: the checkpoint is the output
  }
  result.completed = true;
  result.map = summary.map;
  WriteAtomically(run.checkpoint_file, sampler->Checkpoint().dump());
  // Outputs at the MAP, from a surface likelihood at full resolution.
  likelihood.reset();
  WriteOutputs(run, *sampler, start, refined, chains_calibration, &summary, &result);
  return result;
}

}  // namespace vkr::recon
