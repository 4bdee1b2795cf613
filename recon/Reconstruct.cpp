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
#include "optimiser/Polish.h"
#include "optimiser/Sampler.h"
#include "optimiser/SamplerState.h"  // ReadInteger
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
  s.evaluations = opt::detail::ReadInteger<int64_t>(j.at("evaluations"));
  s.cost = j.at("cost").get<double>();
  s.map = j.at("map").get<std::vector<double>>();
  if (!j.at("log_posterior").is_null()) s.log_posterior = j.at("log_posterior").get<double>();
  s.message = j.at("message").get<std::string>();
  return s;
}

}  // namespace

void RequestStop() { g_stop = true; }

ReconstructResult Reconstruct(const ReconstructOptions& options, vk::Device& device) {
  const Scene scene = LoadSearchScene(options.scene_file, options.overrides);
  const fs::path checkpoint_file = options.output_dir / "checkpoint.json";
  // Under MPI every rank runs this function with the same sampler; rank 0 alone writes
  // (checkpoints, clutter masks, outputs) and talks (docs/SCALE_OUT.md).
  const Ranks& ranks = options.one_process ? Ranks::One() : Ranks::World();
  const bool root = ranks.rank() == 0;
  const bool quiet = options.quiet || !root;
  if (root) fs::create_directories(options.output_dir);

  std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device, scene, scene.sampler.batch);
  LikelihoodTarget local_target(*likelihood, scene, scene.likelihood.sigma_auto, scene.likelihood.clutter,
                                options.output_dir, root, options.observer.evaluated);
  DistributedTarget target(local_target, ranks);

  opt::SamplerOptions sampler_options;
  sampler_options.coarse_levels = likelihood->levels();
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
  if (options.temperatures > 0) sampler_options.temperatures = options.temperatures;

  std::unique_ptr<opt::Sampler> sampler;
  // A run stopped before it wrote its first checkpoint (while starting, loading photographs)
  // left nothing to continue: resuming it is starting it, which gives the same result. Said
  // even with --quiet, in case OUT was mistyped.
  // Rank 0 reads the checkpoint and hands it to the others, so all decide alike (a rank that
  // looked for the file after rank 0 had written its first one would resume while rank 0
  // starts) and OUT need not be visible from every node for this.
  std::string checkpoint_text;
  if (root && options.resume && fs::exists(checkpoint_file)) {
    std::ifstream in(checkpoint_file, std::ios::binary);
    if (!in) throw InputError(checkpoint_file.string(), "", "cannot read the checkpoint");
    checkpoint_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (checkpoint_text.empty()) checkpoint_text = " ";  // empty means "none" below; parsing says what is wrong
  }
  if (options.resume) ranks.Broadcast(&checkpoint_text);
  const bool resume = options.resume && !checkpoint_text.empty();
  if (options.resume && !resume && root)
    std::cerr << "vkrecon run: warning: " << checkpoint_file.string()
              << " does not exist (the run stopped before its first checkpoint, or OUT is not the run's "
                 "folder): starting the run from the beginning\n";
  // The local search before sampling (SamplerOptions::start_search), kept beside the
  // checkpoint: a resumed run compares the same mode at the end.
  const fs::path start_file = options.output_dir / "start_search.json";
  opt::MapSearchSummary start;
  if (resume) {
    std::string start_text;
    if (root && fs::exists(start_file)) {
      std::ifstream in(start_file, std::ios::binary);
      start_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    ranks.Broadcast(&start_text);
    if (!start_text.empty()) {
      try {
        start = StartFromJson(nlohmann::json::parse(start_text));
      } catch (const std::exception& e) {
        throw InputError(start_file.string(), "", std::string("cannot resume: ") + e.what());
      }
    }
  }
  if (resume) {
    nlohmann::json state;
    try {
      state = nlohmann::json::parse(checkpoint_text);
      sampler = std::make_unique<opt::Sampler>(state, target);
    } catch (const std::exception& e) {
      throw InputError(checkpoint_file.string(), "", std::string("cannot resume: ") + e.what());
    }
    const auto& names = sampler->parameters();
    for (size_t i = 0; i < names.size() || i < scene.parameters.size(); ++i)
      if (i >= names.size() || i >= scene.parameters.size() || names[i].name != scene.parameters[i].name)
        throw InputError(checkpoint_file.string(), "parameters", "the checkpoint is of another scene");
  } else {
    std::string why;
    if (!opt::ValidateProblem(sampler_options, ParameterSpecs(scene), target, &why))
      throw InputError(scene.file.string(), "sampler", why);
    PreflightVisibility(scene, *likelihood);
    // Before the first checkpoint, so that any run that resumes has its mode to compare.
    start = RunStartSearch(scene, target, sampler_options.start_search, quiet, options.observer.best);
    if (root && !start.map.empty()) WriteAtomically(start_file, StartJson(start).dump(2) + "\n");
    sampler_options.initial_temperature = InitialTemperature(scene, target);
    sampler = std::make_unique<opt::Sampler>(sampler_options, ParameterSpecs(scene), target);
    // From here on a resume continues this run rather than starting it again (the initial
    // temperature above is drawn from the photographs: not worth redoing).
    if (root) WriteAtomically(checkpoint_file, sampler->Checkpoint().dump());
  }

  ProgressBar bar(quiet);
  auto last_checkpoint = Clock::now();
  // Per invocation: a resumed run gets the whole limit again.
  const double time_limit = options.time_limit >= 0.0 ? options.time_limit : scene.sampler.TimeLimit();
  const auto sampling_start = Clock::now();
  bool said_time_limit = false;
  opt::SamplerCallbacks callbacks;
  callbacks.on_frame = [&](const opt::Progress& p) {
    bar.Update(p);
    if (options.observer.best && !p.best_psi.empty()) options.observer.best(p.best_psi);
    opt::FrameRequest r;
    if (time_limit > 0.0 && p.phase == opt::Phase::Sampling &&
        Clock::now() - sampling_start > std::chrono::duration<double>(time_limit)) {
      r.finish_sampling = true;
      if (!said_time_limit && !quiet)
        std::cerr << "\nvkrecon run: the time limit (" << Duration(time_limit)
                  << ") is up: sampling ends once the burn-in (with iterations \"auto\": the schedule) is over\n";
      said_time_limit = true;
    }
    r.stop = g_stop.load();
    if (ranks.distributed()) {
      // What changes the sampler's course (a stop, the time limit) is rank 0's decision, so
      // that every rank's sampler stays the same: one byte per frame.
      const auto start = Clock::now();
      unsigned char decision = (r.stop ? 1 : 0) | (r.finish_sampling ? 2 : 0);
      ranks.Broadcast(&decision, 1);
      r.stop = decision & 1;
      r.finish_sampling = decision & 2;
      target.times().control += std::chrono::duration<double>(Clock::now() - start).count();
      ++target.times().control_messages;
    }
    r.checkpoint = root && (r.stop || Clock::now() - last_checkpoint > std::chrono::duration<double>(options.checkpoint_seconds));
    return r;
  };
  callbacks.on_checkpoint = [&](const nlohmann::json& state) {
    WriteAtomically(checkpoint_file, state.dump());
    last_checkpoint = Clock::now();
  };
  opt::SamplerSummary summary;
  opt::Run(*sampler, &summary, callbacks);
  bar.Finish();
  summary.evaluations += start.evaluations;  // every evaluation the run made, the local search's too
  // The local search's mode against the chains' MAP, each scored with the colour correction
  // and clutter masks a calibration at it would find (Target::ScoreModes).
  opt::ModeComparison start_compared;
  // The checkpoint keeps the chains' calibration, which an adoption replaces in the summary
  // (the nuisances refitted at the adopted mode): a resumed finished run reloads its masks.
  const nlohmann::json chains_calibration = summary.calibration;
  if (summary.termination == opt::Termination::Completed && !start.map.empty()) {
    start_compared = opt::AdoptIfHigher(sampler->parameters(), target, start.map, &summary);
    if (start_compared.adopted && options.observer.best) options.observer.best(summary.map);
    if (start_compared.adopted && !quiet)
      std::cerr << "vkrecon run: the local search's mode scores " << start_compared.candidate - start_compared.chains
                << " nats above the chains' MAP: it becomes the MAP\n";
  }
  // The MAP polished by BOBYQA (optimiser/Polish.h): every rank runs the same search, as it
  // ran the same sampler. Not in the checkpoint: a resumed finished run polishes again, alike.
  opt::PolishSummary polish;
  if (summary.termination == opt::Termination::Completed) {
    double best = summary.map_log_posterior;
    polish = opt::PolishMap(sampler->parameters(), target, sampler->options().polish_evaluations, &summary,
                            [&](const opt::SearchEvaluation& e) {
                              if (!(e.log_posterior > best)) return;
                              best = e.log_posterior;
                              if (options.observer.best) options.observer.best(*e.psi);
                            });
    if (!quiet && polish.evaluations > 0)
      std::cerr << "vkrecon run: polished the MAP with BOBYQA: " << polish.evaluations << " evaluations, +"
                << polish.improvement << " nats\n";
  }
  const nlohmann::json exchange = ranks.distributed() ? ExchangeCost(target.times(), ranks, scene.sampler.batch)
                                                      : nlohmann::json();

  ReconstructResult result;
  if (summary.termination == opt::Termination::Failed) throw std::runtime_error("sampler failed: " + summary.message);
  if (!root) {  // rank 0 writes everything; the MPI job ends when it has
    result.completed = summary.termination == opt::Termination::Completed;
    result.diagnosis_ok = true;
    result.map = summary.map;
    return result;
  }
  if (ranks.distributed()) {
    // Beside map.json, not in it: map.json is bit-identical to a one-process run's.
    WriteAtomically(options.output_dir / "scale_out.json", exchange.dump(2) + "\n");
    if (!options.quiet)
      std::cerr << "vkrecon run: " << ranks.size() << " MPI ranks: per call "
                << exchange["evaluate_s"].get<double>() * 1e3 << " ms scoring, "
                << exchange["exchange_s"].get<double>() * 1e3 << " ms exchanging ("
                << exchange["share"].get<double>() * 100 << " % with the frame requests), "
                << exchange["wait_s"].get<double>() * 1e3 << " ms waiting for the slowest rank (scale_out.json)\n";
  }
  if (summary.termination == opt::Termination::Stopped) {
    WriteAtomically(checkpoint_file, sampler->Checkpoint().dump());
    return result;  // interrupted: the checkpoint is the output
  }
  result.completed = true;
  result.map = summary.map;
  WriteAtomically(checkpoint_file, sampler->Checkpoint().dump());

  // Outputs at the MAP, from a surface likelihood at full resolution (its composite is the
  // model's texture whichever likelihood sampled).
  likelihood.reset();
  // The MAP climbs on at twice the atlas's side (FinerAtlasPolish.h). Not in the checkpoint
  // either: deterministic, so a resumed finished run polishes alike. Its evaluations count
  // as level −1 (four of level 0's) for the observer.
  const FinerAtlasPolish finer = PolishAtFinerAtlas(
      device, scene, options.overrides, summary, sampler->options().finer_atlas_polish, quiet, [&](size_t n) {
        if (options.observer.evaluated) options.observer.evaluated(-1, n);
      });
  if (finer.ran) {
    AdoptPolishedMap(finer, scene, &summary);
    summary.evaluations += finer.evaluations;
    result.map = summary.map;
    if (options.observer.best) options.observer.best(summary.map);
  }
  SurfaceLikelihoodOptions surface = SurfaceLikelihoodOptions::FromScene(scene);
  surface.max_batch = 1;
  surface.model.sigma = SigmaUsed(scene, summary);
  if (summary.calibration.is_object()) {
    const NoiseCalibration calibration = NoiseCalibrationFromJson(summary.calibration);
    surface.model.position_sd = calibration.position_sd;
  }
  SurfaceLikelihood outputs(device, scene, surface);
  if (summary.calibration.is_object() && !summary.calibration["photometric"].is_null())
    outputs.SetPhotometric(PhotometricFromJson(summary.calibration["photometric"], int(scene.cameras.size())));
  std::vector<Image> clutter;
  std::vector<double> clutter_share;
  nlohmann::json clutter_files = nlohmann::json::array();  // the outputs' names, clutter/<camera>.png
  if (summary.calibration.is_object() && summary.calibration.contains("clutter")) {
    fs::create_directories(options.output_dir / "clutter");
    for (const auto& file : summary.calibration["clutter"]["files"]) {
      clutter.push_back(LoadImage(options.output_dir / file.get<std::string>()));
      const std::string output = "clutter/" + scene.cameras[clutter.size() - 1].name + ".png";
      WritePngAtomically(options.output_dir / output, clutter.back());
      clutter_files.push_back(output);
    }
    clutter_share = summary.calibration["clutter"]["share"].get<std::vector<double>>();
    outputs.SetClutterMasks(clutter);
  }
  // The checkpoint's masks other than the final ones (the outputs', the checkpoint's) will
  // never be read again.
  auto lists = [](const nlohmann::json& calibration, const std::string& name) {
    return calibration.is_object() && calibration.contains("clutter") &&
           std::count(calibration["clutter"]["files"].begin(), calibration["clutter"]["files"].end(), name) > 0;
  };
  if (fs::is_directory(options.output_dir / kCheckpointMasks))
    for (const auto& entry : fs::directory_iterator(options.output_dir / kCheckpointMasks)) {
      const std::string name = std::string(kCheckpointMasks) + "/" + entry.path().filename().string();
      if (!lists(summary.calibration, name) && !lists(chains_calibration, name)) fs::remove(entry.path());
    }
  Evaluation at_map;
  const SurfaceDump dump = outputs.EvaluateAndDump(summary.map, &at_map);
  if (finer.ran) {  // the adopted MAP as the run's (calibrated) likelihood scores it
    summary.map_log_prior = opt::LogPrior(sampler->parameters(), summary.map);
    summary.map_log_likelihood = at_map.total() / KappaFromJson(summary.calibration);
    summary.map_log_posterior = summary.map_log_prior + summary.map_log_likelihood;
  }
  const Image composite = DilateAtlas(dump.composite);
  WriteExr(options.output_dir / "composite.exr", composite);
  WritePng(options.output_dir / "composite.png", composite);
  const SceneGeometry geometry = BuildSceneGeometry(scene, scene.InitialValues(), surface.atlas);
  WriteTexturedGlb(options.output_dir / "model.glb", scene, geometry, summary.map, composite);
  ReprojectionNoise noise;
  noise.sigma_255 = surface.model.sigma;
  noise.position_sd = surface.model.position_sd;
  noise.photometric = outputs.photometric();
  noise.clutter = clutter;
  const std::vector<Reprojection> reprojections =
      WriteReprojections(options.output_dir / "reprojections", device, scene, geometry, summary.map, composite, noise);
  const Diagnosis diagnosis = Diagnose(scene, at_map, surface.model.sigma, summary,
                                       NodeResiduals(scene, geometry.atlas, dump.deviation, dump.noise), reprojections,
                                       clutter_share, &finer);
  result.notes = diagnosis.notes;
  result.diagnosis_ok = diagnosis.ok();
  result.failed = diagnosis.verdict == Diagnosis::Verdict::Failed;

  nlohmann::json map = opt::MapJson(summary);
  map["start_search"] = StartJson(start);
  auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  // Both as they were compared: each with the nuisances fitted at it (ScoreModes).
  map["start_search"]["log_posterior_at_end"] = finite(start_compared.candidate);
  map["start_search"]["chains_log_posterior_at_end"] = finite(start_compared.chains);
  map["start_search"]["adopted"] = start_compared.adopted;
  map["polish"] = {{"method", "bobyqa"}, {"evaluations", polish.evaluations}, {"improved", polish.improved},
                   {"improvement", polish.improvement}, {"message", polish.message}};
  map["finer_atlas_polish"] = ToJson(finer, summary);
  if (!clutter_files.empty()) map["calibration"]["clutter"]["files"] = clutter_files;
  map["settings"] = {{"scene", fs::absolute(options.scene_file).string()},
                     {"overrides", nlohmann::json::array()},
                     {"device", device.name()},
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
                     {"sampler", opt::ToJson(sampler->options())},
                     {"time_limit", time_limit}};
  for (const SceneOverride& o : options.overrides) map["settings"]["overrides"].push_back(o.path + "=" + o.value);
  map["diagnosis"] = diagnosis.json;
  scene.WriteValues(options.output_dir / "at_map.json", summary.map);  // for render --at
  {
    std::ostringstream csv;
    csv.imbue(std::locale::classic());
    opt::WriteChainCsv(csv, summary.chain, sampler->parameters());
    WriteAtomically(options.output_dir / "chain.csv", csv.str());
  }
  // The posterior draws for ArviZ and other CmdStan-CSV readers (README, "vkrecon run").
  fs::create_directories(options.output_dir / "chains");
  for (int c = 0; c < sampler->options().chains; ++c) {
    std::ostringstream stan;
    opt::WriteStanCsv(stan, summary, sampler->parameters(), c, sampler->options().seed);
    WriteAtomically(options.output_dir / "chains" / ("stan-" + std::to_string(c + 1) + ".csv"), stan.str());
  }
  // Last, so that a map.json is the mark of a finished run: a run killed while writing its
  // outputs shows none, and its checkpoint writes them all again on --resume.
  result.map_json = options.output_dir / "map.json";
  WriteAtomically(result.map_json, map.dump(2) + "\n");
  report::WriteRunReport(options.output_dir, scene, geometry, summary.map);  // overlays/, report.html (docs/REPORT.md)
  if (!quiet) std::cerr << summary.BriefReport() << "\n";
  return result;
}

}  // namespace vkr::recon
