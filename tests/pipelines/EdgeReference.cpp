// The CPU reference of the edge term; see EdgeReference.h. Each step is edges.comp's, written
// out literally.

#include "tests/pipelines/EdgeReference.h"

#include <Eigen/Geometry>
#include <cmath>

#include "pipelines/model/EdgeEvidence.h"
#include "pipelines/passes/EdgePass.h"
#include "pipelines/passes/Projection.h"
#include "tests/pipelines/SurfaceReference.h"

namespace vkr::test {
namespace {

constexpr double kCreaseCos = 0.8660254037844386;  // 30°

// One camera at the level: projection to level pixels and what edges.comp's push holds.
struct EdgeCamera {
  Eigen::Matrix4d clip_from_world;
  Eigen::Vector3d centre;
  Eigen::Vector2d size;  // level pixels
  const Image* image = nullptr;
  EdgeStatistic statistic;
};

Eigen::Vector4d Clip(const EdgeCamera& c, const Eigen::Vector3d& p) { return c.clip_from_world * p.homogeneous(); }
Eigen::Vector2d Pixel(const EdgeCamera& c, const Eigen::Vector4d& clip) {
  return ((clip.head<2>() / clip.w()).array() * 0.5 + 0.5).matrix().cwiseProduct(c.size);
}

Eigen::Vector3d Colour(const Image& image, const Eigen::Vector2d& p) {
  float rgba[4];
  SampleBilinear(image, p.x(), p.y(), rgba);
  return Eigen::Vector3d(rgba[0], rgba[1], rgba[2]);
}

// Σ w·log-ratio and Σ w of one edge in one camera.
EdgeSums ScoreEdge(const ModelEdge& e, const Eigen::Matrix4d& m, const EdgeCamera& c,
                   const std::vector<WorldTriangle>& occluders) {
  auto world = [&](const Eigen::Vector3f& p) { return Eigen::Vector3d((m * p.cast<double>().homogeneous()).head<3>()); };
  const Eigen::Vector3d a = world(e.a), b = world(e.b), c0 = world(e.c0), c1 = world(e.c1);
  const double handed = m.topLeftCorner<3, 3>().determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d n0 = handed * e.sign0 * (b - a).cross(c0 - a);
  const Eigen::Vector3d to_camera = c.centre - a;
  const bool front0 = n0.dot(to_camera) > 0.0;
  Eigen::Vector3d inside = c0;
  double cos_front = n0.normalized().dot(to_camera.normalized());
  if (e.sign1 == 0.0f) {
    if (!front0) return {};
  } else {
    const Eigen::Vector3d n1 = handed * e.sign1 * (b - a).cross(c1 - a);
    const bool front1 = n1.dot(to_camera) > 0.0;
    if (!front0 && !front1) return {};
    if (front0 && front1) {
      if (n0.normalized().dot(n1.normalized()) > kCreaseCos) return {};
      cos_front = std::max(cos_front, n1.normalized().dot(to_camera.normalized()));
    } else if (front1) {
      inside = c1;
      cos_front = n1.normalized().dot(to_camera.normalized());
    }
  }
  const Eigen::Vector4d clip_a = Clip(c, a), clip_b = Clip(c, b), clip_in = Clip(c, inside);
  if (clip_a.w() <= kDefaultNear || clip_b.w() <= kDefaultNear || clip_in.w() <= kDefaultNear) return {};
  const Eigen::Vector2d pa = Pixel(c, clip_a), pb = Pixel(c, clip_b);
  const double len = (pb - pa).norm();
  if (len < 1e-3) return {};
  Eigen::Vector2d normal = Eigen::Vector2d(pa.y() - pb.y(), pb.x() - pa.x()) / len;
  if ((Pixel(c, clip_in) - pa).dot(normal) < 0.0) normal = -normal;
  (void)cos_front;  // the GPU's depth tolerance; the ray cast needs none
  const double weight = len / EdgePass::kSamples;
  EdgeSums sums;
  for (uint32_t j = 0; j < EdgePass::kSamples; ++j) {
    const double t = (j + 0.5) / EdgePass::kSamples;
    const Eigen::Vector3d x = a + t * (b - a);
    const Eigen::Vector2d p = Pixel(c, Clip(c, x));
    const Eigen::Vector2d p_in = p + 0.5 * normal, p_out = p - 0.5 * normal;
    if (p_in.minCoeff() < 1.0 || p_out.minCoeff() < 1.0 || (c.size - p_in).minCoeff() < 1.0 ||
        (c.size - p_out).minCoeff() < 1.0)
      continue;
    bool occluded = false;
    for (const WorldTriangle& tri : occluders)
      if (SegmentHits(tri, x, c.centre - x)) {
        occluded = true;
        break;
      }
    if (occluded) continue;
    const Eigen::Vector3d delta = Colour(*c.image, p_in) - Colour(*c.image, p_out);
    sums.log_edges +=
        weight * EdgeLogRatio(delta, c.statistic.variance, c.statistic.clutter, c.statistic.hidden);
    sums.length += weight;
  }
  return sums;
}

}  // namespace

EdgeSums ReferenceEdgeSums(const Scene& scene, const SceneGeometry& geometry,
                           const std::vector<std::vector<Image>>& pyramids, const std::vector<double>& psi, int level,
                           const SurfaceLikelihoodOptions& options) {
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  const std::vector<WorldTriangle> occluders = WorldTriangles(geometry, world_from_node);
  const std::vector<ModelEdge> edges = FindModelEdges(geometry);
  const std::vector<Camera> cameras = scene.Cameras(psi);
  EdgeSums total;
  for (size_t i = 0; i < cameras.size(); ++i) {
    EdgeCamera c;
    c.clip_from_world = ClipFromWorld(cameras[i]);
    c.centre = cameras[i].Centre();
    c.size = Eigen::Vector2d(cameras[i].width, cameras[i].height) / std::exp2(level);
    c.image = &pyramids[i][size_t(level)];
    const double sigma = options.model.sigma / 255.0;
    c.statistic.variance = 2.0 * sigma * sigma / std::exp2(2.0 * level);
    c.statistic.clutter = ClutterShare(PairContrasts(*c.image, Image()), c.statistic.variance, options.edge_model);
    c.statistic.hidden = options.edge_model.hidden;
    for (const ModelEdge& e : edges) {
      const EdgeSums s = ScoreEdge(e, world_from_node[e.node], c, occluders);
      total.log_edges += s.log_edges;
      total.length += s.length;
    }
  }
  return total;
}

}  // namespace vkr::test
