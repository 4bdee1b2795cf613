// The scene at a hypothesis Ψ: priors, node matrices and cameras (docs/guide/SCENE_FORMAT.md).
// WorldFromNode and Cameras run once per hypothesis, so transform chains are applied in
// place to one 4×4 matrix instead of building and multiplying a matrix per component.

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "engine/scene/Expression.h"
#include "engine/scene/Scene.h"
#include "engine/scene/SceneJson.h"

namespace vkr {

// --- priors and parameters ---------------------------------------------------------------

double Prior::LogDensity(double x) const {
  if (kind == Kind::Uniform)
    return (x >= a && x <= b) ? -std::log(b - a) : -std::numeric_limits<double>::infinity();
  const double z = (x - a) / b;
  return -0.5 * z * z - std::log(b * std::sqrt(2.0 * std::numbers::pi));
}

double Prior::Width() const { return kind == Kind::Uniform ? b - a : 4.0 * b; }

double Prior::Centre() const { return kind == Kind::Uniform ? 0.5 * (a + b) : a; }

double Parameter::Initial() const {
  if (init) return *init;
  double x = prior.Centre();
  if (bounds) x = std::clamp(x, bounds->first, bounds->second);
  // A uniform prior that only partly overlaps the bounds: start inside both.
  if (prior.kind == Prior::Kind::Uniform) x = std::clamp(x, prior.a, prior.b);
  return x;
}

bool Parameter::Admissible(double x) const {
  if (!std::isfinite(x)) return false;
  if (prior.kind == Prior::Kind::Uniform && (x < prior.a || x > prior.b)) return false;
  if (bounds && (x < bounds->first || x > bounds->second)) return false;
  return true;
}

const char* ToString(PrimitiveKind kind) {
  switch (kind) {
    case PrimitiveKind::None: return "none";
    case PrimitiveKind::Plane: return "plane";
    case PrimitiveKind::Box: return "box";
    case PrimitiveKind::Prism: return "prism";
    case PrimitiveKind::Cylinder: return "cylinder";
    case PrimitiveKind::Mesh: return "mesh";
  }
  return "unknown";
}

// --- transforms ----------------------------------------------------------------------------

namespace {

// Rotation of `rotate [rx, ry, rz]` (degrees): R = Rz(rz)·Ry(ry)·Rx(rx), i.e. x first.
Eigen::Matrix3d RotationZYX(double rx, double ry, double rz) {
  constexpr double kRad = std::numbers::pi / 180.0;
  return (Eigen::AngleAxisd(rz * kRad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(ry * kRad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx * kRad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// m ← m · T1 · T2 · …, each component applied to m's columns directly.
void ApplyTransforms(const Scene& scene, const std::vector<Transform>& chain,
                     const std::vector<double>& psi, Eigen::Matrix4d& m) {
  for (const Transform& t : chain) {
    const Eigen::Vector3d v(scene.Evaluate(t.value[0], psi), scene.Evaluate(t.value[1], psi),
                            scene.Evaluate(t.value[2], psi));
    switch (t.kind) {
      case Transform::Kind::Translate:
        m.col(3) += m.leftCols<3>() * v;
        break;
      case Transform::Kind::Rotate:
        m.leftCols<3>() = (m.leftCols<3>() * RotationZYX(v.x(), v.y(), v.z())).eval();
        break;
      case Transform::Kind::Scale:
        for (int k = 0; k < 3; ++k) m.col(k) *= v[k];
        break;
    }
  }
}

void CheckSize(const Scene& scene, const std::vector<double>& psi) {
  if (psi.size() != scene.parameters.size())
    throw std::invalid_argument("Ψ has " + std::to_string(psi.size()) + " values, the scene " +
                                std::to_string(scene.parameters.size()) + " parameters");
}

}  // namespace

Eigen::Matrix4d ComposeTransforms(const Scene& scene, const std::vector<Transform>& chain,
                                  const std::vector<double>& psi) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  ApplyTransforms(scene, chain, psi, m);
  return m;
}

// --- scene -------------------------------------------------------------------------------

Scene::Scene() : expressions_(std::make_unique<ExpressionTable>(std::vector<std::string>{}, "")) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

void scene_detail::SceneAccess::SetExpressions(Scene& scene,
                                               std::unique_ptr<ExpressionTable> table) {
  scene.expressions_ = std::move(table);
}

int Scene::ParameterIndex(const std::string& name) const {
  for (size_t i = 0; i < parameters.size(); ++i)
    if (parameters[i].name == name) return int(i);
  return -1;
}

std::vector<double> Scene::InitialValues() const {
  std::vector<double> psi;
  psi.reserve(parameters.size());
  for (const Parameter& p : parameters) psi.push_back(p.Initial());
  return psi;
}

double Scene::Evaluate(const Scalar& s, const std::vector<double>& psi) const {
  return s.IsConstant() ? s.constant : expressions_->Evaluate(s.expression, psi);
}

std::vector<Eigen::Matrix4d> Scene::WorldFromNode(const std::vector<double>& psi) const {
  CheckSize(*this, psi);
  std::vector<Eigen::Matrix4d> world(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const int parent = nodes[i].parent;
    if (parent >= int(i)) throw std::logic_error("Scene: a node's parent must precede it");
    // world = parent_world · T1 · T2 · … (docs/guide/SCENE_FORMAT.md, "nodes").
    world[i] = parent >= 0 ? world[size_t(parent)] : Eigen::Matrix4d::Identity();
    ApplyTransforms(*this, nodes[i].transforms, psi, world[i]);
  }
  return world;
}

std::vector<Camera> Scene::Cameras(const std::vector<double>& psi) const {
  CheckSize(*this, psi);
  std::vector<Camera> result(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) {
    const CameraModel& model = cameras[c];
    Camera& cam = result[c];
    cam.name = model.name;
    cam.image = model.image;
    cam.width = model.width;
    cam.height = model.height;
    cam.distortion = model.distortion;
    cam.shrink = model.shrink;
    for (int k = 0; k < 9; ++k) cam.K(k / 3, k % 3) = Evaluate(model.K[k], psi);
    // The shrunk pixel (i, j) covers the file's shrink·i … shrink·(i+1) − 1: S·K, as a pyramid level.
    cam.K.topRows<2>() /= double(model.shrink);
    cam.cam_from_world.setIdentity();
    cam.cam_from_world.topLeftCorner<3, 3>() = model.R;
    cam.cam_from_world.topRightCorner<3, 1>() = model.t;
    if (!model.pose.empty()) {
      // world_from_cam' = P · world_from_cam, so cam'_from_world = cam_from_world · P⁻¹.
      // (P is rigid: the loader refuses scale in a pose, so R stays a rotation.)
      const Eigen::Matrix4d pose = ComposeTransforms(*this, model.pose, psi);
      cam.cam_from_world = (cam.cam_from_world * pose.inverse()).eval();
    }
  }
  return result;
}

Eigen::Vector2d Camera::Project(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d x = K * (R() * world + t());
  return x.head<2>() / x.z();
}

Eigen::Matrix4d CamFromWorldLookingAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  // OpenCV axes: z forward, x right, y down.
  const Eigen::Vector3d z = (target - eye).normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d r;
  r.row(0) = x;
  r.row(1) = y;
  r.row(2) = z;
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = -r * eye;
  return m;
}

}  // namespace vkr
