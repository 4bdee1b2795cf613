#include "tests/pipelines/SignScene.h"

#include <cmath>
#include <sstream>

#include <Eigen/Dense>

#include "pipelines/rendering/ViewRendering.h"

namespace vkr::test {
namespace {

namespace fs = std::filesystem;

// One camera entry looking from `eye` at `target`, OpenCV convention, z up in the world.
std::string SignCamera(const std::string& name, const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x.transpose(), y.transpose(), z.transpose();
  const Eigen::Vector3d t = -R * eye;
  std::ostringstream s;
  s.precision(17);
  s << R"({"name": ")" << name << R"(", "image": ")" << name << R"(.png", "width": 160, "height": 120,
          "K": [[150, 0, 80], [0, 150, 60], [0, 0, 1]], "R": [)";
  for (int r = 0; r < 3; ++r) s << (r ? ", " : "") << "[" << R(r, 0) << ", " << R(r, 1) << ", " << R(r, 2) << "]";
  s << R"(], "t": [)" << t.x() << ", " << t.y() << ", " << t.z() << "]}";
  return s.str();
}

}  // namespace

Scene SignScene(vk::Device& device, const TempDir& dir) {
  const fs::path textures = fs::path(VKRECON_SOURCE_DIR) / "assets/box/textures";
  std::string cameras;
  for (int i = 0; i < 5; ++i) {
    const double a = (-50.0 + 25.0 * i) * M_PI / 180.0;
    cameras += (i ? ",\n" : "") +
               SignCamera("cam" + std::to_string(i), {3.0 * std::sin(a), -3.0 * std::cos(a), 1.3}, {0.0, 0.0, 0.5});
  }
  // tilt 90°: the sign's face (+z of the plane) turns to −y, towards the cameras; −90°: away.
  WriteText(dir / "scene.json", R"({
    "version": 1,
    "parameters": {"tilt": {"prior": {"uniform": [-100, 100]}}},
    "nodes": [
      {"name": "ground", "primitive": "plane", "albedo": ")" + (textures / "ground.png").string() + R"(",
       "transforms": [{"scale": [4, 4, 1]}]},
      {"name": "sign", "primitive": "plane", "albedo": ")" + (textures / "box.png").string() + R"(",
       "transforms": [{"translate": [0, 0, 0.6]}, {"rotate": ["tilt", 0, 0]}, {"scale": [1, 0.8, 1]}]}],
    "cameras": [)" + cameras + R"(]
  })");
  WriteText(dir / "truth.json", R"({"tilt": 90})");
  SynthOptions synth;
  synth.scene_file = dir / "scene.json";
  synth.at_file = dir / "truth.json";
  synth.output_dir = dir.path();
  synth.noise_sigma = 16.0;
  synth.seed = 3;
  SynthesiseImages(synth, device);
  return LoadScene(dir / "scene.json");
}

}  // namespace vkr::test
