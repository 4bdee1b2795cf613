#include "optimiser/SamplerOptions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

namespace vkr::opt {
namespace {

bool OptionsFail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

// Calls f(name, field) for every field, so that ToJson and FromJson cannot drift apart.
template <class Options, class F>
void ForEachField(Options& o, F&& f) {
  f("iterations", o.iterations);
  f("until_converged", o.until_converged);
  f("time_limit", o.time_limit);
  f("batch", o.batch);
  f("target_rhat", o.target_rhat);
  f("target_ess", o.target_ess);
  f("max_iterations", o.max_iterations);
  f("convergence_interval", o.convergence_interval);
  f("chains", o.chains);
  f("temperatures", o.temperatures);
  f("temperature_ratio", o.temperature_ratio);
  f("swap_interval", o.swap_interval);
  f("initial_temperature", o.initial_temperature);
  f("anneal_fraction", o.anneal_fraction);
  f("anneal_schedule", o.anneal_schedule);
  f("burn_in_fraction", o.burn_in_fraction);
  f("cool_after_settling", o.cool_after_settling);
  f("posterior_chains", o.posterior_chains);
  f("independence_share", o.independence_share);
  f("proposal_scale", o.proposal_scale);
  f("init_jitter", o.init_jitter);
  f("adapt", o.adapt);
  f("adapt_min_samples", o.adapt_min_samples);
  f("adapt_epsilon", o.adapt_epsilon);
  f("coarse_levels", o.coarse_levels);
  f("coarse_fraction", o.coarse_fraction);
  f("settle", o.settle);
  f("settle_rounds", o.settle_rounds);
  f("settle_steps", o.settle_steps);
  f("settle_spread", o.settle_spread);
  f("refine_steps", o.refine_steps);
  f("refine_difference", o.refine_difference);
  f("refine_tolerance", o.refine_tolerance);
  f("polish_evaluations", o.polish_evaluations);
  f("finer_atlas_polish", o.finer_atlas_polish);
  f("start_search", o.start_search);
  f("evidence_rungs", o.evidence_rungs);
  f("evidence_alpha", o.evidence_alpha);
  f("evidence_every", o.evidence_every);
  f("seed", o.seed);
}

}  // namespace

const char* ToString(AnnealSchedule schedule) {
  switch (schedule) {
    case AnnealSchedule::Geometric: return "geometric";
    case AnnealSchedule::Linear: return "linear";
  }
  return "?";
}

bool FromString(const std::string& text, AnnealSchedule* schedule) {
  if (text == "geometric") *schedule = AnnealSchedule::Geometric;
  else if (text == "linear") *schedule = AnnealSchedule::Linear;
  else return false;
  return true;
}

int SamplerOptions::BurnIn() const { return int(std::floor(burn_in_fraction * iterations)); }
int SamplerOptions::AnnealIterations() const {
  return initial_temperature == 1.0 ? 0 : int(std::floor(anneal_fraction * iterations));
}
int SamplerOptions::CoarseIterations() const {
  return coarse_levels <= 1 ? 0 : int(std::floor(coarse_fraction * iterations));
}

bool SamplerOptions::IsValid(std::string* why) const {
  const auto fraction = [](double f) { return std::isfinite(f) && f >= 0.0 && f < 1.0; };
  if (iterations < 1) return OptionsFail(why, "iterations must be ≥ 1");
  if (batch < 1 || batch > kMaxSamplerBatch)
    return OptionsFail(why, "batch must lie in [1, " + std::to_string(kMaxSamplerBatch) + "]");
  if (!(time_limit < 1e9)) return OptionsFail(why, "time_limit must be below 1e9 s");
  if (chains < 1) return OptionsFail(why, "chains must be ≥ 1");
  if (!(std::isfinite(target_rhat) && target_rhat > 1.0)) return OptionsFail(why, "target_rhat must be > 1");
  if (!(std::isfinite(target_ess) && target_ess > 0.0)) return OptionsFail(why, "target_ess must be > 0");
  if (max_iterations < iterations) return OptionsFail(why, "max_iterations must be ≥ iterations");
  if (convergence_interval < 1) return OptionsFail(why, "convergence_interval must be ≥ 1");
  if (temperatures < 1) return OptionsFail(why, "temperatures must be ≥ 1");
  if (temperatures > 1 && !(std::isfinite(temperature_ratio) && temperature_ratio > 1.0))
    return OptionsFail(why, "temperature_ratio must be > 1 when temperatures > 1");
  if (swap_interval < 1) return OptionsFail(why, "swap_interval must be ≥ 1");
  if (!(std::isfinite(initial_temperature) && initial_temperature >= 1.0))
    return OptionsFail(why, "initial_temperature must be ≥ 1");
  if (!fraction(anneal_fraction)) return OptionsFail(why, "anneal_fraction must lie in [0, 1)");
  if (!fraction(burn_in_fraction)) return OptionsFail(why, "burn_in_fraction must lie in [0, 1)");
  if (!fraction(coarse_fraction)) return OptionsFail(why, "coarse_fraction must lie in [0, 1)");
  if (AnnealIterations() > BurnIn())
    return OptionsFail(why, "anneal_fraction must not exceed burn_in_fraction: annealed states are "
                     "not posterior samples");
  if (CoarseIterations() > BurnIn())
    return OptionsFail(why, "coarse_fraction must not exceed burn_in_fraction: coarse-level states "
                     "are not posterior samples");
  if (posterior_chains < 0) return OptionsFail(why, "posterior_chains must be ≥ 0 (0: all)");
  if (!(std::isfinite(independence_share) && independence_share >= 0.0 && independence_share <= 1.0))
    return OptionsFail(why, "independence_share must lie in [0, 1]");
  if (!(std::isfinite(proposal_scale) && proposal_scale > 0.0))
    return OptionsFail(why, "proposal_scale must be > 0");
  if (!(std::isfinite(init_jitter) && init_jitter >= 0.0)) return OptionsFail(why, "init_jitter must be ≥ 0");
  if (adapt_min_samples < 2) return OptionsFail(why, "adapt_min_samples must be ≥ 2");
  if (!(std::isfinite(adapt_epsilon) && adapt_epsilon > 0.0))
    return OptionsFail(why, "adapt_epsilon must be > 0");
  if (coarse_levels < 1) return OptionsFail(why, "coarse_levels must be ≥ 1");
  if (refine_steps < 0) return OptionsFail(why, "refine_steps must be ≥ 0");
  if (polish_evaluations < 0) return OptionsFail(why, "polish_evaluations must be ≥ 0");
  if (finer_atlas_polish < 0) return OptionsFail(why, "finer_atlas_polish must be ≥ 0");
  if (!(start_search >= 0.0 && std::isfinite(start_search))) return OptionsFail(why, "start_search must be ≥ 0");
  if (settle_rounds < 1) return OptionsFail(why, "settle_rounds must be ≥ 1");
  if (settle_steps < 0) return OptionsFail(why, "settle_steps must be ≥ 0");
  if (!(std::isfinite(settle_spread) && settle_spread > 0.0))
    return OptionsFail(why, "settle_spread must be > 0");
  if (!(std::isfinite(refine_difference) && refine_difference > 0.0 && refine_difference < 0.5))
    return OptionsFail(why, "refine_difference must lie in (0, 0.5)");
  if (!(std::isfinite(refine_tolerance) && refine_tolerance > 0.0))
    return OptionsFail(why, "refine_tolerance must be > 0");
  if (evidence_rungs < 0 || evidence_rungs == 1 || evidence_rungs > 1000)
    return OptionsFail(why, "evidence_rungs must be 0 (off) or from 2 to 1000");
  if (!(std::isfinite(evidence_alpha) && evidence_alpha > 0.0 && evidence_alpha <= 1.0))
    return OptionsFail(why, "evidence_alpha must lie in (0, 1]");
  if (evidence_every < 1 || evidence_every > 1000)
    return OptionsFail(why, "evidence_every must be from 1 to 1000");
  return true;
}

nlohmann::json ToJson(const SamplerOptions& options) {
  nlohmann::json j = nlohmann::json::object();
  ForEachField(options, [&](const char* name, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_enum_v<T>) j[name] = ToString(field);
    else j[name] = field;
  });
  if (options.time_limit < 0.0) j["time_limit"] = "auto";
  else if (options.time_limit == 0.0) j["time_limit"] = "none";
  return j;
}

namespace {

// 2.0, which a JSON writer may give for 2 (but not 2.5, nor one beyond 2⁵³ where doubles skip).
bool IntegralFloat(const nlohmann::json& j) {
  if (!j.is_number_float()) return false;
  const double v = j.get<double>();
  return std::isfinite(v) && std::floor(v) == v && std::abs(v) < 9007199254740992.0;
}

// The words FromJson reads before the numbers: "iterations": "auto" and the time limit's
// "auto" and "none". Returns the object without them; `error` set when a word is unknown.
nlohmann::json ReadWords(const nlohmann::json& json, SamplerOptions* out, std::string* error) {
  nlohmann::json rest = json;
  if (const auto it = json.find("iterations"); it != json.end() && it->is_string()) {
    if (*it != "auto") *error = "sampler.iterations: expected an integer or \"auto\", got " + it->dump();
    out->until_converged = true;
    rest.erase("iterations");
  } else if (it != json.end() && !json.contains("until_converged")) {
    out->until_converged = false;  // a number of iterations is exactly that many
  }
  if (const auto it = json.find("time_limit"); it != json.end()) {
    if (it->is_string() && (*it == "auto" || *it == "none")) {
      out->time_limit = *it == "auto" ? -1.0 : 0.0;
      rest.erase("time_limit");
    } else if (!it->is_number() || !(it->get<double>() > 0.0)) {
      *error = "sampler.time_limit: time limit " + it->dump() + " s must be > 0 (or \"none\", \"auto\")";
    }
  }
  return rest;
}

}  // namespace

bool FromJson(const nlohmann::json& json, SamplerOptions* options, std::string* why) {
  if (!json.is_object()) return OptionsFail(why, "sampler options must be a JSON object");
  SamplerOptions out = *options;
  std::string word_error;
  const nlohmann::json numbers = ReadWords(json, &out, &word_error);
  if (!word_error.empty()) return OptionsFail(why, word_error);
  std::set<std::string> known;
  std::string error;
  ForEachField(out, [&](const char* name, auto& field) {
    known.insert(name);
    const auto it = numbers.find(name);
    if (it == numbers.end() || !error.empty()) return;
    using T = std::decay_t<decltype(field)>;
    const std::string key = std::string("sampler.") + name;
    if constexpr (std::is_enum_v<T>) {
      if (!it->is_string() || !FromString(it->template get<std::string>(), &field))
        error = key + ": unknown value " + it->dump();
    } else if constexpr (std::is_same_v<T, bool>) {
      if (!it->is_boolean()) error = key + ": expected true or false";
      else field = it->template get<bool>();
    } else if constexpr (std::is_unsigned_v<T>) {
      // nlohmann reads every non-negative integer as unsigned; 2.0 counts as 2, as everywhere
      // in a scene file.
      if (IntegralFloat(*it) && it->template get<double>() >= 0.0) field = T(it->template get<double>());
      else if (!it->is_number_unsigned()) error = key + ": expected an integer ≥ 0";
      else field = it->template get<T>();
    } else if constexpr (std::is_integral_v<T>) {
      if (IntegralFloat(*it) && std::abs(it->template get<double>()) <= double(std::numeric_limits<T>::max())) {
        field = T(it->template get<double>());
        return;
      }
      const bool fits = it->is_number_unsigned()
                            ? it->template get<uint64_t>() <= uint64_t(std::numeric_limits<T>::max())
                            : it->is_number_integer() &&
                                  it->template get<int64_t>() >= std::numeric_limits<T>::min() &&
                                  it->template get<int64_t>() <= std::numeric_limits<T>::max();
      if (!fits) error = key + ": expected an integer";
      else field = it->template get<T>();
    } else {
      if (!it->is_number()) error = key + ": expected a number";
      else field = it->template get<T>();
    }
  });
  if (!error.empty()) return OptionsFail(why, error);
  for (const auto& [key, value] : json.items())
    if (!known.count(key)) return OptionsFail(why, "sampler." + key + ": unknown option");
  // As many replicas per chain as the batch holds, unless the object says how many; a long
  // fixed run may exceed the default cap on convergence-driven ones.
  if ((json.contains("batch") || json.contains("chains")) && !json.contains("temperatures"))
    out.temperatures = std::max(1, out.batch / std::max(1, out.chains));
  if (json.contains("iterations") && !json.contains("max_iterations"))
    out.max_iterations = std::max(out.max_iterations, out.iterations);
  if (!out.IsValid(why)) return false;
  *options = out;
  return true;
}

}  // namespace vkr::opt
