// The table of `vkrecon compare` (SceneComparison.h): reading each run's evidence, the Bayes
// factors and model probabilities with their errors, the checks that the rows compare, and
// the table's two forms.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>

#include "engine/common/InputError.h"
#include "recon/SceneComparison.h"

namespace fs = std::filesystem;

namespace vkr::recon {
namespace {

double NumberAt(const nlohmann::json& j, const char* key, const std::string& file, const std::string& field) {
  const auto it = j.find(key);
  if (it == j.end() || !it->is_number())
    throw InputError(file, field + key, "missing or not a number: the run's evidence cannot be read");
  return it->get<double>();
}

// The lowest swap rate between neighbouring rungs (rungs[k].swap_acceptance, with the rung above).
double MinSwap(const nlohmann::json& rungs) {
  double lowest = 1.0;
  for (const nlohmann::json& rung : rungs)
    if (rung.contains("swap_acceptance") && rung["swap_acceptance"].is_number())
      lowest = std::min(lowest, rung["swap_acceptance"].get<double>());
  return lowest;
}

std::string Fixed(double x, int digits) {
  if (!std::isfinite(x)) return "n/a";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, x);
  return text;
}

// A probability: in percent with as many digits as tell it from 0.
std::string Percent(double p) {
  if (!std::isfinite(p)) return "n/a";
  char text[64];
  if (p >= 0.001 || p == 0.0) std::snprintf(text, sizeof text, "%.1f %%", 100.0 * p);
  else std::snprintf(text, sizeof text, "%.1e %%", 100.0 * p);
  return text;
}

// Each row's verdict with every error multiplied by `error_factor`: the runner-up's margin
// decides how sure the best's verdict is.
std::vector<std::string> Verdicts(const std::vector<ComparedScene>& rows, ptrdiff_t best,
                                  const ComparisonBars& bars, double error_factor) {
  double runner_up = -INFINITY, runner_up_se = 0.0;
  for (ptrdiff_t i = 0; i < ptrdiff_t(rows.size()); ++i)
    if (i != best && rows[size_t(i)].log_z > runner_up) {
      runner_up = rows[size_t(i)].log_z;
      runner_up_se = error_factor * rows[size_t(i)].se_log_bayes_factor;
    }
  std::vector<std::string> out;
  for (ptrdiff_t i = 0; i < ptrdiff_t(rows.size()); ++i) {
    const ComparedScene& r = rows[size_t(i)];
    const double lnb = r.log_bayes_factor;
    if (i == best) {
      const double margin = r.log_z - runner_up;
      if (rows.size() == 1) out.push_back("only scene");
      else if (margin >= bars.decisive_log_bayes_factor && margin >= 3.0 * runner_up_se) out.push_back("best, decisive");
      else if (margin >= 1.0) out.push_back("best, not decisive");
      else out.push_back("best, barely");
    } else if (-lnb >= bars.decisive_log_bayes_factor && -lnb >= 3.0 * error_factor * r.se_log_bayes_factor) {
      out.push_back("rejected");
    } else {
      out.push_back(-lnb >= 1.0 ? "disfavoured" : "as good");
    }
  }
  return out;
}

}  // namespace

ComparedScene ReadComparedRun(const fs::path& run_folder, const std::string& name) {
  const fs::path file = run_folder / "map.json";
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "no map.json: not a finished run's folder");
  nlohmann::json map;
  try {
    map = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(file.string(), "", std::string("not JSON: ") + e.what());
  }
  const auto evidence = map.find("evidence");
  if (evidence == map.end() || !evidence->is_object())
    throw InputError(file.string(), "evidence",
                     "missing: the run had no evidence ladder (run it again with --set sampler.evidence_rungs=12)");
  ComparedScene row;
  row.name = name;
  row.run = run_folder;
  const std::string f = file.string();
  row.log_z = NumberAt(*evidence, "log_z_ss", f, "evidence.");
  row.se = NumberAt(*evidence, "se_ss", f, "evidence.");
  row.log_z_ti = NumberAt(*evidence, "log_z_ti", f, "evidence.");
  row.se_ti = NumberAt(*evidence, "se_ti", f, "evidence.");
  row.agree = evidence->value("agree", false);
  row.ess = evidence->value("ess", 0.0);
  row.min_swap = MinSwap(evidence->value("rungs", nlohmann::json::array()));
  row.likelihood = evidence->value("likelihood", nlohmann::json());
  if (map.contains("log_likelihood") && map["log_likelihood"].is_number())
    row.map_log_likelihood = map["log_likelihood"].get<double>();
  if (map.contains("diagnosis") && map["diagnosis"].is_object())
    row.chi2_per_dof = map["diagnosis"].value("chi2_per_dof", 0.0);
  return row;
}

void TabulateComparison(std::vector<ComparedScene>* rows, const ComparisonBars& bars) {
  if (rows->empty()) return;
  const auto best = std::max_element(rows->begin(), rows->end(),
                                     [](const ComparedScene& a, const ComparedScene& b) { return a.log_z < b.log_z; });
  const double best_log_z = best->log_z, best_se = best->se;
  // p_i = exp(log Z_i − log Z_best) / Σ_j exp(log Z_j − log Z_best): no overflow.
  double total = 0.0;
  for (const ComparedScene& r : *rows) total += std::exp(r.log_z - best_log_z);
  for (ComparedScene& r : *rows) r.probability = std::exp(r.log_z - best_log_z) / total;
  // Independent runs: ∂p_i/∂log Z_j = p_i (δ_ij − p_j), so Var p_i = Σ_j p_i² (δ_ij − p_j)² se_j².
  for (ComparedScene& r : *rows) {
    double variance = 0.0;
    for (const ComparedScene& other : *rows) {
      const double slope = r.probability * ((&other == &r ? 1.0 : 0.0) - other.probability);
      variance += slope * slope * other.se * other.se;
    }
    r.se_probability = std::sqrt(variance);
  }
  for (ComparedScene& r : *rows) {
    r.log_bayes_factor = r.log_z - best_log_z;
    r.se_log_bayes_factor = &r == &*best ? 0.0 : std::hypot(r.se, best_se);
    r.doubts.clear();
    if (!r.agree) r.doubts.push_back("the two estimators disagree");
    if (r.ess < bars.min_ess) r.doubts.push_back("ESS " + Fixed(r.ess, 0) + " < " + Fixed(bars.min_ess, 0));
    if (r.min_swap < bars.min_swap)
      r.doubts.push_back("a rung pair swaps " + Fixed(r.min_swap, 2) + " < " + Fixed(bars.min_swap, 2));
  }
  const std::vector<std::string> verdicts = Verdicts(*rows, &*best - rows->data(), bars, 1.0);
  const std::vector<std::string> wider = Verdicts(*rows, &*best - rows->data(), bars, bars.doubt_error_factor);
  for (size_t i = 0; i < rows->size(); ++i) {
    (*rows)[i].verdict = verdicts[i];
    (*rows)[i].robust = verdicts[i] == wider[i];
  }
}

void CheckOneLikelihood(const std::vector<ComparedScene>& rows) {
  if (rows.empty()) return;
  const nlohmann::json& first = rows.front().likelihood;
  for (const ComparedScene& r : rows) {
    const std::string file = (r.run / "map.json").string();
    if (!r.likelihood.is_object())
      throw InputError(file, "evidence.likelihood",
                       "missing: the run does not say which likelihood its evidence is of (a run before compare existed)");
    for (const char* key : {"sigma", "position_sd", "kappa"}) {
      const double a = first.value(key, NAN), b = r.likelihood.value(key, NAN);
      if (!(std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b))))
        throw InputError(file, std::string("evidence.likelihood.") + key,
                         Fixed(b, 6) + " against " + Fixed(a, 6) + " in " + rows.front().name +
                             ": the evidences are of different likelihoods and do not compare");
    }
    // A run from before the edge term had none.
    const nlohmann::json unstated[] = {nullptr, nullptr, nullptr, false};
    const char* const words[] = {"kind", "photometric", "clutter", "edges"};
    for (size_t k = 0; k < std::size(words); ++k) {
      const char* key = words[k];
      if (first.value(key, unstated[k]) != r.likelihood.value(key, unstated[k]))
        throw InputError(file, std::string("evidence.likelihood.") + key,
                         r.likelihood.value(key, unstated[k]).dump() + " against " +
                             first.value(key, unstated[k]).dump() + " in " + rows.front().name +
                             ": the evidences are of different likelihoods and do not compare");
    }
  }
}

void CheckSamePhotographs(const Scene& first, const Scene& second) {
  const std::string file = second.file.string();
  const std::string other = " than " + first.file.string() + ": the scenes do not explain the same photographs";
  if (first.cameras.size() != second.cameras.size())
    throw InputError(file, "cameras", std::to_string(second.cameras.size()) + " cameras, other" + other);
  const auto close = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(a)); };
  for (size_t i = 0; i < first.cameras.size(); ++i) {
    const CameraModel &a = first.cameras[i], &b = second.cameras[i];
    const std::string field = "cameras[" + std::to_string(i) + "]";
    std::error_code error;
    if (a.name != b.name) throw InputError(file, field + ".name", "'" + b.name + "', another camera" + other);
    if (!fs::equivalent(a.image, b.image, error))
      throw InputError(file, field + ".image", b.image.string() + ", another photograph" + other);
    bool same = a.width == b.width && a.height == b.height;
    // An intrinsic the scene estimates (an expression) must be the same expression's slot.
    for (int k = 0; k < 9; ++k)
      same = same && a.K[k].expression == b.K[k].expression && close(a.K[k].constant, b.K[k].constant);
    for (int k = 0; k < 3; ++k) {
      same = same && close(a.t[k], b.t[k]);
      for (int m = 0; m < 3; ++m) same = same && close(a.R(k, m), b.R(k, m));
    }
    if (!same) throw InputError(file, field, "another size, intrinsics or pose" + other);
  }
}

nlohmann::json ToJson(const std::vector<ComparedScene>& rows) {
  nlohmann::json scenes = nlohmann::json::array();
  const auto finite = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  for (const ComparedScene& r : rows)
    scenes.push_back({{"scene", r.name}, {"run", r.run.string()},
                      {"log_z", finite(r.log_z)}, {"se", finite(r.se)},
                      {"log_z_ti", finite(r.log_z_ti)}, {"se_ti", finite(r.se_ti)}, {"agree", r.agree},
                      {"ess", finite(r.ess)}, {"min_swap_acceptance", finite(r.min_swap)},
                      {"log_bayes_factor", finite(r.log_bayes_factor)},
                      {"se_log_bayes_factor", finite(r.se_log_bayes_factor)},
                      {"probability", finite(r.probability)}, {"se_probability", finite(r.se_probability)},
                      {"map_log_likelihood", finite(r.map_log_likelihood)}, {"chi2_per_dof", finite(r.chi2_per_dof)},
                      {"verdict", r.verdict}, {"doubts", r.doubts}, {"verdict_holds_at_wider_errors", r.robust}});
  return {{"scenes", scenes},
          {"likelihood", rows.empty() ? nlohmann::json() : rows.front().likelihood},
          {"prior_odds", "equal"}};
}

std::string MarkdownTable(const std::vector<ComparedScene>& rows) {
  std::ostringstream o;
  o << "| scene | log Z (SS) | log Z (TI) | ln B vs best | P (equal prior odds) | MAP log L | chi2/dof | verdict |\n"
    << "|---|---|---|---|---|---|---|---|\n";
  for (const ComparedScene& r : rows) {
    std::string verdict = r.verdict;
    if (!r.robust)
      for (const std::string& doubt : r.doubts) verdict += "; doubt: " + doubt;
    o << "| " << r.name << " | " << Fixed(r.log_z, 2) << " ± " << Fixed(r.se, 2) << " | " << Fixed(r.log_z_ti, 2)
      << " ± " << Fixed(r.se_ti, 2) << " | " << Fixed(r.log_bayes_factor, 2) << " ± "
      << Fixed(r.se_log_bayes_factor, 2) << " | " << Percent(r.probability) << " ± " << Percent(r.se_probability)
      << " | " << Fixed(r.map_log_likelihood, 1) << " | " << Fixed(r.chi2_per_dof, 3) << " | " << verdict << " |\n";
  }
  return o.str();
}

}  // namespace vkr::recon
