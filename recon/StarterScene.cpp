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

// Three significant digits: priors and inits are guesses, not measurements. Through text, so
// that the JSON reads 89.3 and not 89.30000000000001.
double Round(double v) {
  if (v == 0.0 || !std::isfinite(v)) return v;
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v, std::chars_format::general, 3).ptr;
  double rounded = v;
  std::from_chars(text, end, rounded);
  return rounded;
}

Json Uniform(double lo, double hi, double init) {
  return Json{{"prior", {{"uniform", {Round(lo), Round(hi)}}}}, {"init", Round(init)}};
}

// A guess within ±reach of it.
Json Around(double guess, double reach) { return Uniform(guess - reach, guess + reach, guess); }

// A size measured from the points, which undershoot it: 0.5–1.6 times it.
Json Extent(double measured) { return Uniform(kSizeLo * measured, kSizeHi * measured, measured); }

// x y yaw w d: the footprint. The origin is under the points' median, +x along their
// principal axis, so the footprint's centre is near 0 and its long side near yaw 0; ±45°
// covers a footprint whose sides the principal axis does not follow.
void FootprintParameters(const StarterExtents& e, Json& parameters) {
  const Eigen::Vector3d size = e.hi - e.lo, centre = 0.5 * (e.hi + e.lo);
  const double reach = 0.25 * std::max(size.x(), size.y());
  parameters["x"] = Around(centre.x(), reach);
  parameters["y"] = Around(centre.y(), reach);
  parameters["yaw"] = Uniform(-45.0, 45.0, 0.0);
  parameters["w"] = Extent(size.x());
  parameters["d"] = Extent(size.y());
}

Json Scale(Json x, Json y, Json z) { return Json{{"scale", {x, y, z}}}; }

// The walls box on its footprint, as in assets/box and assets/house.
Json Walls(const char* name) {
  return Json{{"name", name},
              {"primitive", "box"},
              {"transforms", {Json{{"translate", {"x", "y", 0}}}, Json{{"rotate", {0, 0, "yaw"}}}, Scale("w", "d", "h")}}};
}

// Two walls from the corner, as docs/examples/merton: wall a along the corner's +x, wall b
// `angle` counter-clockwise from it, both facing the cameras between them. Their lengths are
// the points' and fixed: the photographs may not show where a wall ends.
void CornerNodes(const CornerFit& c, Json& nodes) {
  const double a = Round(c.length_a), b = Round(c.length_b);
  nodes.push_back(Json{{"name", "corner"}, {"transforms", {Json{{"translate", {"xc", "yc", 0}}}, Json{{"rotate", {0, 0, "yaw"}}}}}});
  nodes.push_back(Json{{"name", "wall_a"},
                       {"parent", "corner"},
                       {"primitive", "plane"},
                       {"transforms", {Json{{"translate", {a / 2, 0, "h/2"}}}, Json{{"rotate", {-90, 0, 0}}}, Scale(a, "h", 1)}}});
  nodes.push_back(Json{{"name", "wall_b"},
                       {"parent", "corner"},
                       {"primitive", "plane"},
                       {"transforms", {Json{{"rotate", {0, 0, "angle - 90"}}}, Json{{"translate", {0, b / 2, "h/2"}}},
                                       Json{{"rotate", {-90, 0, -90}}}, Scale(b, "h", 1)}}});
}

// xc yc yaw angle: where the walls meet and how they run, within a twentieth of the longer
// wall, 10° and 15° of what the points say.
void CornerParameters(const CornerFit& c, Json& parameters) {
  const double reach = 0.05 * std::max(c.length_a, c.length_b);
  parameters["xc"] = Around(c.corner.x(), reach);
  parameters["yc"] = Around(c.corner.y(), reach);
  parameters["yaw"] = Around(c.yaw_deg, 10.0);
  parameters["angle"] = Around(c.angle_deg, 15.0);
}

// Four steps up the stairs' local +y from the front edge at (x, y), as assets/stairs: step k
// is `run` deep and (k + 1)·`rise` high. Other flights need steps added or removed, and
// run's and rise's priors scaled to match.
void AddStairs(const StairsFit& s, double top, Json& parameters, Json& nodes) {
  constexpr int kSteps = 4;
  const double reach = 0.25 * std::max(s.width, s.depth), run = s.depth / kSteps, rise = top / kSteps;
  parameters["x"] = Around(s.front.x(), reach);
  parameters["y"] = Around(s.front.y(), reach);
  parameters["yaw"] = Around(s.yaw_deg, 30.0);
  parameters["width"] = Extent(s.width);
  parameters["run"] = Extent(run);
  parameters["rise"] = Extent(rise);
  nodes.push_back(Json{{"name", "stairs"}, {"transforms", {Json{{"translate", {"x", "y", 0}}}, Json{{"rotate", {0, 0, "yaw"}}}}}});
  for (int k = 0; k < kSteps; ++k) {
    const std::string along = std::to_string(k) + ".5*run", height = k == 0 ? "rise" : std::to_string(k + 1) + "*rise";
    nodes.push_back(Json{{"name", "step" + std::to_string(k)},
                         {"parent", "stairs"},
                         {"primitive", "box"},
                         {"transforms", {Json{{"translate", {0, along, 0}}}, Scale("width", "run", height)}}});
  }
}

void AddBox(const StarterExtents& e, Json& parameters, Json& nodes) {
  FootprintParameters(e, parameters);
  parameters["h"] = Extent(e.hi.z());
  nodes.push_back(Walls("box"));
}

void AddHouse(const StarterExtents& e, Json& parameters, Json& nodes) {
  FootprintParameters(e, parameters);
  // The points' top is the ridge: the eaves lie somewhere below it, the roof above them.
  const double top = e.hi.z();
  parameters["h"] = Uniform(0.25 * top, 1.05 * top, 0.6 * top);
  parameters["rh"] = Uniform(0.05 * top, 0.75 * top, 0.4 * top);
  nodes.push_back(Walls("walls"));
  nodes.push_back(Json{{"name", "roof"},
                       {"parent", "walls"},
                       {"primitive", "prism"},
                       {"transforms", {Json{{"translate", {0, 0, 1}}}, Scale(1, 1, "rh/h")}}});
}

void AddCylinder(const StarterExtents& e, Json& parameters, Json& nodes) {
  // The footprint's sides both span the diameter; the robust box undershoots it a little.
  const Eigen::Vector3d size = e.hi - e.lo, centre = 0.5 * (e.hi + e.lo);
  const double across = 0.5 * (size.x() + size.y()), reach = 0.25 * across;
  parameters["x"] = Around(centre.x(), reach);
  parameters["y"] = Around(centre.y(), reach);
  parameters["diameter"] = Extent(across);
  parameters["height"] = Extent(e.hi.z());
  nodes.push_back(Json{{"name", "column"},
                       {"primitive", "cylinder"},
                       {"transforms", {Json{{"translate", {"x", "y", 0}}}, Scale("diameter", "diameter", "height")}}});
}

void AddCorner(const StarterExtents& e, Json& parameters, Json& nodes) {
  CornerParameters(e.corner.value(), parameters);
  // As the house's: the points' top may be a roof's ridge above the walls.
  parameters["h"] = Uniform(0.25 * e.hi.z(), 1.05 * e.hi.z(), 0.6 * e.hi.z());
  CornerNodes(e.corner.value(), nodes);
}

}  // namespace

Json StarterSceneJson(InitTemplate kind, const StarterExtents& e, const std::string& images,
                      const std::optional<std::string>& masks) {
  Json scene{{"version", 1}, {"images", images}};
  if (masks) scene["masks"] = *masks;
  scene["cameras"] = "cameras.json";
  Json parameters = Json::object();
  Json nodes = Json::array();
  const double ground = Round(e.ground_size);
  nodes.push_back(Json{{"name", "ground"}, {"primitive", "plane"}, {"transforms", {Scale(ground, ground, 1)}}});
  switch (kind) {
    case InitTemplate::Box: AddBox(e, parameters, nodes); break;
    case InitTemplate::House: AddHouse(e, parameters, nodes); break;
    case InitTemplate::Cylinder: AddCylinder(e, parameters, nodes); break;
    case InitTemplate::Stairs: AddStairs(e.stairs.value(), e.hi.z(), parameters, nodes); break;
    case InitTemplate::Corner: AddCorner(e, parameters, nodes); break;
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
