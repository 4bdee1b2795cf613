#include "optimiser/Polish.h"

#include <algorithm>
#include <cmath>

namespace vkr::opt {

PolishSummary PolishMap(const std::vector<ParameterSpec>& parameters, Target& target, int evaluations,
                        SamplerSummary* summary, const SearchCallback& on_evaluation) {
  PolishSummary out;
  if (evaluations <= 0 || summary->map.empty() || !std::isfinite(summary->map_log_posterior)) return out;
  MapSearchOptions options;
  options.method = SearchMethod::Bobyqa;
  options.max_cost = evaluations;
  options.levels = 1;
  options.start = summary->map;
  // Convergence far below what the photographs resolve: the budget ends the polish.
  options.tolerance = 1e-9;
  for (size_t i = 0; i < parameters.size(); ++i) {
    const double width = parameters[i].Width();
    double sd = i < summary->parameters.size() ? summary->parameters[i].sd : NAN;
    if (!(std::isfinite(sd) && sd > 0) && i < summary->parameters.size()) sd = summary->parameters[i].laplace_sd;
    if (!(std::isfinite(sd) && sd > 0)) sd = 1e-3 * width;
    options.initial_steps.push_back(std::clamp(2.0 * sd, 1e-6 * width, 0.05 * width));
  }
  MapSearchSummary search;
  SearchMap(options, parameters, target, &search, on_evaluation);
  out.evaluations = search.evaluations;
  out.message = search.message;
  summary->evaluations += search.evaluations;
  if (search.ok && search.log_posterior > summary->map_log_posterior) {
    out.improved = true;
    out.improvement = search.log_posterior - summary->map_log_posterior;
    summary->map = search.map;
    summary->map_log_prior = search.log_prior;
    summary->map_log_likelihood = search.log_likelihood;
    summary->map_log_posterior = search.log_posterior;
    for (size_t i = 0; i < summary->parameters.size() && i < search.map.size(); ++i)
      summary->parameters[i].map = search.map[i];
  }
  return out;
}

}  // namespace vkr::opt
