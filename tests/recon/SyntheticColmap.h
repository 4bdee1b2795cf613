#pragma once
// A COLMAP model made from a bundled asset at its truth, as `colmap mapper` would leave it:
// the asset's cameras and points sampled on its visible surfaces, all moved by a random
// similarity (COLMAP's frame has an arbitrary rotation, origin and scale), with photographs
// of the cameras' sizes. For `vkrecon init`'s tests (recon/SceneInit.h).

#include <Eigen/Geometry>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "engine/geometry/Mesh.h"
#include "engine/scene/Colmap.h"
#include "engine/scene/Scene.h"
#include "tests/common/TestFiles.h"

namespace vkr::test {

struct SyntheticColmap {
  std::filesystem::path sparse, images;
  Scene scene;               // the asset
  std::vector<double> truth;  // its truth.json, in the order of scene.parameters
  std::vector<Camera> cameras;  // the truth's cameras, truth frame
  // X_model = scale · rotation · X_truth + translation
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;
  std::vector<ColmapPoint> points;  // model frame
  std::uint64_t far_a = 0, far_b = 0;  // two points far apart, and their distance in metres
  double far_metres = 0.0;
};

// Points on the faces of the scene's nodes at `psi` that a camera above the ground could see
// (no face that looks down), area-weighted, with Gaussian noise of `noise` metres.
inline std::vector<Eigen::Vector3d> SampleSurfaces(const Scene& scene, const std::vector<double>& psi, int count,
                                                   double noise, std::mt19937_64& rng) {
  std::vector<Eigen::Vector3d> a, b, c;
  std::vector<double> area;
  const std::vector<Eigen::Matrix4d> world = scene.WorldFromNode(psi);
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const Node& node = scene.nodes[n];
    if (node.primitive == PrimitiveKind::None) continue;
    const Mesh mesh = node.primitive == PrimitiveKind::Mesh ? LoadGltfMesh(node.mesh) : MakePrimitive(node.primitive);
    const auto at = [&](uint32_t i) {
      return (world[n] * mesh.positions[i].cast<double>().homogeneous()).head<3>().eval();
    };
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const Eigen::Vector3d p = at(mesh.indices[t]), q = at(mesh.indices[t + 1]), r = at(mesh.indices[t + 2]);
      const Eigen::Vector3d cross = (q - p).cross(r - p);
      if (cross.norm() <= 0.0 || cross.normalized().z() < -0.5) continue;
      a.push_back(p), b.push_back(q), c.push_back(r), area.push_back(cross.norm());
    }
  }
  std::discrete_distribution<size_t> triangle(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> jitter(0.0, noise);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) {
    const size_t t = triangle(rng);
    double u = unit(rng), v = unit(rng);
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    points.push_back(a[t] + u * (b[t] - a[t]) + v * (c[t] - a[t]) + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  }
  return points;
}

#ifdef VKRECON_SOURCE_DIR  // the test targets define it (tests/CMakeLists.txt); the header check does not
// Writes the asset's model (text in `dir`/sparse, or binary) and grey photographs in `dir`/images.
inline SyntheticColmap MakeSyntheticColmap(const std::string& asset, const std::filesystem::path& dir, bool binary,
                                           std::uint64_t seed, int count = 3000) {
  SyntheticColmap s;
  const std::filesystem::path folder = std::filesystem::path(VKRECON_SOURCE_DIR) / "assets" / asset;
  LoadOptions no_images;
  no_images.require_images = false;
  s.scene = LoadScene(folder / "scene.json", {}, no_images);
  s.truth = s.scene.ValuesFromFile(folder / "truth.json");
  s.cameras = s.scene.Cameras(s.truth);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  s.rotation = Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix();
  s.translation = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)) * 3.0;
  s.scale = std::exp(normal(rng));
  s.images = dir / "images";
  s.sparse = dir / "sparse";
  std::vector<Camera> model_cameras;
  for (const Camera& truth : s.cameras) {
    Camera c = truth;
    c.image = s.images / (c.name + ".pgm");
    const Eigen::Matrix3d R = truth.R() * s.rotation.transpose();
    c.cam_from_world.topLeftCorner<3, 3>() = R;
    c.cam_from_world.topRightCorner<3, 1>() = s.scale * truth.t() - R * s.translation;
    WriteText(c.image, "P5\n" + std::to_string(c.width) + " " + std::to_string(c.height) + "\n255\n" +
                           std::string(size_t(c.width) * size_t(c.height), '\x80'));
    model_cameras.push_back(c);
  }
  const std::vector<Eigen::Vector3d> truth_points = SampleSurfaces(s.scene, s.truth, count, 0.003, rng);
  for (size_t i = 0; i < truth_points.size(); ++i) {
    ColmapPoint p;
    p.id = 1000 + 3 * i;
    p.xyz = s.scale * (s.rotation * truth_points[i]) + s.translation;
    p.rgb = {std::uint8_t(i % 256), 128, 64};
    p.track = {{1, std::uint32_t(i)}, {2, std::uint32_t(i)}};
    s.points.push_back(p);
    if ((truth_points[i] - truth_points[0]).norm() > s.far_metres)
      s.far_b = p.id, s.far_metres = (truth_points[i] - truth_points[0]).norm();
  }
  if (!s.points.empty()) s.far_a = s.points[0].id;
  WriteColmapText(s.sparse, model_cameras, s.images, s.points);
  if (binary) {
    const ColmapReconstruction model = ReadColmapModel(s.sparse, "sparse");
    for (const char* name : {"cameras.txt", "images.txt", "points3D.txt"}) std::filesystem::remove(s.sparse / name);
    WriteColmapBinary(s.sparse, model);
  }
  return s;
}
#endif

// Replaces the model in s.sparse by `change`(the model), written binary.
template <typename Change>
void RewriteColmap(const SyntheticColmap& s, Change change) {
  ColmapReconstruction model = ReadColmapModel(s.sparse, "sparse");
  change(model);
  std::filesystem::remove_all(s.sparse);
  WriteColmapBinary(s.sparse, model);
}

}  // namespace vkr::test
