// LoadScene: the scene file contract of docs/guide/SCENE_FORMAT.md. The
// order matters: overrides first (they are part of the input), then parameters (the
// expressions of nodes and cameras need their names), then everything that may hold an
// expression, and last the checks that need the whole scene (unused parameters, values at
// the initial Ψ).

#include <climits>
#include <cmath>
#include <map>

#include "engine/common/InputError.h"
#include "engine/scene/Expression.h"
#include "engine/scene/Photographs.h"
#include "engine/scene/SceneJson.h"

namespace vkr {
namespace scene_detail {
namespace {

// [lo, hi] with lo < hi, as for priors and bounds.
std::pair<double, double> ReadInterval(const Reader& r, const Json& j, const std::string& path,
                                       const char* what) {
  if (!j.is_array() || j.size() != 2) r.Fail(path, std::string("expected ") + what);
  return {r.Number(j[0], Index(path, 0)), r.Number(j[1], Index(path, 1))};
}

Parameter ReadParameter(const Reader& r, const std::string& name, const Json& j) {
  const std::string path = Join("parameters", name);
  r.CheckObject(j, path, {"prior", "bounds", "init"});
  Parameter p;
  p.name = name;
  const Json& prior = r.Require(j, path, "prior");
  const std::string prior_path = Join(path, "prior");
  if (!prior.is_object() || prior.size() != 1)
    r.Fail(prior_path, "expected {\"uniform\": [lo, hi]} or {\"normal\": [mean, sd]}");
  const std::string kind = prior.begin().key();
  const std::string value_path = Join(prior_path, kind);
  if (kind == "uniform") {
    const auto [lo, hi] = ReadInterval(r, prior.begin().value(), value_path, "[lo, hi]");
    if (!(lo < hi)) r.Fail(value_path, "lo " + Num(lo) + " must be below hi " + Num(hi));
    p.prior = {Prior::Kind::Uniform, lo, hi};
  } else if (kind == "normal") {
    const auto [mean, sd] = ReadInterval(r, prior.begin().value(), value_path, "[mean, sd]");
    if (!(sd > 0)) r.Fail(value_path, "sd " + Num(sd) + " must be > 0");
    p.prior = {Prior::Kind::Normal, mean, sd};
  } else {
    r.Fail(Join(prior_path, kind), "unknown prior '" + kind + "' (uniform, normal)");
  }
  if (const auto it = j.find("bounds"); it != j.end()) {
    const std::string bounds_path = Join(path, "bounds");
    const auto [lo, hi] = ReadInterval(r, *it, bounds_path, "[lo, hi]");
    if (!(lo < hi)) r.Fail(bounds_path, "lo " + Num(lo) + " must be below hi " + Num(hi));
    p.bounds = std::make_pair(lo, hi);
    if (p.prior.kind == Prior::Kind::Uniform && (hi < p.prior.a || lo > p.prior.b))
      r.Fail(bounds_path, "bounds [" + Num(lo) + ", " + Num(hi) +
                              "] do not overlap the uniform prior [" + Num(p.prior.a) + ", " +
                              Num(p.prior.b) + "]");
  }
  if (const auto it = j.find("init"); it != j.end()) {
    p.init = r.Number(*it, Join(path, "init"));
    if (!p.Admissible(*p.init))
      r.Fail(Join(path, "init"), "init " + Num(*p.init) + " lies outside the prior or bounds");
  }
  return p;
}

PrimitiveKind ReadPrimitive(const Reader& r, const Json& j, const std::string& path, Node& node) {
  if (j.is_object()) {
    r.CheckObject(j, path, {"mesh"});
    node.mesh = r.ExistingFile(r.Require(j, path, "mesh"), Join(path, "mesh"), "mesh file");
    return PrimitiveKind::Mesh;
  }
  const std::string name = r.String(j, path);
  for (PrimitiveKind k : {PrimitiveKind::Plane, PrimitiveKind::Box, PrimitiveKind::Prism,
                          PrimitiveKind::Cylinder})
    if (name == ToString(k)) return k;
  if (name == "mesh") r.Fail(path, "a mesh names its file: {\"mesh\": \"file.glb\"}");
  r.Fail(path, "unknown primitive '" + name +
                   "' (plane, box, prism, cylinder, {\"mesh\": \"file.glb\"})");
}

// Parents are referenced by name and must be listed first, so node indices stay the file's
// order (what error messages, `--dump` and the GPU node buffer show) and WorldFromNode
// needs a single pass. A forward reference is therefore either a cycle or a misordering,
// and the message says which.
void ReadNodes(const Reader& r, const Json& j, std::vector<Node>& nodes) {
  if (!j.is_array()) r.Fail("nodes", "expected a list of nodes");
  std::map<std::string, int> index;
  std::vector<std::string> parent_name(j.size());
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string path = Index("nodes", i);
    r.CheckObject(j[i], path, {"name", "parent", "primitive", "transforms", "albedo"});
    const std::string name = r.String(r.Require(j[i], path, "name"), Join(path, "name"));
    if (name.empty()) r.Fail(Join(path, "name"), "empty node name");
    if (!index.emplace(name, int(i)).second)
      r.Fail(Join(path, "name"), "node name '" + name + "' is used twice");
    if (auto it = j[i].find("parent"); it != j[i].end())
      parent_name[i] = r.String(*it, Join(path, "parent"));
  }
  // parent index per node (-1: none); unknown names first, then cycles, then order.
  std::vector<int> parent(j.size(), -1);
  for (size_t i = 0; i < j.size(); ++i) {
    if (!j[i].contains("parent")) continue;
    const auto it = index.find(parent_name[i]);
    if (it == index.end())
      r.Fail(Join(Index("nodes", i), "parent"), "unknown parent '" + parent_name[i] + "'");
    parent[i] = it->second;
  }
  for (size_t i = 0; i < j.size(); ++i) {
    std::string chain = j[i]["name"].get<std::string>();
    int k = parent[i];
    for (size_t steps = 0; k >= 0 && steps < j.size(); ++steps, k = parent[size_t(k)]) {
      chain += " -> " + j[size_t(k)]["name"].get<std::string>();
      if (k == int(i)) r.Fail(Join(Index("nodes", i), "parent"), "cyclic parents: " + chain);
    }
  }
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string path = Index("nodes", i);
    const Json& jn = j[i];
    Node node;
    node.name = jn["name"].get<std::string>();
    if (parent[i] >= int(i))
      r.Fail(Join(path, "parent"), "parent '" + parent_name[i] +
                                       "' is listed after this node; list parents first");
    node.parent = parent[i];
    if (auto it = jn.find("primitive"); it != jn.end())
      node.primitive = ReadPrimitive(r, *it, Join(path, "primitive"), node);
    if (auto it = jn.find("transforms"); it != jn.end())
      node.transforms = r.Transforms(*it, Join(path, "transforms"), /*allow_scale=*/true);
    if (auto it = jn.find("albedo"); it != jn.end())
      node.albedo = r.ExistingFile(*it, Join(path, "albedo"), "albedo image");
    nodes.push_back(std::move(node));
  }
}

// Checks that need the whole scene: every parameter is used (docs/guide/SCENE_FORMAT.md,
// "parameters": one declared but used nowhere is an error), and every expression is finite at the
// initial values.
void CheckScene(const Scene& scene, const std::string& display) {
  const ExpressionTable& table = scene.expressions();
  for (size_t p = 0; p < scene.parameters.size(); ++p)
    if (!table.IsUsed(int(p)))
      throw InputError(display, Join("parameters", scene.parameters[p].name),
                       "declared but used nowhere (in no node transform, camera K or pose)");
  const std::vector<double> init = scene.InitialValues();
  for (int id = 0; id < table.size(); ++id) {
    const double v = table.Evaluate(id, init);
    if (!std::isfinite(v))
      throw InputError(table.File(id), table.Field(id),
                       "expression \"" + table.Text(id) + "\" is not finite at the initial "
                       "parameter values (" + Num(v) + ")");
  }
  for (size_t c = 0; c < scene.cameras.size(); ++c) {
    const CameraModel& cam = scene.cameras[c];
    const double fx = scene.Evaluate(cam.K[0], init), fy = scene.Evaluate(cam.K[4], init);
    if (!(fx > 0) || !(fy > 0))
      throw InputError(display, Index("cameras", c) + ".K",
                       "focal lengths must be > 0 (fx " + Num(fx) + ", fy " + Num(fy) +
                           " at the initial values)");
  }
}

}  // namespace
}  // namespace scene_detail

Scene LoadScene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides,
                const LoadOptions& options) {
  using namespace scene_detail;
  const std::string display = file.string();
  Json root = ParseJsonFile(file, display);
  const std::set<std::string> overridden = ApplyOverrides(root, overrides, display);

  Scene scene;
  scene.file = std::filesystem::absolute(file).lexically_normal();
  scene.overrides = overrides;
  Reader r;
  r.file = display;
  r.dir = scene.file.parent_path();
  r.overridden = &overridden;
  r.CheckObject(root, "", {"version", "images", "max_side", "cameras", "masks", "parameters", "nodes",
                           "likelihood", "sampler", "synth"});

  const long long version = r.Integer(r.Require(root, "", "version"), "version", 0, LLONG_MAX);
  if (version != 1)
    r.Fail("version", "unsupported version " + std::to_string(version) + " (this vkrecon reads 1)");
  scene.images_dir = r.dir;
  if (auto it = root.find("images"); it != root.end())
    scene.images_dir = (r.dir / r.String(*it, "images")).lexically_normal();
  if (!scene.images_dir.has_filename()) scene.images_dir = scene.images_dir.parent_path();

  std::vector<std::string> names;
  if (auto it = root.find("parameters"); it != root.end()) {
    if (!it->is_object()) r.Fail("parameters", "expected an object {\"name\": {…}, …}");
    for (const auto& [name, value] : it->items()) {
      scene.parameters.push_back(ReadParameter(r, name, value));
      names.push_back(name);
    }
  }
  auto table = std::make_unique<ExpressionTable>(names, display);
  r.table = table.get();
  SceneAccess::SetExpressions(scene, std::move(table));

  // The settings blocks are read by the layers they belong to (SettingsReader.h).
  for (const char* block : {"likelihood", "sampler", "synth"}) {
    const auto it = root.find(block);
    if (it == root.end()) continue;
    if (!it->is_object()) r.Fail(block, "expected an object");
    scene.settings[block] = it->dump();
  }
  if (auto it = root.find("nodes"); it != root.end()) ReadNodes(r, *it, scene.nodes);
  if (auto it = root.find("cameras"); it != root.end())
    ReadCameras(*it, r, options.require_images, scene);
  const auto masks = root.find("masks");
  ResolveMasks(masks == root.end() ? nullptr : &*masks, r, options.require_images, scene);
  // After the checks of every photograph's and mask's own size: the shrunk size is derived.
  if (auto it = root.find("max_side"); it != root.end()) {
    scene.max_side = int(r.Integer(*it, "max_side", 16, 1 << 16));
    for (CameraModel& cam : scene.cameras) {
      cam.shrink = ShrinkFactor(cam.width, cam.height, scene.max_side);
      cam.width /= cam.shrink;
      cam.height /= cam.shrink;
    }
  }
  CheckScene(scene, display);
  return scene;
}

}  // namespace vkr
