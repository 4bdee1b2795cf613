#include "recon/Reconstruct.h"

#include "recon/AtomicWrite.h"
#include "recon/Diagnosis.h"
#include "recon/DistributedTarget.h"
#include "recon/FinerAtlasPolish.h"
#include "recon/LikelihoodTarget.h"
#include "recon/Ranks.h"
#include "recon/RunOutputs.h"
#include "recon/RunStages.h"
#include "recon/SearchSetup.h"
#include "report/Report.h"

#include <unistd.h>

#include <algorithm>
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
#include "engine/scene/SettingsReader.h"
#include "optimiser/Evidence.h"
#include "optimiser/Polish.h"
#include "optimiser/Sampler.h"
#include "pipelines/likelihood/LikelihoodTool.h"
#include "pipelines/likelihood/SurfaceLikelihood.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace vkr::recon {

std::string Duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  char buf[32];
  if (seconds < 60) std::snprintf(buf, sizeof buf, "%.0fs", seconds);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(seconds) / 60, int(seconds) % 60);
  return buf;
}

namespace {

// One progress line on `out` (null: none): redrawn in place on a terminal's stderr, every
// 10 % otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream* out) : out_(out), tty_(out == &std::cerr && isatty(2)), start_(Clock::now()) {}
  void Update(const opt::Progress& p) {
    if (!out_) return;
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
    *out_ << (tty_ ? "\r" : "") << line << (tty_ ? "" : "\n") << std::flush;
  }
  void Finish() {
    if (out_ && tty_) *out_ << "\n";
  }

 private:
  std::ostream* out_;
  bool tty_;
  Clock::time_point start_, last_{};
  int last_decile_ = -1;
};

// The annealing's starting temperature, from the data: at T₀ the log-likelihood should vary
// across the prior by about the number of parameters, so the first iterations can roam. A
// fixed T₀ is far too cold for photographs, whose log-likelihood spans 10⁴–10⁵ nats
// across the prior at full resolution. Scored at the coarsest level, where sampling starts,
// through the (uncalibrated, κ = 1) target, so that MPI ranks share the batch.
double InitialTemperature(const Scene& scene, std::uint64_t seed, opt::Target& target) {
  std::mt19937_64 rng(seed);
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

// The local search before sampling (SamplerOptions::start_search), with the running MAP
// reported as the sampler reports its own: the best at the current level.
opt::MapSearchSummary RunStartSearch(const Scene& scene, opt::Target& target, double cost, std::ostream* say,
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
  if (say)
    *say << "vkrecon run: a local search (BOBYQA) from the initial values first: " << s.evaluations
              << " evaluations, " << Duration(std::chrono::duration<double>(Clock::now() - start).count())
              << "; its mode competes with the chains' at the end\n";
  return s;
}

// The scene's sampler block with the likelihood's levels (unless the block sets
// coarse_levels) and the command line's --temperatures.
opt::SamplerOptions SamplerOptionsFor(const RunContext& run, int levels) {
  opt::SamplerOptions sampler_options = run.sampler;
  if (!SettingsReader(run.scene, "sampler").Find("coarse_levels")) sampler_options.coarse_levels = levels;
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
  if (run.options.resume && checkpoint_text.empty() && run.Warn())
    *run.Warn() << "vkrecon run: warning: " << run.checkpoint_file.string()
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
      start = StartSearchFromJson(nlohmann::json::parse(start_text));
    } catch (const std::exception& e) {
      throw InputError(run.start_file.string(), "", std::string("cannot resume: ") + e.what());
    }
  }
  return start;
}

// The sampler's state with the scene's likelihood settings and max_side (which photographs the
// likelihood compares) beside it, atomically.
void WriteCheckpoint(const RunContext& run, nlohmann::json state) {
  state["likelihood_settings"] = ToJson(run.likelihood);
  state["max_side"] = run.scene.max_side;
  WriteAtomically(run.checkpoint_file, state.dump());
}

// InputError naming the first likelihood setting a checkpoint's run had otherwise: chains
// resumed under another likelihood would sample two posteriors as one.
void RequireSameLikelihood(const RunContext& run, const nlohmann::json& state) {
  if (!state.is_object()) return;
  const auto require = [&](const std::string& field, const nlohmann::json& then, const nlohmann::json& now) {
    if (then != now)
      throw InputError(run.checkpoint_file.string(), field,
                       "the checkpoint's run had " + then.dump() + ", this one has " + now.dump() +
                           ": resume with the same setting, or start again without --resume");
  };
  if (const auto it = state.find("max_side"); it != state.end()) require("max_side", *it, run.scene.max_side);
  if (!state.contains("likelihood_settings")) return;  // written before they were kept
  const nlohmann::json now = ToJson(run.likelihood);
  for (const auto& [key, then] : state["likelihood_settings"].items())
    if (now.contains(key)) require("likelihood." + key, then, now[key]);
}

// The sampler as the checkpoint left it; InputError when it is not this scene's.
std::unique_ptr<opt::Sampler> ResumeSampler(const RunContext& run, const std::string& checkpoint_text,
                                            opt::Target& target) {
  const auto unreadable = [&](const std::exception& e) {
    return InputError(run.checkpoint_file.string(), "", std::string("cannot resume: ") + e.what());
  };
  nlohmann::json state;
  try {
    state = nlohmann::json::parse(checkpoint_text);
  } catch (const std::exception& e) {
    throw unreadable(e);
  }
  // Before the sampler restores the target's state (its clutter masks are of the photographs).
  RequireSameLikelihood(run, state);
  std::unique_ptr<opt::Sampler> sampler;
  try {
    sampler = std::make_unique<opt::Sampler>(state, target);
  } catch (const std::exception& e) {
    throw unreadable(e);
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
  *start = RunStartSearch(run.scene, target, sampler_options.start_search, run.Say(), run.options.observer.best);
  if (run.root && !start->map.empty()) WriteAtomically(run.start_file, ToJson(*start).dump(2) + "\n");
  sampler_options.initial_temperature = InitialTemperature(run.scene, sampler_options.seed, target);
  auto sampler = std::make_unique<opt::Sampler>(sampler_options, ParameterSpecs(run.scene), target);
  // From here on a resume continues this run rather than starting it again (the initial
  // temperature above is drawn from the photographs: not worth redoing).
  if (run.root) WriteCheckpoint(run, sampler->Checkpoint());
  return sampler;
}

// The sampler's frames, with the progress bar, the time limit, SIGINT and the checkpoints.
opt::SamplerSummary Sample(const RunContext& run, opt::Sampler& sampler, DistributedTarget& target) {
  ProgressBar bar(run.Say());
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
      if (!said_time_limit && run.Say())
        *run.Say() << "\nvkrecon run: the time limit (" << Duration(run.time_limit)
                  << ") is up: sampling ends once the burn-in (with iterations \"auto\": the schedule) is over\n";
      said_time_limit = true;
    }
    r.stop = run.options.should_stop && run.options.should_stop();
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
    WriteCheckpoint(run, state);
    last_checkpoint = Clock::now();
  };
  opt::SamplerSummary summary;
  opt::Run(sampler, &summary, callbacks);
  bar.Finish();
  return summary;
}

// The local search's mode adopted where it scores higher (each scored with the colour
// correction and clutter masks a calibration at it would find: Target::ScoreModes), then the
// MAP polished by BOBYQA (optimiser/Polish.h): every rank runs the same search, as it ran the
// same sampler. Not in the checkpoint: a resumed finished run polishes again, alike.
void Refine(const RunContext& run, const opt::Sampler& sampler, opt::Target& target, ReconstructSummary* out) {
  if (!out->completed()) return;
  opt::SamplerSummary* summary = &out->sampler;
  const opt::MapSearchSummary& start = out->start_search;
  opt::ModeComparison& compared = out->start_compared;
  const RunObserver& observer = run.options.observer;
  if (!start.map.empty()) {
    compared = opt::AdoptIfHigher(sampler.parameters(), target, start.map, summary);
    if (compared.adopted && observer.best) observer.best(summary->map);
    if (compared.adopted && run.Say())
      *run.Say() << "vkrecon run: the local search's mode scores " << compared.candidate - compared.chains
                 << " nats above the chains' MAP: it becomes the MAP\n";
  }
  double best = summary->map_log_posterior;
  out->polish = opt::PolishMap(sampler.parameters(), target, sampler.options().polish_evaluations, summary,
                                  [&](const opt::SearchEvaluation& e) {
                                    if (!(e.log_posterior > best)) return;
                                    best = e.log_posterior;
                                    if (observer.best) observer.best(*e.psi);
                                  });
  if (run.Say() && out->polish.evaluations > 0)
    *run.Say() << "vkrecon run: polished the MAP with BOBYQA: " << out->polish.evaluations << " evaluations, +"
               << out->polish.improvement << " nats\n";
}

// Rank 0 under MPI: OUT/scale_out.json, beside map.json, not in it (map.json is bit-identical
// to a one-process run's), and one line on what the exchange cost.
void WriteScaleOut(const RunContext& run, const nlohmann::json& exchange) {
  WriteAtomically(run.options.output_dir / "scale_out.json", exchange.dump(2) + "\n");
  if (run.Say())
    *run.Say() << "vkrecon run: " << run.ranks.size() << " MPI ranks: per call "
               << exchange["evaluate_s"].get<double>() * 1e3 << " ms scoring, "
              << exchange["exchange_s"].get<double>() * 1e3 << " ms exchanging ("
              << exchange["share"].get<double>() * 100 << " % with the frame requests), "
              << exchange["wait_s"].get<double>() * 1e3 << " ms waiting for the slowest rank (scale_out.json)\n";
}


// Rank 0, after a completed run: everything at the MAP, then the writer over the summary
// (map.json last), then the report.
void WriteOutputs(const RunContext& run, const opt::Sampler& sampler, const nlohmann::json& chains_calibration,
                  ReconstructSummary* summary) {
  SceneGeometry geometry;
  FinishAtMap(run, sampler, chains_calibration, summary, &geometry);
  for (fs::path& file : WriteRunFiles(*summary, run.scene)) summary->written.push_back(std::move(file));
  // overlays/, report.html (docs/guide/REPORT.md)
  report::WriteRunReport(run.options.output_dir, run.scene, geometry, summary->map());
  summary->written.push_back(run.options.output_dir / "report.html");
  if (run.Say()) *run.Say() << summary->sampler.BriefReport() << "\n";
  // With sampler.evidence_rungs: the log evidence (docs/internals/EVIDENCE.md), also in map.json.
  if (run.Say() && summary->sampler.evidence) *run.Say() << opt::BriefReport(*summary->sampler.evidence) << "\n";
}

// What the evidence is of: the noise model the ladder scored with, and which of its numbers
// the scene fixed (two runs' evidences compare only under one likelihood).
nlohmann::json EvidenceLikelihood(const LikelihoodSettings& settings, const nlohmann::json& calibration) {
  if (!calibration.is_object() || !calibration.contains("sigma")) return nullptr;
  return {{"sigma", calibration["sigma"]},
          {"position_sd", calibration.value("position_sd", settings.position_sd)},
          {"kappa", calibration.value("kappa", 1.0)},
          {"sigma_fixed", !settings.sigma_auto},
          {"kappa_fixed", settings.kappa > 0.0},
          {"kind", ToString(settings.kind)},
          {"photometric", ToString(settings.photometric)},
          {"clutter", settings.clutter},
          {"edges", settings.edges}};
}

}  // namespace

bool ReconstructOptions::IsValid(std::string* why) const {
  const auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (!scene) return fail("no scene: load one with LoadSearchScene");
  if (scene->parameters.empty()) return fail("the scene declares no parameter: nothing to reconstruct");
  if (output_dir.empty()) return fail("no output folder");
  if (!(checkpoint_seconds >= 0.0)) return fail("checkpoint_seconds must be at least 0");
  if (temperatures < 0) return fail("temperatures must be at least 0 (0: the scene's)");
  return true;
}

void Reconstruct(const ReconstructOptions& options, vk::Device& device, ReconstructSummary* out) {
  if (std::string why; !options.IsValid(&why)) throw std::invalid_argument("Reconstruct: " + why);
  const RunContext run(options, device);
  if (run.root) fs::create_directories(options.output_dir);

  std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device, run.scene, run.sampler.batch);
  LikelihoodTarget local_target(*likelihood, run.scene, run.likelihood.sigma_auto, run.likelihood.clutter,
                                options.output_dir, run.root, options.observer.evaluated);
  DistributedTarget target(local_target, run.ranks);
  const opt::SamplerOptions sampler_options = SamplerOptionsFor(run, likelihood->levels());

  const std::string checkpoint_text = ReadCheckpoint(run);
  ReconstructSummary summary;
  summary.output_dir = options.output_dir;
  std::unique_ptr<opt::Sampler> sampler;
  if (!checkpoint_text.empty()) {
    summary.start_search = ReadStartSearch(run);
    sampler = ResumeSampler(run, checkpoint_text, target);
  } else {
    sampler = StartSampler(run, sampler_options, target, *likelihood, &summary.start_search);
  }

  summary.sampler = Sample(run, *sampler, target);
  summary.termination = summary.sampler.termination;
  // every evaluation the run made, the local search's too
  summary.sampler.evaluations += summary.start_search.evaluations;
  // The checkpoint keeps the chains' calibration, which an adoption replaces in the summary
  // (the nuisances refitted at the adopted mode): a resumed finished run reloads its masks.
  const nlohmann::json chains_calibration = summary.sampler.calibration;
  summary.evidence_likelihood = EvidenceLikelihood(run.likelihood, chains_calibration);
  Refine(run, *sampler, target, &summary);
  const nlohmann::json exchange =
      run.ranks.distributed() ? ExchangeCost(target.times(), run.ranks, run.sampler.batch) : nlohmann::json();

  if (summary.termination == opt::Termination::Failed)
    throw std::runtime_error("sampler failed: " + summary.sampler.message);
  // Rank 0 writes everything; the MPI job ends when it has. Stopped, the checkpoint is the output.
  if (run.root && run.ranks.distributed()) WriteScaleOut(run, exchange);
  if (run.root) WriteCheckpoint(run, sampler->Checkpoint());
  if (run.root && summary.completed()) {
    likelihood.reset();  // the outputs come from a surface likelihood at full resolution
    WriteOutputs(run, *sampler, chains_calibration, &summary);
  }
  *out = std::move(summary);
}

}  // namespace vkr::recon
