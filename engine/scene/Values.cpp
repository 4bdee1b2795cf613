// Parameter value files: `--at P.json` and every asset's `truth.json` are
// {"param": value, …} (docs/guide/SCENE_FORMAT.md, "Parameter files").

#include <charconv>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "engine/common/InputError.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SceneJson.h"

namespace vkr {

std::vector<double> Scene::ValuesFromFile(const std::filesystem::path& at_file) const {
  using namespace scene_detail;
  const std::string display = at_file.string();
  const Json j = ParseJsonFile(at_file, display);
  if (!j.is_object())
    throw InputError(display, "", "expected an object {\"parameter\": value, …}");
  std::vector<double> psi(parameters.size(), 0.0);
  std::vector<bool> given(parameters.size(), false);
  for (const auto& [name, value] : j.items()) {
    const int p = ParameterIndex(name);
    if (p < 0) throw InputError(display, name, "unknown parameter '" + name + "'");
    if (!value.is_number()) throw InputError(display, name, "expected a number");
    const double x = value.get<double>();
    if (!std::isfinite(x)) throw InputError(display, name, "value is not finite");
    if (!parameters[size_t(p)].Admissible(x))
      throw InputError(display, name,
                       "value " + Num(x) + " lies outside the prior or bounds of '" + name + "'");
    psi[size_t(p)] = x;
    given[size_t(p)] = true;
  }
  for (size_t p = 0; p < parameters.size(); ++p)
    if (!given[p])
      throw InputError(display, parameters[p].name,
                       "missing value for parameter '" + parameters[p].name + "'");
  return psi;
}

void Scene::WriteValues(const std::filesystem::path& file, const std::vector<double>& psi) const {
  if (psi.size() != parameters.size())
    throw std::invalid_argument("WriteValues: Ψ has " + std::to_string(psi.size()) +
                                " values, the scene " + std::to_string(parameters.size()));
  // Written by hand rather than by nlohmann::json::dump so the numbers are exact and
  // locale-independent: std::to_chars gives the shortest text that reads back to the same
  // double (full precision without %.17g's 0.10000000000000001 noise).
  std::string text = "{\n";
  for (size_t p = 0; p < psi.size(); ++p) {
    if (!std::isfinite(psi[p]))
      throw std::invalid_argument("WriteValues: " + parameters[p].name + " is not finite");
    char number[32];
    const auto result = std::to_chars(number, number + sizeof number, psi[p]);
    text += "  " + scene_detail::Json(parameters[p].name).dump() + ": " +
            std::string(number, result.ptr) + (p + 1 < psi.size() ? ",\n" : "\n");
  }
  text += "}\n";
  std::ofstream out(file, std::ios::binary);
  if (!out || !(out << text) || !out.flush())
    throw InputError(file.string(), "", "cannot write file");
}

}  // namespace vkr
