#include "optimiser/Polish.h"

#include <algorithm>
#include <cmath>

namespace vkr::opt {
namespace {

void SetMap(const std::vector<double>& map, double log_prior, double log_likelihood, SamplerSummary* summary) {
  summary->map = map;
  summary->map_log_prior = log_prior;
  summary->map_log_likelihood = log_likelihood;
  summary->map_log_posterior = log_prior + log_likelihood;
  for (size_t i = 0; i < summary->parameters.size() && i < map.size(); ++i) summary->parameters[i].map = map[i];
}

}  // namespace

MapSearchOptions PolishOptions(const std::vector<ParameterSpec>& parameters, const SamplerSummary& summary,
                               int evaluations) {
  MapSearchOptions options;
  options.method = SearchMethod::Bobyqa;
  options.max_cost = evaluations;
  options.levels = 1;
  options.start = summary.map;
  options.tolerance = 1e-9;
  for (size_t i = 0; i < parameters.size(); ++i) {
    const double width = parameters[i].Width();
    double sd = i < summary.parameters.size() ? summary.parameters[i].PosteriorSd() : NAN;
    if (!std::isfinite(sd)) sd = 1e-3 * width;
    options.initial_steps.push_back(std::clamp(2.0 * sd, 1e-6 * width, 0.05 * width));
  }
  return options;
}

PolishSummary PolishMap(const std::vector<ParameterSpec>& parameters, Target& target, int evaluations,
                        SamplerSummary* summary, const SearchCallback& on_evaluation) {
  PolishSummary out;
  if (evaluations <= 0 || summary->map.empty() || !std::isfinite(summary->map_log_posterior)) return out;
  const MapSearchOptions options = PolishOptions(parameters, *summary, evaluations);
  MapSearchSummary search;
  SearchMap(options, parameters, target, &search, on_evaluation);
  out.evaluations = search.evaluations;
  out.message = search.message;
  summary->evaluations += search.evaluations;
  if (search.ok && search.log_posterior > summary->map_log_posterior) {
    out.improved = true;
    out.improvement = search.log_posterior - summary->map_log_posterior;
    SetMap(search.map, search.log_prior, search.log_likelihood, summary);
  }
  return out;
}

MapSearchSummary SearchStart(const std::vector<ParameterSpec>& parameters, Target& target, double cost,
                             const SearchCallback& on_evaluation) {
  MapSearchSummary search;
  if (!(cost > 0.0)) return search;
  MapSearchOptions options;
  options.method = SearchMethod::Bobyqa;
  options.max_cost = cost;
  options.levels = target.levels();
  SearchMap(options, parameters, target, &search, on_evaluation);
  return search;
}

ModeComparison AdoptIfHigher(const std::vector<ParameterSpec>& parameters, Target& target,
                             const std::vector<double>& candidate, SamplerSummary* summary) {
  ModeComparison c;
  if (candidate.size() != parameters.size() || summary->map.size() != parameters.size()) return c;
  const double log_prior = LogPrior(parameters, candidate);
  if (!std::isfinite(log_prior)) return c;
  const std::vector<double> scores = target.ScoreModes({summary->map, candidate});
  summary->evaluations += 2;
  c.chains = LogPrior(parameters, summary->map) + scores.at(0);
  c.candidate = log_prior + scores.at(1);
  if (!std::isfinite(c.candidate) || !(c.candidate > c.chains)) return c;
  // The colour correction and masks fitted at the chains' mode would otherwise go on
  // describing it: in the polish, and in the outputs a run writes at its MAP.
  const nlohmann::json refit = target.RefitAt(candidate);
  target.SetLevel(0);
  const double log_likelihood = target.Evaluate({candidate}).at(0);
  summary->evaluations += 1;
  if (!std::isfinite(log_likelihood)) {
    if (!refit.is_null()) target.RestoreCalibration(summary->calibration);
    return c;
  }
  if (!refit.is_null()) summary->calibration = refit;
  SetMap(candidate, log_prior, log_likelihood, summary);
  summary->map_from_search = true;
  c.adopted = true;
  return c;
}

}  // namespace vkr::opt
