#include "engine/geometry/AtlasFootprint.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "engine/geometry/SceneGeometry.h"

namespace vkr {
namespace {

// Pixels of the triangle (world corners) in `camera`: 0 when a corner is behind the camera
// or the triangle faces away; otherwise its projected area times the share of its bounding
// box that lies in the image (a cheap clip, exact for triangles wholly inside or outside).
double TrianglePixels(const Camera& camera, const Eigen::Vector3d (&world)[3]) {
  const Eigen::Vector3d normal = (world[1] - world[0]).cross(world[2] - world[0]);
  const Eigen::Vector3d centroid = (world[0] + world[1] + world[2]) / 3.0;
  if (normal.dot(camera.Centre() - centroid) <= 0.0) return 0.0;
  Eigen::Vector2d p[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector4d cam = camera.cam_from_world * world[k].homogeneous();
    if (cam.z() <= 1e-6) return 0.0;
    p[k] = camera.Project(world[k]);
  }
  const double area = 0.5 * std::abs((p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x());
  const Eigen::Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
  const double box = std::max((hi - lo).prod(), 1e-12);
  const double inside_w = std::max(0.0, std::min(hi.x(), double(camera.width)) - std::max(lo.x(), 0.0));
  const double inside_h = std::max(0.0, std::min(hi.y(), double(camera.height)) - std::max(lo.y(), 0.0));
  return area * std::min(1.0, inside_w * inside_h / box);
}

}  // namespace

double SurfaceFootprintPixels(const Scene& scene, const std::vector<Mesh>& meshes) {
  const std::vector<double> psi = scene.InitialValues();
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  const std::vector<Camera> cameras = scene.Cameras(psi);
  double total = 0.0;
  for (size_t n = 0; n < meshes.size() && n < world_from_node.size(); ++n) {
    const Mesh& mesh = meshes[n];
    for (const Face& face : mesh.faces) {
      double largest = 0.0;
      for (const Camera& camera : cameras) {
        double pixels = 0.0;
        for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
          Eigen::Vector3d world[3];
          for (int k = 0; k < 3; ++k)
            world[k] = (world_from_node[n] * mesh.positions[mesh.indices[size_t(3 * t + k)]].cast<double>().homogeneous())
                           .head<3>();
          pixels += TrianglePixels(camera, world);
        }
        largest = std::max(largest, pixels);
      }
      total += largest;
    }
  }
  return total;
}

int AutoAtlasSide(double pixels) {
  const double side = std::sqrt(std::max(pixels, 0.0) / kPixelsPerTexel / kPackingShare);
  if (!(side >= kMinAutoAtlas)) return kMinAutoAtlas;
  const int power = int(std::lround(std::log2(side)));
  return std::clamp(1 << std::min(power, 30), kMinAutoAtlas, kMaxAutoAtlas);
}

int AutoLevels(int atlas_side) {
  int levels = 1;
  while (levels < 3 && (atlas_side >> levels) >= kMinAutoAtlas) ++levels;
  return levels;
}

LikelihoodSettings ResolvedLikelihood(const Scene& scene) {
  LikelihoodSettings s = scene.likelihood;
  if (s.atlas <= 0) s.atlas = AutoAtlasSide(SurfaceFootprintPixels(scene, BuildMeshes(scene)));
  if (s.levels <= 0) s.levels = AutoLevels(s.atlas);
  return s;
}

void ResolveAutoLikelihood(Scene& scene) { scene.likelihood = ResolvedLikelihood(scene); }

}  // namespace vkr
