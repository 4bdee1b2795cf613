#pragma once
// What the sampler knows of one component of a hypothesis Ψ: its name, its prior and its
// hard limits. The scene's parameters (engine/scene/Scene.h) map onto this one to one;
// optimiser/ keeps its own description so that it needs nothing from the scene model.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace vkr::opt {

enum class PriorKind {
  Uniform,  // a = lo, b = hi
  Normal,   // a = mean, b = sd
};
const char* ToString(PriorKind kind);
bool FromString(const std::string& text, PriorKind* kind);

struct ParameterSpec {
  std::string name;
  PriorKind prior = PriorKind::Uniform;
  double a = 0.0, b = 1.0;  // see PriorKind
  // Hard limits on top of the prior; a normal prior without bounds is unbounded.
  std::optional<std::pair<double, double>> bounds;
  // Starting value; without it the prior's centre clamped into the support.
  std::optional<double> init;

  // Log prior density (normalised, like Prior::LogDensity of the scene model), −∞ outside
  // the support. Bounds truncate a normal prior without renormalising: a constant.
  double LogPrior(double x) const;
  // Scale of the prior: hi − lo, or 4 sd. Proposal widths and finite-difference steps are
  // fractions of it.
  double Width() const;
  // The support: the uniform's interval or ℝ, intersected with the bounds (±∞ if open).
  double Lower() const;
  double Upper() const;
  bool Admissible(double x) const;  // finite and inside [Lower(), Upper()]
  double Clamp(double x) const;     // into [Lower(), Upper()]
  double Initial() const;
  // Finite numbers, lo < hi, sd > 0, bounds that overlap the prior, init admissible.
  bool IsValid(std::string* why) const;
};

// Σ_i LogPrior(x_i); −∞ when any component lies outside its support.
double LogPrior(const std::vector<ParameterSpec>& parameters, const std::vector<double>& x);
// A non-empty list of valid parameters with distinct names.
bool IsValid(const std::vector<ParameterSpec>& parameters, std::string* why);

// {"name", "prior": "uniform"|"normal", "a", "b", "bounds"?: [lo, hi], "init"?}
nlohmann::json ToJson(const ParameterSpec& parameter);
bool FromJson(const nlohmann::json& json, ParameterSpec* parameter, std::string* why);

}  // namespace vkr::opt
