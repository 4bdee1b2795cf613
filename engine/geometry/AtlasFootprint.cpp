#include "engine/geometry/AtlasFootprint.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include <Eigen/Geometry>

#include "engine/geometry/SceneGeometry.h"

namespace vkr {
namespace {

// Keeps the part of `polygon` where inside(p) ≥ 0, inside affine along edges (one
// Sutherland–Hodgman step).
template <typename Point, typename Inside>
std::vector<Point> ClipPolygon(const std::vector<Point>& polygon, Inside inside) {
  std::vector<Point> out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Point& a = polygon[(i + polygon.size() - 1) % polygon.size()];
    const Point& b = polygon[i];
    const double da = inside(a), db = inside(b);
    if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    if (db >= 0.0) out.push_back(b);
  }
  return out;
}

// Pixels of the triangle (world corners) in `camera`'s image: 0 when it faces away;
// otherwise the area of its part in front of the camera, projected and clipped to the image.
double ClippedPixels(const Camera& camera, const std::array<Eigen::Vector3d, 3>& world) {
  const Eigen::Vector3d normal = (world[1] - world[0]).cross(world[2] - world[0]);
  const Eigen::Vector3d centroid = (world[0] + world[1] + world[2]) / 3.0;
  if (normal.dot(camera.Centre() - centroid) <= 0.0) return 0.0;
  // Surface nearer than this to the camera's plane is none a photograph shows.
  constexpr double kNear = 1e-3;
  std::vector<Eigen::Vector3d> near_clipped;
  for (const Eigen::Vector3d& w : world) near_clipped.push_back(camera.R() * w + camera.t());
  near_clipped = ClipPolygon(near_clipped, [](const Eigen::Vector3d& c) { return c.z() - kNear; });
  std::vector<Eigen::Vector2d> image;
  for (const Eigen::Vector3d& c : near_clipped) image.push_back((camera.K * c).hnormalized());
  const double w = camera.width, h = camera.height;
  image = ClipPolygon(image, [](const Eigen::Vector2d& p) { return p.x(); });
  image = ClipPolygon(image, [w](const Eigen::Vector2d& p) { return w - p.x(); });
  image = ClipPolygon(image, [](const Eigen::Vector2d& p) { return p.y(); });
  image = ClipPolygon(image, [h](const Eigen::Vector2d& p) { return h - p.y(); });
  double twice = 0.0;  // shoelace
  for (size_t i = 0; i < image.size(); ++i) {
    const Eigen::Vector2d& p = image[i];
    const Eigen::Vector2d& q = image[(i + 1) % image.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * std::abs(twice);
}

// The sizing rule's cruder count, which its constants were fitted with (the bundled assets
// land at the 256² their study validated): 0 when a corner is behind the camera (so a ground
// plane that runs on under the cameras counts nothing) or the triangle faces away; otherwise
// its projected area times the share of its bounding box that lies in the image.
double BoxClippedPixels(const Camera& camera, const std::array<Eigen::Vector3d, 3>& world) {
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

using TrianglePixels = double (*)(const Camera&, const std::array<Eigen::Vector3d, 3>&);

// Triangle t of `mesh` in world coordinates.
std::array<Eigen::Vector3d, 3> WorldTriangle(const Mesh& mesh, int t, const Eigen::Matrix4d& world_from_node) {
  std::array<Eigen::Vector3d, 3> world;
  for (int k = 0; k < 3; ++k)
    world[k] = (world_from_node * mesh.positions[mesh.indices[size_t(3 * t + k)]].cast<double>().homogeneous()).head<3>();
  return world;
}

// Per face, the largest of `pixels` summed over its triangles, over the cameras.
std::vector<double> PixelsPerFace(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi,
                                  TrianglePixels pixels_of) {
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  const std::vector<Camera> cameras = scene.Cameras(psi);
  std::vector<double> faces;
  for (size_t n = 0; n < meshes.size(); ++n) {
    const Mesh& mesh = meshes[n];
    for (const Face& face : mesh.faces) {
      double largest = 0.0;
      for (const Camera& camera : cameras) {
        double pixels = 0.0;
        for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
          const std::array<Eigen::Vector3d, 3> world = WorldTriangle(mesh, t, world_from_node.at(n));
          pixels += pixels_of(camera, world);
        }
        largest = std::max(largest, pixels);
      }
      faces.push_back(largest);
    }
  }
  return faces;
}

}  // namespace

std::vector<double> FacePixels(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi) {
  return PixelsPerFace(scene, meshes, psi, ClippedPixels);
}

double SurfaceFootprintPixels(const Scene& scene, const std::vector<Mesh>& meshes) {
  const std::vector<double> faces = PixelsPerFace(scene, meshes, scene.InitialValues(), BoxClippedPixels);
  return std::accumulate(faces.begin(), faces.end(), 0.0);
}

std::vector<double> ChartDensities(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi) {
  const std::vector<double> pixels = FacePixels(scene, meshes, psi);
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  std::vector<double> area;
  for (size_t n = 0; n < meshes.size(); ++n) {
    for (const Face& face : meshes[n].faces) {
      double a = 0.0;
      for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
        const std::array<Eigen::Vector3d, 3> w = WorldTriangle(meshes[n], t, world_from_node.at(n));
        a += 0.5 * (w[1] - w[0]).cross(w[2] - w[0]).norm();
      }
      area.push_back(a);
    }
  }
  const double total_pixels = std::accumulate(pixels.begin(), pixels.end(), 0.0);
  const double total_area = std::accumulate(area.begin(), area.end(), 0.0);
  // No face seen at all, or no area: nothing to follow; every face the same density.
  if (!(total_pixels > 0.0 && total_area > 0.0)) return std::vector<double>(pixels.size(), 1.0);
  const double even = std::sqrt(total_pixels / total_area);
  std::vector<double> density(pixels.size());
  for (size_t f = 0; f < pixels.size(); ++f)
    density[f] = area[f] > 0.0 ? std::max(std::sqrt(pixels[f] / area[f]), 0.25 * even) / even : 1.0;
  return density;
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

}  // namespace vkr
