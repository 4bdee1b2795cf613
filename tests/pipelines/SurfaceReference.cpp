// The CPU reference of the surface-space likelihood; see SurfaceReference.h. The
// definitions here are the ones SurfaceLikelihood implements on the GPU, written out
// literally: texel centres in atlas UV, analytic inside tests with ε = 1e-3 in each
// primitive's unit frame, ray-cast visibility, host bilinear sampling.

#include "tests/pipelines/SurfaceReference.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "engine/image/Pyramid.h"
#include "pipelines/passes/Projection.h"
#include "pipelines/likelihood/ReferenceImages.h"
#include "pipelines/rendering/ViewRendering.h"

namespace vkr::test {
namespace {

constexpr double kInsideEpsilon = 1e-3;     // unit-frame slack of the interior test
constexpr double kRayStart = 1e-4;          // segment parameter below which hits are the texel's own surface
constexpr double kRayEnd = 1.0 - 1e-6;      // and above which they are at the camera centre

// A texel's point on the surface: the triangle that owns it and its barycentrics.
struct TexelHit {
  int triangle = -1;
  double b[3] = {0, 0, 0};
};

// Assigns every texel centre to the first triangle (in index order) containing it,
// boundaries included, by rasterising each triangle's bounding box in atlas space.
std::vector<TexelHit> LocateTexels(const SceneGeometry& geometry, int side) {
  std::vector<TexelHit> hits(size_t(side) * side);
  const size_t triangles = geometry.indices.size() / 3;
  for (size_t t = 0; t < triangles; ++t) {
    Eigen::Vector2d p[3];
    for (int k = 0; k < 3; ++k) {
      const GpuVertex& v = geometry.vertices[geometry.indices[3 * t + k]];
      p[k] = Eigen::Vector2d(v.atlas_uv[0], v.atlas_uv[1]) * double(side);  // texel units
    }
    const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    if (area == 0.0) continue;
    const double lo_x = std::min({p[0].x(), p[1].x(), p[2].x()});
    const double hi_x = std::max({p[0].x(), p[1].x(), p[2].x()});
    const double lo_y = std::min({p[0].y(), p[1].y(), p[2].y()});
    const double hi_y = std::max({p[0].y(), p[1].y(), p[2].y()});
    // Texel i's centre is i + 0.5.
    const int i0 = std::max(0, int(std::ceil(lo_x - 0.5))), i1 = std::min(side - 1, int(std::floor(hi_x - 0.5)));
    const int j0 = std::max(0, int(std::ceil(lo_y - 0.5))), j1 = std::min(side - 1, int(std::floor(hi_y - 0.5)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        TexelHit& hit = hits[size_t(j) * side + i];
        if (hit.triangle >= 0) continue;
        const Eigen::Vector2d c(i + 0.5, j + 0.5);
        double b[3];
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& a = p[(k + 1) % 3];
          const Eigen::Vector2d& e = p[(k + 2) % 3];
          b[k] = ((e - a).x() * (c - a).y() - (e - a).y() * (c - a).x()) / area;
        }
        if (b[0] < 0.0 || b[1] < 0.0 || b[2] < 0.0) continue;
        hit.triangle = int(t);
        for (int k = 0; k < 3; ++k) hit.b[k] = b[k];
      }
  }
  return hits;
}

// Whether the point p (in a node's unit frame) lies inside or on its primitive, with slack ε.
bool InsidePrimitive(PrimitiveKind kind, const Eigen::Vector3d& p) {
  const double e = kInsideEpsilon;
  switch (kind) {
    case PrimitiveKind::Box:
      return std::abs(p.x()) <= 0.5 + e && std::abs(p.y()) <= 0.5 + e && p.z() >= -e && p.z() <= 1 + e;
    case PrimitiveKind::Prism:
      return std::abs(p.x()) <= 0.5 + e && p.z() >= -e && p.z() <= 1 + e &&
             std::abs(p.y()) <= 0.5 * (1.0 - p.z()) + e;
    case PrimitiveKind::Cylinder:
      return p.x() * p.x() + p.y() * p.y() <= (0.5 + e) * (0.5 + e) && p.z() >= -e && p.z() <= 1 + e;
    case PrimitiveKind::Plane:
      // The half-space below the plane: what stands on the ground has its underside inside.
      return std::abs(p.x()) <= 0.5 + e && std::abs(p.y()) <= 0.5 + e && p.z() <= e;
    case PrimitiveKind::Mesh:
    case PrimitiveKind::None:
      return false;
  }
  return false;
}

}  // namespace

bool SegmentHits(const WorldTriangle& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const Eigen::Vector3d pv = d.cross(tri.e2);
  const double det = tri.e1.dot(pv);
  if (std::abs(det) < 1e-14) return false;  // parallel to the plane
  const double inv = 1.0 / det;
  const Eigen::Vector3d tv = o - tri.v0;
  const double u = tv.dot(pv) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d qv = tv.cross(tri.e1);
  const double v = d.dot(qv) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = tri.e2.dot(qv) * inv;
  return t > kRayStart && t < kRayEnd;
}

std::vector<WorldTriangle> WorldTriangles(const SceneGeometry& geometry,
                                          const std::vector<Eigen::Matrix4d>& world_from_node) {
  const size_t triangle_count = geometry.indices.size() / 3;
  std::vector<WorldTriangle> world_triangles(triangle_count);
  auto world_vertex = [&](uint32_t index) {
    const GpuVertex& v = geometry.vertices[index];
    const Eigen::Vector4d p(v.position[0], v.position[1], v.position[2], 1.0);
    return Eigen::Vector3d((world_from_node[v.node] * p).head<3>());
  };
  for (size_t t = 0; t < triangle_count; ++t) {
    const Eigen::Vector3d a = world_vertex(geometry.indices[3 * t]);
    const Eigen::Vector3d b = world_vertex(geometry.indices[3 * t + 1]);
    const Eigen::Vector3d c = world_vertex(geometry.indices[3 * t + 2]);
    world_triangles[t] = {a, b - a, c - a};
  }
  return world_triangles;
}

namespace {

// A camera at one pyramid level.
struct LevelCamera {
  Eigen::Matrix3d K;  // K_l = diag(2^-l, 2^-l, 1)·K
  Eigen::Matrix4d cam_from_world;
  Eigen::Vector3d centre;
  const std::vector<Image>* pyramid = nullptr;
  const std::vector<Image>* validity = nullptr;  // null or empty: every pixel counts
  int width = 0, height = 0;  // of level l
};

}  // namespace

std::vector<std::vector<Image>> LoadReferencePyramids(const Scene& scene, int levels,
                                                      std::vector<std::vector<Image>>* validity) {
  std::vector<std::vector<Image>> pyramids;
  if (validity) validity->clear();
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const CameraPhoto photo = LoadCameraPhoto(scene, int(c), 1);
    pyramids.push_back(BuildPyramid(photo.image, levels));
    for (Image& level : pyramids.back()) StoreGradientInAlpha(level);
    if (validity)
      validity->push_back(photo.validity.Empty() ? std::vector<Image>{} : BuildValidityPyramid(photo.validity, levels));
  }
  return pyramids;
}

uint32_t SurfaceTexelCount(const SceneGeometry& geometry, int level) {
  const std::vector<bool> surface = SurfaceTexels(geometry, level);
  return uint32_t(std::count(surface.begin(), surface.end(), true));
}

std::vector<bool> SurfaceTexels(const SceneGeometry& geometry, int level) {
  std::vector<bool> surface;
  for (const TexelHit& h : LocateTexels(geometry, geometry.atlas.size >> level)) surface.push_back(h.triangle >= 0);
  return surface;
}

TexelStatistic ReferenceTexelStatistic(const std::vector<ViewSample>& views, const LikelihoodModel& model,
                                       const PhotometricCorrection& photometric) {
  const double sigma = model.sigma / 255.0, K = model.outlier_chi2;
  const size_t n = views.size();
  std::vector<Eigen::Vector3d> c(n);
  std::vector<double> w(n), v(n), omega(n, 1.0), e2(n);
  for (size_t i = 0; i < n; ++i) {
    const auto& gain = photometric.gain[size_t(views[i].camera)];
    const auto& offset = photometric.offset[size_t(views[i].camera)];
    for (int ch = 0; ch < 3; ++ch) c[i][ch] = gain[size_t(ch)] * views[i].colour[ch] + offset[size_t(ch)];
    const double g = (gain[0] + gain[1] + gain[2]) / 3.0 * views[i].texture;
    const double mass = std::max(views[i].mass, 1.0);
    w[i] = views[i].weight;
    v[i] = sigma * sigma / mass + model.position_sd * model.position_sd * g * g;
  }
  TexelStatistic s;
  // Consensus: the precision-weighted mean, reweighted (three rounds, composite.comp's
  // kRounds) by Welsch weights that are 1 up to e² = K/3 and relative to the best-agreeing
  // view beyond, unless every view is within K/3 of the plain mean.
  const double flat = K / 3.0;
  auto fit = [&]() {
    double sp = 0.0;
    Eigen::Vector3d spc = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) {
      const double p = omega[i] * w[i] / v[i];
      sp += p;
      spc += p * c[i];
    }
    s.mean = spc / sp;
    double farthest = 0.0;
    for (size_t i = 0; i < n; ++i) farthest = std::max(farthest, e2[i] = (c[i] - s.mean).squaredNorm() / v[i]);
    return farthest;
  };
  const int rounds = fit() > flat ? 3 : 0;
  for (int round = 0; round < rounds; ++round) {
    double closest = INFINITY;
    for (size_t i = 0; i < n; ++i) closest = std::min(closest, e2[i]);
    const double base = std::max(closest, flat);
    for (size_t i = 0; i < n; ++i) omega[i] = std::exp((base - std::max(e2[i], flat)) / K);
    fit();
  }
  // Loss: quadratic up to K/3, then saturating to K with a continuous slope. Its expectation
  // under the noise model: 3(Σw − Σw·p/Σp) for the quadratic loss (view i's residual from the
  // plain precision-weighted mean has variance a_i·v_i per channel and Σ w_i 3a_i is that);
  // the saturation lowers it by under 0.3 %.
  const double t = K / 3.0;
  double sp = 0.0, spw = 0.0, sum_w = 0.0;
  for (size_t i = 0; i < n; ++i) sp += w[i] / v[i], spw += w[i] * w[i] / v[i], sum_w += w[i];
  for (size_t i = 0; i < n; ++i) {
    s.chi2 += w[i] * (e2[i] <= t ? e2[i] : t + (K - t) * (1.0 - std::exp((t - e2[i]) / (K - t))));
    s.outliers += e2[i] > K;
  }
  s.expected = 3.0 * std::max(sum_w - spw / sp, 0.0);
  // A texel whose views all disagree costs one average view's saturation beyond the expectation.
  s.chi2 = std::min(s.chi2, s.expected + K * sum_w / double(n));
  return s;
}

ReducedScalars ReferenceSurfaceScalars(const Scene& scene, const SceneGeometry& geometry,
                                       const std::vector<std::vector<Image>>& pyramids,
                                       const std::vector<double>& psi, int level,
                                       const SurfaceLikelihoodOptions& options,
                                       ReferenceTexels* texels, ColourSampling sampling,
                                       const std::vector<std::vector<Image>>* validity,
                                       const PhotometricCorrection* photometric) {
  const PhotometricCorrection identity = PhotometricCorrection::Identity(int(scene.cameras.size()));
  if (!photometric) photometric = &identity;
  const int side = geometry.atlas.size >> level;
  if (side <= 0) throw std::invalid_argument("ReferenceSurfaceScalars: level too coarse for the atlas");
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  const size_t nodes = world_from_node.size();
  std::vector<Eigen::Matrix4d> node_from_world(nodes);
  std::vector<Eigen::Matrix3d> normal_matrix(nodes);
  for (size_t n = 0; n < nodes; ++n) {
    node_from_world[n] = world_from_node[n].inverse();
    normal_matrix[n] = world_from_node[n].topLeftCorner<3, 3>().inverse().transpose();
  }

  const std::vector<Camera> scene_cameras = scene.Cameras(psi);
  if (pyramids.size() != scene_cameras.size() || (validity && validity->size() != pyramids.size()))
    throw std::invalid_argument("ReferenceSurfaceScalars: one pyramid per camera expected");
  const double s = std::ldexp(1.0, -level);
  std::vector<LevelCamera> cameras;
  for (size_t c = 0; c < scene_cameras.size(); ++c) {
    if (int(pyramids[c].size()) <= level) throw std::invalid_argument("ReferenceSurfaceScalars: pyramid too short");
    LevelCamera lc;
    lc.K = Eigen::Vector3d(s, s, 1.0).asDiagonal() * scene_cameras[c].K;
    lc.cam_from_world = scene_cameras[c].cam_from_world;
    lc.centre = scene_cameras[c].Centre();
    lc.pyramid = &pyramids[c];
    if (validity && !(*validity)[c].empty()) lc.validity = &(*validity)[c];
    lc.width = pyramids[c][level].width;
    lc.height = pyramids[c][level].height;
    cameras.push_back(lc);
  }

  // Every triangle of the scene in world space at Ψ, the occluders of the visibility test.
  const std::vector<WorldTriangle> world_triangles = WorldTriangles(geometry, world_from_node);
  auto world_vertex = [&](uint32_t index) {
    const GpuVertex& v = geometry.vertices[index];
    const Eigen::Vector4d p(v.position[0], v.position[1], v.position[2], 1.0);
    return Eigen::Vector3d((world_from_node[v.node] * p).head<3>());
  };

  const double sigma = options.model.sigma / 255.0;
  const double sigma2 = sigma * sigma;

  if (texels) {
    texels->side = side;
    texels->state.assign(size_t(side) * side, TexelState::OffSurface);
    texels->chart.assign(size_t(side) * side, -1);
    texels->views.assign(size_t(side) * side, 0);
    texels->deviation.assign(size_t(side) * side, 0.0);
    texels->dof.assign(size_t(side) * side, 0.0);
    texels->outliers.assign(size_t(side) * side, 0);
    texels->view_textures.assign(cameras.size(), Image(side, side, 0.0f));
  }

  ReducedScalars out;
  const std::vector<TexelHit> hits = LocateTexels(geometry, side);
  std::vector<ViewSample> samples(cameras.size());
  for (size_t index = 0; index < hits.size(); ++index) {
    const TexelHit& hit = hits[index];
    if (hit.triangle < 0) continue;
    const GpuVertex* v[3];
    for (int k = 0; k < 3; ++k) v[k] = &geometry.vertices[geometry.indices[3 * hit.triangle + k]];
    const uint32_t node = v[0]->node;
    Eigen::Vector3d X = Eigen::Vector3d::Zero(), normal_node = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      X += hit.b[k] * world_vertex(geometry.indices[3 * hit.triangle + k]);
      normal_node += hit.b[k] * Eigen::Vector3d(v[k]->normal[0], v[k]->normal[1], v[k]->normal[2]);
    }
    const Eigen::Vector3d n = (normal_matrix[node] * normal_node).normalized();
    if (texels) texels->chart[index] = int(v[0]->face);
    // T_l: the world area of one level-l texel of this texel's chart, from the layout (not
    // from the vertex's copy the GPU reads, so that copy is checked too).
    const double texel_metres = std::ldexp(1.0, level) / geometry.atlas.charts.at(v[0]->face).texels_per_metre;
    const double texel_area = texel_metres * texel_metres;

    bool interior = false;
    for (size_t other = 0; other < nodes && !interior; ++other) {
      if (other == node) continue;
      const Eigen::Vector3d p = (node_from_world[other] * X.homogeneous()).head<3>();
      interior = InsidePrimitive(scene.nodes[other].primitive, p);
    }
    if (interior) {
      ++out.interior;
      if (texels) texels->state[index] = TexelState::Interior;
      continue;
    }

    int seen = 0, masked = 0;
    for (size_t c = 0; c < cameras.size(); ++c) {
      const LevelCamera& cam = cameras[c];
      const Eigen::Vector3d x_cam = (cam.cam_from_world * X.homogeneous()).head<3>();
      const double z = x_cam.z();
      if (!(z > kDefaultNear)) continue;
      const Eigen::Vector3d uvw = cam.K * (x_cam / z);
      const double u = uvw.x(), vv = uvw.y();
      if (u < 0.0 || u > cam.width || vv < 0.0 || vv > cam.height) continue;
      const Eigen::Vector3d to_camera = cam.centre - X;
      if (!(n.dot(to_camera) > 0.0)) continue;
      bool occluded = false;
      for (const WorldTriangle& tri : world_triangles)
        if (SegmentHits(tri, X, to_camera)) {
          occluded = true;
          break;
        }
      if (occluded) continue;

      const double cos_theta = n.dot(to_camera.normalized());
      // The texel's area in level-l pixels.
      const double footprint = texel_area * cos_theta * cam.K(0, 0) * cam.K(1, 1) / (z * z);
      // One sample of a pyramid (the colours', or the validity's, read the same way).
      auto sample = [&](const std::vector<Image>& pyramid, float rgba[4]) {
        if (sampling == ColourSampling::LevelBilinear) {
          SampleBilinear(pyramid[level], u, vv, rgba);
          return;
        }
        const int last = int(pyramid.size()) - 1;
        double lambda = level + std::max(0.0, 0.5 * std::log2(std::max(footprint, 1e-12)));
        lambda = std::min(lambda, double(last));
        const int k0 = int(std::floor(lambda));
        const double frac = lambda - k0;
        SampleBilinear(pyramid[k0], std::ldexp(u, level - k0), std::ldexp(vv, level - k0), rgba);
        if (frac > 0.0 && k0 < last) {
          float finer[4];
          for (int ch = 0; ch < 4; ++ch) finer[ch] = rgba[ch];
          SampleBilinear(pyramid[k0 + 1], std::ldexp(u, level - k0 - 1), std::ldexp(vv, level - k0 - 1), rgba);
          for (int ch = 0; ch < 4; ++ch) rgba[ch] = float((1.0 - frac) * finer[ch] + frac * rgba[ch]);
        }
      };
      // Masked pixels and the lens border are no evidence: a sample touching one is dropped.
      if (cam.validity) {
        float valid[4];
        sample(*cam.validity, valid);
        if (valid[0] < 0.999f) {
          ++masked;
          continue;
        }
      }
      float rgba[4];
      sample(*cam.pyramid, rgba);
      double w = 1.0;
      if (options.weights == ViewWeights::Angle) w = cos_theta * std::min(1.0, footprint);
      if (texels) {
        float* out = texels->view_textures[c].At(int(index % side), int(index / side));
        out[0] = rgba[0];
        out[1] = rgba[1];
        out[2] = rgba[2];
        out[3] = float(w);
      }
      // Alpha holds |∇I| (StoreGradientInAlpha), the noise model's texture. The sample
      // averages max(1, footprint) level pixels of 4^level full-resolution ones each.
      samples[size_t(seen)] = {Eigen::Vector3d(rgba[0], rgba[1], rgba[2]), w, double(rgba[3]), int(c),
                               std::max(1.0, footprint) * std::ldexp(1.0, 2 * level)};
      ++seen;
    }

    if (texels) {
      texels->state[index] = TexelState::Exterior;
      texels->views[index] = uint8_t(seen);
    }
    if (seen < 2 && masked > 0) {
      ++out.masked;  // unknown, not unverifiable: neither compared nor charged
    } else if (seen == 0) {
      ++out.seen_none;
    } else if (seen == 1) {
      ++out.seen_once;
      out.unverified += samples[0].weight * options.model.outlier_chi2;
    } else {
      ++out.seen_multi;
      const TexelStatistic s = ReferenceTexelStatistic(
          std::vector<ViewSample>(samples.begin(), samples.begin() + seen), options.model, *photometric);
      out.sum_squares += s.chi2 * sigma2;
      out.dof += s.expected;
      out.views += uint32_t(seen);
      out.outlier_views += uint32_t(s.outliers);
      if (texels) texels->deviation[index] = s.chi2, texels->dof[index] = s.expected, texels->outliers[index] = uint8_t(s.outliers);
    }
  }
  return out;
}

std::string LookAtCameraJson(const std::string& name, const Eigen::Vector3d& eye,
                             const Eigen::Vector3d& target, int width, int height, double f,
                             double cx, double cy) {
  const Eigen::Vector3d z = (target - eye).normalized();  // forward
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);  // down
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  const Eigen::Vector3d t = -R * eye;
  char text[1024];
  std::snprintf(text, sizeof text,
                R"({"name": "%s", "image": "%s.png", "width": %d, "height": %d,)"
                R"( "K": [[%.17g, 0, %.17g], [0, %.17g, %.17g], [0, 0, 1]],)"
                R"( "R": [[%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g]],)"
                R"( "t": [%.17g, %.17g, %.17g]})",
                name.c_str(), name.c_str(), width, height, f, cx, f, cy, R(0, 0), R(0, 1), R(0, 2),
                R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2), t.x(), t.y(), t.z());
  return text;
}

SynthBoxScene MakeSynthBoxScene(vk::Device& device) {
  SynthBoxScene s;
  s.dir = std::make_unique<TempDir>();
  const std::string assets = VKRECON_SOURCE_DIR "/assets/box/";
  std::string cameras;
  for (int k = 0; k < 5; ++k) {
    const double a = (20.0 + 72.0 * k) * M_PI / 180.0;
    const Eigen::Vector3d eye(1.9 * std::cos(a), 1.9 * std::sin(a), 1.3 + 0.1 * k);
    cameras += (k ? ",\n    " : "") +
               LookAtCameraJson("cam" + std::to_string(k), eye, {0.1, -0.05, 0.25}, 160, 120, 150.0, 81.3, 58.7);
  }
  // The truth as initial values: the atlas layout follows the true box.
  const std::string scene = R"({
  "version": 1,
  "images": "images/",
  "parameters": {
    "x": {"prior": {"uniform": [-0.5, 0.5]}, "init": 0.12},
    "y": {"prior": {"uniform": [-0.5, 0.5]}, "init": -0.08},
    "yaw": {"prior": {"uniform": [-45, 45]}, "init": 17},
    "w": {"prior": {"uniform": [0.3, 1.5]}, "init": 0.8},
    "d": {"prior": {"uniform": [0.3, 1.5]}, "init": 0.6},
    "h": {"prior": {"uniform": [0.2, 1.0]}, "init": 0.5}
  },
  "nodes": [
    {"name": "ground", "primitive": "plane", "transforms": [{"scale": [4, 4, 1]}],
     "albedo": ")" + assets + R"(textures/ground.png"},
    {"name": "box", "primitive": "box", "albedo": ")" + assets + R"(textures/box.png",
     "transforms": [{"translate": ["x", "y", 0]}, {"rotate": [0, 0, "yaw"]}, {"scale": ["w", "d", "h"]}]}
  ],
  "cameras": [
    )" + cameras + R"(
  ]
})";
  s.scene_file = *s.dir / "scene.json";
  WriteText(s.scene_file, scene);
  SynthOptions synth;
  synth.scene_file = s.scene_file;
  synth.at_file = assets + "truth.json";
  synth.output_dir = *s.dir / "images";
  synth.atlas = 1024;  // the albedo's own resolution is lower; a bigger atlas only costs time
  SynthesiseImages(synth, device);
  s.scene = LoadScene(s.scene_file);
  s.truth = s.scene.ValuesFromFile(synth.at_file);
  return s;
}

std::vector<double> With(const Scene& scene, std::vector<double> psi, const std::string& name,
                         double value) {
  const int p = scene.ParameterIndex(name);
  if (p < 0) throw std::invalid_argument("With: no parameter " + name);
  psi[size_t(p)] = value;
  return psi;
}

}  // namespace vkr::test
