// The MAP search with NLopt (MapSearch.h): one NLopt run per level, coarsest first, each
// started at the best point of the level before, within the level's share of the budget.

#include "optimiser/MapSearch.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>

#include <nlopt.hpp>

namespace vkr::opt {
namespace {

constexpr double kSearchInf = std::numeric_limits<double>::infinity();
// What NLopt sees for a hypothesis the target cannot score, before any could be: finite
// (NLopt's methods compare and model values; −∞ or NaN corrupt BOBYQA's quadratic model and
// the simplex's ordering), and below anything a likelihood of photographs reaches.
constexpr double kUnscorable = -1e30;

constexpr SearchMethod kMethods[] = {SearchMethod::Bobyqa, SearchMethod::NelderMead, SearchMethod::Sbplx,
                                     SearchMethod::Crs2Lm, SearchMethod::Isres};

nlopt::algorithm Algorithm(SearchMethod method) {
  switch (method) {
    case SearchMethod::Bobyqa: return nlopt::LN_BOBYQA;
    case SearchMethod::NelderMead: return nlopt::LN_NELDERMEAD;
    case SearchMethod::Sbplx: return nlopt::LN_SBPLX;
    case SearchMethod::Crs2Lm: return nlopt::GN_CRS2_LM;
    case SearchMethod::Isres: return nlopt::GN_ISRES;
  }
  return nlopt::LN_BOBYQA;
}

bool SearchFail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

const char* ResultName(nlopt::result result) {
  switch (result) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "stopval reached";
    case nlopt::FTOL_REACHED: return "ftol reached";
    case nlopt::XTOL_REACHED: return "converged (xtol)";
    case nlopt::MAXEVAL_REACHED: return "budget spent";
    case nlopt::MAXTIME_REACHED: return "time limit";
    case nlopt::FORCED_STOP: return "budget spent";
    case nlopt::ROUNDOFF_LIMITED: return "roundoff limited";
    default: return "failed";
  }
}

// One search: the target, the bookkeeping of evaluations, cost and the best point per level.
class Search {
 public:
  Search(const MapSearchOptions& options, const std::vector<ParameterSpec>& parameters, Target& target,
         MapSearchSummary* summary, const SearchCallback& on_evaluation)
      : o_(options), parameters_(parameters), target_(target), s_(*summary), on_evaluation_(on_evaluation) {}

  // NLopt's objective: log prior + log likelihood of one hypothesis at the current level.
  double Objective(const std::vector<double>& x) {
    const double cost = std::pow(o_.level_cost, -level_);
    // A rounding margin: the shares are sums of powers of level_cost^-1.
    if (s_.cost + cost > o_.max_cost * (1.0 + 1e-12)) throw nlopt::forced_stop();
    const double log_prior = LogPrior(parameters_, x);
    double log_likelihood = -kSearchInf;
    if (std::isfinite(log_prior)) log_likelihood = target_.Evaluate({x}).at(0);
    double value = log_prior + log_likelihood;
    if (!std::isfinite(value)) value = -kSearchInf;
    ++s_.evaluations;
    ++s_.level_evaluations.back();
    s_.cost += cost;
    if (value > best_value_) {
      best_value_ = value;
      best_ = x;
      best_prior_ = log_prior;
      best_likelihood_ = log_likelihood;
    }
    if (on_evaluation_) on_evaluation_({level_, &x, value, s_.evaluations, s_.cost});
    if (std::isfinite(value)) {
      worst_ = std::min(worst_, value);
      return value;
    }
    // A plateau at the worst value seen: the methods step away from it without a cliff.
    return std::isfinite(worst_) ? worst_ : kUnscorable;
  }

  // Searches one level from `start` within `allowance` full-resolution equivalents; the best
  // point of this level (the start itself if nothing better was scored) is returned.
  std::vector<double> Level(int level, std::vector<double> start, double allowance, double step_fraction,
                            double tolerance, const std::string& name) {
    level_ = level;
    target_.SetLevel(level);
    best_value_ = -kSearchInf;
    best_ = start;
    s_.levels.push_back(level);
    s_.level_evaluations.push_back(0);
    const int d = int(parameters_.size());
    const int64_t evaluations = int64_t(std::floor(allowance * std::pow(o_.level_cost, level) + 1e-9));
    if (evaluations < 1) return start;

    nlopt::opt opt(Algorithm(o_.method), unsigned(d));
    std::vector<double> lower(d), upper(d), steps(d), xtol(d);
    for (int i = 0; i < d; ++i) {
      const ParameterSpec& p = parameters_[size_t(i)];
      lower[i] = SearchLower(p, o_.normal_span);
      upper[i] = SearchUpper(p, o_.normal_span);
      start[size_t(i)] = std::clamp(start[size_t(i)], lower[i], upper[i]);
      steps[i] = o_.initial_steps.empty() ? step_fraction * p.Width() : o_.initial_steps[size_t(i)];
      // Never a step past the box on both sides (BOBYQA needs 2 · step ≤ upper − lower).
      steps[i] = std::min(steps[i], 0.45 * (upper[i] - lower[i]));
      xtol[i] = tolerance * p.Width();
    }
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_max_objective(
        [](unsigned, const double* x, double*, void* data) {
          Search& self = *static_cast<Search*>(data);
          try {
            return self.Objective(std::vector<double>(x, x + self.parameters_.size()));
          } catch (const nlopt::forced_stop&) {
            throw;
          } catch (...) {
            // NLopt's wrapper would turn the target's error into a bare "nlopt failure":
            // keep it, stop NLopt, and throw it again below.
            self.error_ = std::current_exception();
            throw nlopt::forced_stop();
          }
        },
        this);
    opt.set_maxeval(int(std::min<int64_t>(evaluations, std::numeric_limits<int>::max())));
    opt.set_xtol_abs(xtol);
    opt.set_initial_step(steps);
    nlopt::srand(o_.seed + uint64_t(level));  // the global methods draw; the same seed, the same search
    nlopt::result result = nlopt::FAILURE;
    double value = 0.0;
    try {
      result = opt.optimize(start, value);
    } catch (const nlopt::forced_stop&) {
      result = nlopt::FORCED_STOP;
    } catch (const nlopt::roundoff_limited&) {
      result = nlopt::ROUNDOFF_LIMITED;  // as good as it gets at this level's precision
    }
    if (error_) std::rethrow_exception(error_);
    // (Other NLopt errors, invalid arguments, are programmer errors: they propagate.)
    if (!s_.message.empty()) s_.message += "; ";
    s_.message += name + ": " + ResultName(result);
    // A restart that found nothing higher keeps the MAP it started from.
    if (level == 0 && std::isfinite(best_value_) && (s_.map.empty() || best_value_ > s_.log_posterior)) {
      s_.map = best_;
      s_.log_prior = best_prior_;
      s_.log_likelihood = best_likelihood_;
      s_.log_posterior = best_value_;
    }
    return best_;
  }

 private:
  const MapSearchOptions& o_;
  const std::vector<ParameterSpec>& parameters_;
  Target& target_;
  MapSearchSummary& s_;
  const SearchCallback& on_evaluation_;
  int level_ = 0;
  std::exception_ptr error_;  // the target's, thrown through NLopt
  double worst_ = kSearchInf;
  std::vector<double> best_;
  double best_value_ = -kSearchInf, best_prior_ = -kSearchInf, best_likelihood_ = -kSearchInf;
};

}  // namespace

const char* ToString(SearchMethod method) {
  switch (method) {
    case SearchMethod::Bobyqa: return "bobyqa";
    case SearchMethod::NelderMead: return "neldermead";
    case SearchMethod::Sbplx: return "sbplx";
    case SearchMethod::Crs2Lm: return "crs2lm";
    case SearchMethod::Isres: return "isres";
  }
  return "?";
}

bool FromString(const std::string& text, SearchMethod* method) {
  for (SearchMethod m : kMethods)
    if (text == ToString(m)) {
      *method = m;
      return true;
    }
  return false;
}

std::string SearchMethodNames() {
  std::string names;
  for (SearchMethod m : kMethods) names += (names.empty() ? "" : ", ") + std::string(ToString(m));
  return names;
}

double SearchLower(const ParameterSpec& p, double normal_span) {
  return std::isfinite(p.Lower()) ? p.Lower() : p.a - normal_span * p.b;
}

double SearchUpper(const ParameterSpec& p, double normal_span) {
  return std::isfinite(p.Upper()) ? p.Upper() : p.a + normal_span * p.b;
}

bool MapSearchOptions::IsValid(std::string* why) const {
  if (!(std::isfinite(max_cost) && max_cost > 0)) return SearchFail(why, "max_cost must be a positive number");
  if (!(std::isfinite(level_cost) && level_cost >= 1)) return SearchFail(why, "level_cost must be ≥ 1");
  if (levels < 1) return SearchFail(why, "levels must be ≥ 1");
  if (!(coarse_share >= 0 && coarse_share < 1)) return SearchFail(why, "coarse_share must lie in [0, 1)");
  if (!(initial_step > 0 && initial_step <= 1)) return SearchFail(why, "initial_step must lie in (0, 1]");
  if (!(step_shrink > 0 && step_shrink <= 1)) return SearchFail(why, "step_shrink must lie in (0, 1]");
  for (double s : initial_steps)
    if (!(std::isfinite(s) && s > 0)) return SearchFail(why, "initial_steps must be positive numbers");
  if (!(tolerance >= 0 && coarse_tolerance >= 0)) return SearchFail(why, "tolerances must be ≥ 0");
  if (!(normal_span > 0)) return SearchFail(why, "normal_span must be positive");
  if (restarts < 0) return SearchFail(why, "restarts must be ≥ 0");
  if (!(restart_step > 0 && restart_step <= 1)) return SearchFail(why, "restart_step must lie in (0, 1]");
  if (!(restart_tolerance >= 0)) return SearchFail(why, "restart_tolerance must be ≥ 0");
  return true;
}

std::string MapSearchSummary::BriefReport() const {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out << ToString(method) << ": " << (ok ? "" : "FAILED ") << "log posterior " << log_posterior << " after "
      << evaluations << " evaluations (" << cost << " full-resolution equivalents); " << message;
  return out.str();
}

bool SearchMap(const MapSearchOptions& options, const std::vector<ParameterSpec>& parameters, Target& target,
               MapSearchSummary* summary, const SearchCallback& on_evaluation) {
  *summary = MapSearchSummary{};
  summary->method = options.method;
  std::string why;
  if (!options.IsValid(&why) || !IsValid(parameters, &why)) return SearchFail(&summary->message, why);
  if (target.levels() < 1 || target.max_batch() < 1) return SearchFail(&summary->message, "the target has no level or batch");
  const size_t d = parameters.size();
  if (!options.initial_steps.empty() && options.initial_steps.size() != d)
    return SearchFail(&summary->message, "initial_steps must have one entry per parameter");
  std::vector<double> point = options.start;
  if (point.empty())
    for (const ParameterSpec& p : parameters) point.push_back(p.Initial());
  if (point.size() != d || !std::isfinite(LogPrior(parameters, point)))
    return SearchFail(&summary->message, "the start must have one admissible value per parameter");

  Search search(options, parameters, target, summary, on_evaluation);
  const int levels = std::min(options.levels, target.levels());
  double step = options.initial_step;
  for (int level = levels - 1; level >= 0; --level) {
    // A coarse level may spend its share plus what the levels before it left; level 0 the rest.
    const double spent_before = summary->cost;
    const int coarse_done = levels - 1 - level;
    const double allowance = level > 0 ? options.coarse_share * options.max_cost * (coarse_done + 1) - spent_before
                                       : options.max_cost - spent_before;
    point = search.Level(level, point, allowance, step, level > 0 ? options.coarse_tolerance : options.tolerance,
                         "level " + std::to_string(level));
    step *= options.step_shrink;
  }
  const bool local = options.method == SearchMethod::Bobyqa || options.method == SearchMethod::NelderMead ||
                     options.method == SearchMethod::Sbplx;
  while (local && summary->restarts < options.restarts && !summary->map.empty() &&
         summary->cost + 1.0 <= options.max_cost * (1.0 + 1e-12)) {
    const std::vector<double> from = summary->map;
    ++summary->restarts;
    search.Level(0, from, options.max_cost - summary->cost, options.restart_step, options.tolerance,
                 "restart " + std::to_string(summary->restarts));
    double moved = 0.0;
    for (size_t i = 0; i < d; ++i) moved = std::max(moved, std::abs(summary->map[i] - from[i]) / parameters[i].Width());
    if (!(moved > options.restart_tolerance)) break;
  }
  target.SetLevel(0);
  summary->ok = !summary->map.empty();
  if (!summary->ok) summary->message += "; no hypothesis with a finite log posterior at level 0";
  return summary->ok;
}

}  // namespace vkr::opt
