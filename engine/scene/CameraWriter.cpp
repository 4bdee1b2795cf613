#include "engine/scene/CameraWriter.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/common/InputError.h"

namespace vkr {

void WriteCamerasJson(const std::filesystem::path& file, const std::vector<Camera>& cameras) {
  const std::filesystem::path folder = std::filesystem::absolute(file).parent_path();
  nlohmann::json list = nlohmann::json::array();
  for (const Camera& c : cameras) {
    nlohmann::json j;
    j["name"] = c.name;
    std::filesystem::path image = std::filesystem::absolute(c.image);
    const auto rel = image.lexically_relative(folder);
    if (!rel.empty() && *rel.begin() != "..") image = rel;
    j["image"] = image.generic_string();
    j["width"] = c.width;
    j["height"] = c.height;
    const Eigen::Matrix3d R = c.R();
    const Eigen::Vector3d t = c.t();
    for (int r = 0; r < 3; ++r) {
      j["K"].push_back({c.K(r, 0), c.K(r, 1), c.K(r, 2)});
      j["R"].push_back({R(r, 0), R(r, 1), R(r, 2)});
      j["t"].push_back(t(r));
    }
    if (!c.distortion.IsNone()) {  // what LoadScene reads back (CameraLoader.cpp)
      nlohmann::json d{{"model", ToString(c.distortion.model)}};
      const std::vector<std::string>& names = CoefficientNames(c.distortion.model);
      for (size_t i = 0; i < names.size(); ++i) d[names[i]] = c.distortion.coefficients[i];
      j["distortion"] = d;
    }
    list.push_back(j);
  }
  std::ofstream out(file);
  if (!out) throw InputError(file.string(), "", "cannot write the camera file");
  // nlohmann writes doubles with round-trip precision and the classic locale.
  out << nlohmann::json{{"cameras", list}}.dump(2) << "\n";
  if (!out) throw InputError(file.string(), "", "write failed");
}

}  // namespace vkr
