#include "recon/StarterScene.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace vkr::recon {
namespace {

using Json = nlohmann::ordered_json;

// Priors bracket a robust estimate generously: the 2nd–98th percentiles of sparse points
// undershoot a face's extent, and a template is only a first guess of the shape.
constexpr double kSizeLo = 0.5, kSizeHi = 1.6;

// A few significant digits: priors and inits are guesses, not measurements.
double Round(double v) {
  if (v == 0.0 || !std::isfinite(v)) return v;
  const double unit = std::pow(10.0, std::floor(std::log10(std::abs(v))) - 2);
  return std::round(v / unit) * unit;
}

Json Uniform(double lo, double hi, double init) {
  return Json{{"prior", {{"uniform", {Round(lo), Round(hi)}}}}, {"init", Round(init)}};
}

// x y yaw w d: the footprint. The origin is under the points' median, +x along their
// principal axis, so the footprint's centre is near 0 and its long side near yaw 0; ±45°
// covers a footprint whose sides the principal axis does not follow.
void FootprintParameters(const StarterExtents& e, Json& parameters) {
  const Eigen::Vector3d size = e.hi - e.lo, centre = 0.5 * (e.hi + e.lo);
  const double reach = 0.25 * std::max(size.x(), size.y());
  parameters["x"] = Uniform(centre.x() - reach, centre.x() + reach, centre.x());
  parameters["y"] = Uniform(centre.y() - reach, centre.y() + reach, centre.y());
  parameters["yaw"] = Uniform(-45.0, 45.0, 0.0);
  parameters["w"] = Uniform(kSizeLo * size.x(), kSizeHi * size.x(), size.x());
  parameters["d"] = Uniform(kSizeLo * size.y(), kSizeHi * size.y(), size.y());
}

Json Scale(Json x, Json y, Json z) { return Json{{"scale", {x, y, z}}}; }

// The walls box on its footprint, as in assets/box and assets/house.
Json Walls(const char* name) {
  return Json{{"name", name},
              {"primitive", "box"},
              {"transforms", {Json{{"translate", {"x", "y", 0}}}, Json{{"rotate", {0, 0, "yaw"}}}, Scale("w", "d", "h")}}};
}

}  // namespace

Json StarterSceneJson(InitTemplate kind, const StarterExtents& e, const std::string& images,
                      const std::optional<std::string>& masks) {
  Json scene{{"version", 1}, {"images", images}};
  if (masks) scene["masks"] = *masks;
  scene["cameras"] = "cameras.json";
  Json parameters = Json::object();
  FootprintParameters(e, parameters);
  const double top = e.hi.z();
  Json nodes = Json::array();
  nodes.push_back(Json{{"name", "ground"}, {"primitive", "plane"}, {"transforms", {Scale(e.ground_size, e.ground_size, 1)}}});
  if (kind == InitTemplate::Box) {
    parameters["h"] = Uniform(kSizeLo * top, kSizeHi * top, top);
    nodes.push_back(Walls("box"));
  } else {
    // The points' top is the ridge: the eaves lie somewhere below it, the roof above them.
    parameters["h"] = Uniform(0.25 * top, 1.05 * top, 0.6 * top);
    parameters["rh"] = Uniform(0.05 * top, 0.75 * top, 0.4 * top);
    nodes.push_back(Walls("walls"));
    nodes.push_back(Json{{"name", "roof"},
                         {"parent", "walls"},
                         {"primitive", "prism"},
                         {"transforms", {Json{{"translate", {0, 0, 1}}}, Scale(1, 1, "rh/h")}}});
  }
  scene["parameters"] = parameters;
  scene["nodes"] = nodes;
  // The ground is 2–6 times the footprint and seen obliquely: shared by area it would take most
  // texels, and the object, which the photographs show largest, would get too few.
  scene["likelihood"] = Json{{"kind", "surface"}, {"sigma", "auto"}, {"weights", "angle"}, {"charts", "pixels"}};
  return scene;
}

std::string PointsPly(const std::vector<Eigen::Vector3d>& xyz, const std::vector<std::array<std::uint8_t, 3>>& rgb) {
  std::string ply = "ply\nformat ascii 1.0\ncomment vkrecon init: COLMAP's points in the scene frame\nelement vertex " +
                    std::to_string(xyz.size()) +
                    "\nproperty double x\nproperty double y\nproperty double z\n"
                    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  char text[32];
  for (size_t i = 0; i < xyz.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      ply.append(text, std::to_chars(text, text + sizeof text, xyz[i][k]).ptr);
      ply += ' ';
    }
    ply += std::to_string(int(rgb[i][0])) + " " + std::to_string(int(rgb[i][1])) + " " + std::to_string(int(rgb[i][2])) + "\n";
  }
  return ply;
}

}  // namespace vkr::recon
