#include "recon/Fit.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "recon/AtomicWrite.h"
#include "recon/LikelihoodTarget.h"
#include "recon/SearchSetup.h"
#include "engine/common/InputError.h"

namespace fs = std::filesystem;

namespace vkr::recon {
namespace {

// One line per tenth of the budget and per level: a search of a few minutes says where it is.
class FitProgress {
 public:
  FitProgress(bool quiet, double budget) : quiet_(quiet), budget_(budget) {}
  void Update(const opt::SearchEvaluation& e) {
    if (std::isfinite(e.log_posterior) && e.log_posterior > best_) best_ = e.log_posterior;
    const int tenth = int(10.0 * e.cost / budget_);
    if (quiet_ || (tenth == tenth_ && e.level == level_)) return;
    tenth_ = tenth;
    level_ = e.level;
    char line[160];
    std::snprintf(line, sizeof line, "vkrecon fit: level %d  %lld evaluations  %.1f of %.0f full-res equivalents  best log post %.1f\n",
                  e.level, static_cast<long long>(e.evaluations), e.cost, budget_, best_);
    std::cerr << line;
  }

 private:
  bool quiet_;
  double budget_;
  int tenth_ = -1, level_ = -1;
  double best_ = -INFINITY;
};

}  // namespace

void CheckFitOptions(const FitOptions& options) {
  if (!(std::isfinite(options.evaluations) && options.evaluations >= 1))
    throw InputError("", "--evaluations", "the budget must be at least 1 full-resolution evaluation");
  if (options.levels < 0) throw InputError("", "--levels", "must be ≥ 0 (0: all the scene's levels)");
  if (options.restarts < 0) throw InputError("", "--restarts", "must be ≥ 0");
}

FitResult FitMap(const FitOptions& options, vk::Device& device) {
  CheckFitOptions(options);
  const Scene scene = LoadSearchScene(options.scene_file, options.overrides);
  // NLopt scores one hypothesis at a time: a batch of 1 keeps the device's buffers small.
  std::unique_ptr<Likelihood> likelihood = MakeSearchLikelihood(device, scene, 1);
  PreflightVisibility(scene, *likelihood);
  LikelihoodTarget target(*likelihood, scene, false, false, options.output_dir, false);

  opt::MapSearchOptions search;
  search.method = options.method;
  search.max_cost = options.evaluations;
  search.levels = options.levels > 0 ? options.levels : likelihood->levels();
  search.seed = SamplerOptionsOf(scene).seed;
  search.restarts = options.restarts;
  FitProgress progress(options.quiet, options.evaluations);
  FitResult result;
  for (const Parameter& p : scene.parameters) result.names.push_back(p.name);
  const auto start = std::chrono::steady_clock::now();
  opt::SearchMap(search, ParameterSpecs(scene), target, &result.summary, [&](const opt::SearchEvaluation& e) {
    progress.Update(e);
    if (options.on_evaluation) options.on_evaluation(e);
  });
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const opt::MapSearchSummary& s = result.summary;
  if (!s.ok) throw std::runtime_error("fit failed: " + s.message);
  if (!options.quiet) std::cerr << "vkrecon fit: " << s.BriefReport() << "\n";
  if (options.output_dir.empty()) return result;

  fs::create_directories(options.output_dir);
  nlohmann::json parameters = nlohmann::json::object();
  for (size_t i = 0; i < result.names.size(); ++i) parameters[result.names[i]] = {{"map", s.map[i]}};
  nlohmann::json overrides = nlohmann::json::array();
  for (const SceneOverride& o : options.overrides) overrides.push_back(o.path + "=" + o.value);
  const nlohmann::json map = {
      {"map_only", true},
      {"note", "MAP only: no posterior mean, sd or intervals (vkrecon run gives them)"},
      {"method", opt::ToString(s.method)},
      {"parameters", parameters},
      {"log_posterior", s.log_posterior},
      {"log_prior", s.log_prior},
      {"log_likelihood", s.log_likelihood},
      {"evaluations", s.evaluations},
      {"full_resolution_equivalents", s.cost},
      {"levels", s.levels},
      {"level_evaluations", s.level_evaluations},
      {"restarts", s.restarts},
      {"wall_s", result.wall_s},
      {"message", s.message},
      {"settings",
       {{"scene", fs::absolute(options.scene_file).string()},
        {"overrides", overrides},
        {"device", device.name()},
        {"budget", options.evaluations},
        {"levels", search.levels},
        {"restarts", search.restarts},
        {"seed", search.seed}}}};
  scene.WriteValues(options.output_dir / "at_map.json", s.map);  // for render --at, likelihood --at
  result.map_json = options.output_dir / "map.json";
  WriteAtomically(result.map_json, map.dump(2) + "\n");  // last: the mark of a finished fit
  return result;
}

}  // namespace vkr::recon
