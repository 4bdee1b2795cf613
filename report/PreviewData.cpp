#include "report/PreviewData.h"

#include <algorithm>

#include "engine/scene/Expression.h"
#include "pipelines/rendering/WireframeOverlay.h"
#include "report/Preview.h"

namespace vkr::report {
namespace {

using Json = nlohmann::ordered_json;

// A camera's check points: this many of the scene's vertices in front of it.
constexpr size_t kCheckPoints = 8;

Json ScalarJson(const Scalar& s) {
  if (s.IsConstant()) return s.constant;
  return Json{{"expr", s.expression}};
}

const char* KindName(Transform::Kind kind) {
  switch (kind) {
    case Transform::Kind::Translate: return "translate";
    case Transform::Kind::Rotate: return "rotate";
    case Transform::Kind::Scale: return "scale";
  }
  return "?";
}

Json ChainJson(const std::vector<Transform>& chain) {
  Json out = Json::array();
  for (const Transform& t : chain)
    out.push_back({{"kind", KindName(t.kind)},
                   {"value", {ScalarJson(t.value[0]), ScalarJson(t.value[1]), ScalarJson(t.value[2])}}});
  return out;
}

Json ParametersJson(const Scene& scene, const std::vector<double>& psi) {
  Json out = Json::array();
  for (size_t i = 0; i < scene.parameters.size(); ++i) {
    const Parameter& p = scene.parameters[i];
    const auto [lo, hi] = SliderRange(p);
    out.push_back({{"name", p.name},
                   {"prior", {{"kind", p.prior.kind == Prior::Kind::Uniform ? "uniform" : "normal"},
                              {"a", p.prior.a}, {"b", p.prior.b}}},
                   {"lo", lo}, {"hi", hi}, {"value", psi[i]}});
  }
  return out;
}

Json ExpressionsJson(const Scene& scene, const std::vector<double>& psi) {
  Json out = Json::array();
  const ExpressionTable& table = scene.expressions();
  for (int id = 0; id < table.size(); ++id)
    out.push_back({{"text", table.Text(id)}, {"field", table.Field(id)}, {"value", table.Evaluate(id, psi)}});
  return out;
}

Json NodeJson(const Node& node, const NodeWire& wire) {
  Json vertices = Json::array(), triangles = Json::array(), edges = Json::array();
  for (const Eigen::Vector3d& v : wire.vertices) vertices.push_back({v.x(), v.y(), v.z()});
  for (const auto& t : wire.triangles) triangles.push_back({t[0], t[1], t[2]});
  for (const NodeWire::Edge& e : wire.edges) edges.push_back({{"a", e.a}, {"b", e.b}, {"triangles", e.triangles}});
  return {{"name", node.name}, {"parent", node.parent}, {"transforms", ChainJson(node.transforms)},
          {"vertices", std::move(vertices)}, {"triangles", std::move(triangles)}, {"edges", std::move(edges)}};
}

// Up to kCheckPoints vertices in front of `camera` at Ψ, spread over the scene's vertices,
// each as [node, vertex, u, v] with the C++ pixel (LensPixel) the page must reproduce.
Json CheckPoints(const Camera& camera, const std::vector<NodeWire>& wires, const std::vector<Eigen::Matrix4d>& world_from_node) {
  std::vector<std::pair<size_t, size_t>> candidates;
  for (size_t n = 0; n < wires.size(); ++n)
    for (size_t v = 0; v < wires[n].vertices.size(); ++v) candidates.emplace_back(n, v);
  Json out = Json::array();
  const size_t stride = std::max<size_t>(1, candidates.size() / kCheckPoints);
  for (size_t i = 0; i < candidates.size() && out.size() < kCheckPoints; i += stride) {
    const auto [n, v] = candidates[i];
    const Eigen::Vector4d world = world_from_node[n] * wires[n].vertices[v].homogeneous();
    const Eigen::Vector3d x_cam = (camera.cam_from_world * world).head<3>();
    if (x_cam.z() < 1e-3) continue;
    const Eigen::Vector2d pixel = LensPixel(camera, x_cam);
    if (pixel.allFinite()) out.push_back({n, v, pixel.x(), pixel.y()});
  }
  return out;
}

Json CameraJson(const CameraModel& model, const Camera& camera, const std::vector<NodeWire>& wires,
                const std::vector<Eigen::Matrix4d>& world_from_node) {
  Json K = Json::array(), R = Json::array();
  for (const Scalar& k : model.K) K.push_back(ScalarJson(k));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R.push_back(model.R(r, c));
  Json lens = nullptr;
  if (!model.distortion.IsNone()) lens = model.distortion.FullOpenCV();
  return {{"name", model.name}, {"width", model.width}, {"height", model.height}, {"K", std::move(K)},
          {"shrink", model.shrink}, {"R", std::move(R)}, {"t", {model.t.x(), model.t.y(), model.t.z()}}, {"pose", ChainJson(model.pose)},
          {"lens", std::move(lens)}, {"check", CheckPoints(camera, wires, world_from_node)}};
}

}  // namespace

nlohmann::ordered_json PreviewData(const Scene& scene, const std::vector<Mesh>& meshes, const std::vector<double>& psi) {
  std::vector<NodeWire> wires;
  for (size_t n = 0; n < scene.nodes.size(); ++n) wires.push_back(n < meshes.size() ? WeldWire(meshes[n]) : NodeWire{});
  Json nodes = Json::array();
  for (size_t n = 0; n < scene.nodes.size(); ++n) nodes.push_back(NodeJson(scene.nodes[n], wires[n]));
  const std::vector<Eigen::Matrix4d> world_from_node = scene.WorldFromNode(psi);
  const std::vector<Camera> cameras = scene.Cameras(psi);
  Json camera_json = Json::array();
  for (size_t c = 0; c < cameras.size(); ++c)
    camera_json.push_back(CameraJson(scene.cameras[c], cameras[c], wires, world_from_node));
  return {{"parameters", ParametersJson(scene, psi)},
          {"expressions", ExpressionsJson(scene, psi)},
          {"nodes", std::move(nodes)},
          {"cameras", std::move(camera_json)},
          {"crease_degrees", WireframeOptions{}.crease_degrees}};
}

}  // namespace vkr::report
