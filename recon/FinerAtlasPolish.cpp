#include "recon/FinerAtlasPolish.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>

#include "recon/SearchSetup.h"
#include "pipelines/model/LikelihoodSettings.h"
#include "optimiser/Polish.h"
#include "pipelines/likelihood/NoiseCalibration.h"

namespace vkr::recon {
namespace {

// The doubled atlas's likelihood as the search sees it. Its log-likelihood is divided by the
// run's κ times the ratio of texels: κ counts texels per independent sample, and a texel
// half as wide puts four where one was (Merton: κ 541 at 512², 1,799 at 1024²). Only the
// balance against the prior depends on it, not where the likelihood peaks.
class DoubledAtlasTarget : public opt::Target {
 public:
  DoubledAtlasTarget(Likelihood& likelihood, double kappa, int64_t* evaluations,
                     const std::function<void(size_t)>& on_evaluate)
      : likelihood_(likelihood), kappa_(kappa), evaluations_(evaluations), on_evaluate_(on_evaluate) {}
  int max_batch() const override { return 1; }
  std::vector<double> Evaluate(const std::vector<std::vector<double>>& batch) override {
    std::vector<double> out;
    for (const Evaluation& e : likelihood_.Evaluate(batch)) out.push_back(e.total() / kappa_);
    *evaluations_ += int64_t(batch.size());
    if (on_evaluate_) on_evaluate_(batch.size());
    return out;
  }

 private:
  Likelihood& likelihood_;
  double kappa_;
  int64_t* evaluations_;
  const std::function<void(size_t)>& on_evaluate_;
};

}  // namespace

FinerAtlasPolish PolishAtFinerAtlas(vk::Device& device, const Scene& scene, std::vector<SceneOverride> overrides,
                                    const opt::SamplerSummary& summary, int evaluations, bool quiet,
                                    const std::function<void(size_t)>& on_evaluate) {
  FinerAtlasPolish polish;
  if (evaluations <= 0) return polish;
  const LikelihoodSettings settings = LikelihoodSettingsOf(scene);
  if (settings.kind != LikelihoodKind::Surface) {
    polish.skipped = "the image-space likelihood has no atlas";
    return polish;
  }
  if (summary.map.empty() || summary.parameters.size() != summary.map.size() ||
      !std::isfinite(summary.map_log_posterior)) {
    polish.skipped = "the run has no MAP";
    return polish;
  }
  if (2 * settings.atlas > kFinerAtlasMaxSide) {
    polish.skipped = "the atlas is " + std::to_string(settings.atlas) + "²: a polish at twice that side would cost as much as a run";
    return polish;
  }
  const auto start = std::chrono::steady_clock::now();
  polish.atlas = 2 * settings.atlas;
  overrides.push_back({"likelihood.atlas", std::to_string(polish.atlas)});
  if (!quiet)
    std::cerr << "vkrecon run: polishing the MAP at a " << polish.atlas << "² atlas (at most " << evaluations
              << " evaluations)\n";
  // After a whole run, a doubled atlas that does not fit the device (MemoryPlan.h), a scene
  // file gone since (Python's scene_from_dict) or any other failure here costs the polish,
  // not the run's outputs.
  std::optional<Scene> doubled;  // read again as the run read it: a Scene is not copyable
  std::unique_ptr<Likelihood> likelihood;
  try {
    doubled.emplace(LoadSearchScene(scene.file, overrides));
    likelihood = MakeSearchLikelihood(device, *doubled, 1);
    polish.sigma = CalibrateNoise(*likelihood, summary.map, {}, 1.0, settings.sigma_auto, settings.clutter,
                                  settings.sandwich_blocks)
                       .sigma;
  } catch (const std::exception& e) {
    polish.skipped = std::string("no likelihood at the doubled atlas: ") + e.what();
    if (!quiet) std::cerr << "vkrecon run: warning: not polished at the finer atlas: " << polish.skipped << "\n";
    return polish;
  }
  // polish.evaluations counts the search's; the calibration's few are in the seconds.
  DoubledAtlasTarget target(*likelihood, KappaFromJson(summary.calibration) * 4.0, &polish.evaluations, on_evaluate);
  const std::vector<opt::ParameterSpec> parameters = ParameterSpecs(scene);
  opt::MapSearchSummary search;
  opt::SearchMap(opt::PolishOptions(parameters, summary, evaluations), parameters, target, &search);
  polish.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!search.ok || search.map.size() != summary.map.size()) {
    polish.skipped = "nothing scored at the doubled atlas (" + search.message + ")";
    return polish;
  }
  polish.ran = true;
  polish.map = search.map;
  polish.map_at_atlas = summary.map;
  for (size_t i = 0; i < search.map.size(); ++i) {
    const double sd = summary.parameters[i].PosteriorSd();
    polish.shift_sd.push_back((search.map[i] - summary.map[i]) / sd);
    if (std::isfinite(polish.shift_sd.back()) &&
        (polish.worst < 0 || std::abs(polish.shift_sd.back()) > std::abs(polish.shift_sd[size_t(polish.worst)])))
      polish.worst = int(i);
  }
  if (!quiet) {
    std::fprintf(stderr, "vkrecon run: the mode at a %d² atlas, %.2f posterior sds from the chains' MAP", polish.atlas,
                 polish.MaxShiftSd());
    if (polish.worst >= 0) std::fprintf(stderr, " (%s)", summary.parameters[size_t(polish.worst)].name.c_str());
    std::fprintf(stderr, ", becomes the MAP; %lld evaluations, %.0f s\n", static_cast<long long>(polish.evaluations),
                 polish.seconds);
  }
  return polish;
}

void AdoptPolishedMap(const FinerAtlasPolish& polish, const Scene& scene, opt::SamplerSummary* summary) {
  if (!polish.ran || polish.map.size() != summary->parameters.size()) return;
  summary->map = polish.map;
  for (size_t i = 0; i < summary->parameters.size(); ++i) {
    opt::ParameterSummary& p = summary->parameters[i];
    const double shift = polish.map[i] - polish.map_at_atlas[i];
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    if (i < scene.parameters.size()) {  // the support: a uniform prior's and the hard bounds
      const Parameter& parameter = scene.parameters[i];
      if (parameter.prior.kind == Prior::Kind::Uniform) lo = parameter.prior.a, hi = parameter.prior.b;
      if (parameter.bounds) lo = std::max(lo, parameter.bounds->first), hi = std::min(hi, parameter.bounds->second);
    }
    p.map = polish.map[i];
    p.interval_shift = shift;
    for (double* v : {&p.mean, &p.q025, &p.q975}) *v = std::clamp(*v + shift, lo, hi);
  }
}

nlohmann::json ToJson(const FinerAtlasPolish& polish, const opt::SamplerSummary& summary) {
  if (!polish.ran) return {{"ran", false}, {"skipped", polish.skipped}};
  nlohmann::json map = nlohmann::json::object(), before = nlohmann::json::object(), shift = nlohmann::json::object();
  for (size_t i = 0; i < polish.map.size() && i < summary.parameters.size(); ++i) {
    map[summary.parameters[i].name] = polish.map[i];
    before[summary.parameters[i].name] = polish.map_at_atlas[i];
    shift[summary.parameters[i].name] =
        std::isfinite(polish.shift_sd[i]) ? nlohmann::json(polish.shift_sd[i]) : nlohmann::json();
  }
  return {{"ran", true},
          {"atlas", polish.atlas},
          {"sigma", polish.sigma},
          {"map", map},
          {"map_at_atlas", before},
          {"shift_sd", shift},
          {"max_shift_sd", polish.MaxShiftSd()},
          {"threshold_sd", kFinerAtlasShiftSd},
          {"moved", polish.Moved()},
          {"evaluations", polish.evaluations}};  // not the seconds: map.json is the same from run to run
}

std::string FinerAtlasNote(const FinerAtlasPolish& polish, const opt::SamplerSummary& summary) {
  if (!polish.Moved()) return "";
  const size_t w = size_t(polish.worst);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "the MAP depends on the atlas's resolution: polished at a %d² atlas it moved %.1f posterior sds "
                "(%s %.4g against %.4g at the run's atlas), so the intervals, sampled at the run's atlas and "
                "moved with the MAP, may not describe the likelihood there; run again with --set "
                "likelihood.atlas=%d (docs/internals/LIKELIHOOD.md, \"The finer atlas\")",
                polish.atlas, polish.MaxShiftSd(), summary.parameters[w].name.c_str(), polish.map[w],
                polish.map_at_atlas[w], polish.atlas);
  return buf;
}

}  // namespace vkr::recon
