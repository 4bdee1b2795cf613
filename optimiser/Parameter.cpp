#include "optimiser/Parameter.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include <nlohmann/json.hpp>

namespace vkr::opt {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool ParameterFail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

}  // namespace

const char* ToString(PriorKind kind) {
  switch (kind) {
    case PriorKind::Uniform: return "uniform";
    case PriorKind::Normal: return "normal";
  }
  return "?";
}

bool FromString(const std::string& text, PriorKind* kind) {
  if (text == "uniform") *kind = PriorKind::Uniform;
  else if (text == "normal") *kind = PriorKind::Normal;
  else return false;
  return true;
}

double ParameterSpec::LogPrior(double x) const {
  if (!Admissible(x)) return -kInfinity;
  if (prior == PriorKind::Uniform) return -std::log(b - a);
  const double z = (x - a) / b;
  return -0.5 * z * z - std::log(b * std::sqrt(2.0 * std::numbers::pi));
}

double ParameterSpec::Width() const { return prior == PriorKind::Uniform ? b - a : 4.0 * b; }

double ParameterSpec::Lower() const {
  double lo = prior == PriorKind::Uniform ? a : -kInfinity;
  if (bounds) lo = std::max(lo, bounds->first);
  return lo;
}

double ParameterSpec::Upper() const {
  double hi = prior == PriorKind::Uniform ? b : kInfinity;
  if (bounds) hi = std::min(hi, bounds->second);
  return hi;
}

bool ParameterSpec::Admissible(double x) const {
  return std::isfinite(x) && x >= Lower() && x <= Upper();
}

double ParameterSpec::Clamp(double x) const { return std::min(std::max(x, Lower()), Upper()); }

double ParameterSpec::Initial() const {
  if (init) return *init;
  return Clamp(prior == PriorKind::Uniform ? 0.5 * (a + b) : a);
}

bool ParameterSpec::IsValid(std::string* why) const {
  const std::string who = "parameter '" + name + "': ";
  if (name.empty()) return ParameterFail(why, "parameter: empty name");
  if (!std::isfinite(a) || !std::isfinite(b)) return ParameterFail(why, who + "prior values must be finite");
  if (prior == PriorKind::Uniform && !(a < b))
    return ParameterFail(why, who + "uniform prior needs lo < hi");
  if (prior == PriorKind::Normal && !(b > 0)) return ParameterFail(why, who + "normal prior needs sd > 0");
  if (bounds) {
    if (!std::isfinite(bounds->first) || !std::isfinite(bounds->second) ||
        !(bounds->first < bounds->second))
      return ParameterFail(why, who + "bounds must be finite with lo < hi");
    if (!(Lower() < Upper())) return ParameterFail(why, who + "bounds do not overlap the prior");
  }
  if (init && !Admissible(*init)) return ParameterFail(why, who + "init lies outside the prior or bounds");
  return true;
}

double LogPrior(const std::vector<ParameterSpec>& parameters, const std::vector<double>& x) {
  double sum = 0.0;
  for (size_t i = 0; i < parameters.size(); ++i) {
    const double l = parameters[i].LogPrior(x[i]);
    if (l == -kInfinity) return -kInfinity;
    sum += l;
  }
  return sum;
}

bool IsValid(const std::vector<ParameterSpec>& parameters, std::string* why) {
  if (parameters.empty()) return ParameterFail(why, "no parameters");
  std::set<std::string> names;
  for (const ParameterSpec& p : parameters) {
    if (!p.IsValid(why)) return false;
    if (!names.insert(p.name).second) return ParameterFail(why, "parameter '" + p.name + "' declared twice");
  }
  return true;
}

nlohmann::json ToJson(const ParameterSpec& p) {
  nlohmann::json j = {{"name", p.name}, {"prior", ToString(p.prior)}, {"a", p.a}, {"b", p.b}};
  if (p.bounds) j["bounds"] = {p.bounds->first, p.bounds->second};
  if (p.init) j["init"] = *p.init;
  return j;
}

bool FromJson(const nlohmann::json& j, ParameterSpec* p, std::string* why) {
  try {
    ParameterSpec out;
    out.name = j.at("name").get<std::string>();
    if (!FromString(j.at("prior").get<std::string>(), &out.prior))
      return ParameterFail(why, "parameter '" + out.name + "': unknown prior");
    out.a = j.at("a").get<double>();
    out.b = j.at("b").get<double>();
    if (j.contains("bounds")) out.bounds = std::make_pair(j["bounds"].at(0).get<double>(),
                                                          j["bounds"].at(1).get<double>());
    if (j.contains("init")) out.init = j["init"].get<double>();
    if (!out.IsValid(why)) return false;
    *p = out;
    return true;
  } catch (const nlohmann::json::exception& e) {
    return ParameterFail(why, std::string("parameter: ") + e.what());
  }
}

}  // namespace vkr::opt
