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

// A field that takes a word instead of a number: whether `j` is that word; another
// string fails naming what the field takes.
bool IsWord(const Reader& r, const Json& j, const std::string& path, const char* word, const char* number) {
  if (!j.is_string()) return false;
  if (j.get<std::string>() == word) return true;
  r.Fail(path, std::string("expected ") + number + " or \"" + word + "\", got '" + j.get<std::string>() + "'");
}

void ReadLikelihood(const Reader& r, const Json& j, LikelihoodSettings& s) {
  const std::string path = "likelihood";
  r.CheckObject(j, path, {"kind", "sigma", "weights", "atlas", "levels", "charts", "photometric", "clutter", "edges", "slot_images",
                         "partners", "partner_ranking", "sandwich_blocks", "sandwich_adjustment", "kappa",
                         "position_sd"});
  if (auto it = j.find("kind"); it != j.end()) {
    s.kind = r.String(*it, "likelihood.kind");
    if (s.kind != "surface" && s.kind != "image")
      r.Fail("likelihood.kind", "unknown kind '" + s.kind + "' (surface, image)");
  }
  if (auto it = j.find("sigma"); it != j.end()) {
    if (it->is_string() && it->get<std::string>() == "auto") {
      s.sigma_auto = true;
    } else {
      s.sigma_auto = false;
      s.sigma = r.Number(*it, "likelihood.sigma");
      if (!(s.sigma > 0)) r.Fail("likelihood.sigma", "sigma " + Num(s.sigma) + " must be > 0");
    }
  }
  if (auto it = j.find("weights"); it != j.end()) {
    s.weights = r.String(*it, "likelihood.weights");
    if (s.weights != "uniform" && s.weights != "angle")
      r.Fail("likelihood.weights", "unknown weights '" + s.weights + "' (uniform, angle)");
  }
  if (auto it = j.find("atlas"); it != j.end() && IsWord(r, *it, "likelihood.atlas", "auto", "a power of two")) {
    s.atlas = 0;
  } else if (it != j.end()) {
    s.atlas = int(r.Integer(*it, "likelihood.atlas", 64, 8192));
    if (s.atlas & (s.atlas - 1))
      r.Fail("likelihood.atlas", "atlas " + std::to_string(s.atlas) + " is not a power of two");
  }
  if (auto it = j.find("levels"); it != j.end() && IsWord(r, *it, "likelihood.levels", "auto", "an integer"))
    s.levels = 0;
  else if (it != j.end())
    s.levels = int(r.Integer(*it, "likelihood.levels", 1, 8));
  if (auto it = j.find("charts"); it != j.end()) {
    s.charts = r.String(*it, "likelihood.charts");
    if (s.charts != "area" && s.charts != "pixels")
      r.Fail("likelihood.charts", "unknown chart sizing '" + s.charts + "' (area, pixels)");
  }
  if (auto it = j.find("slot_images"); it != j.end()) {
    s.slot_images = r.String(*it, "likelihood.slot_images");
    if (s.slot_images != "auto" && s.slot_images != "shared" && s.slot_images != "per_slot")
      r.Fail("likelihood.slot_images", "unknown value '" + s.slot_images + "' (auto, shared, per_slot)");
  }
  if (auto it = j.find("photometric"); it != j.end()) {
    s.photometric = r.String(*it, "likelihood.photometric");
    if (s.photometric != "none" && s.photometric != "gain" && s.photometric != "affine")
      r.Fail("likelihood.photometric", "unknown photometric model '" + s.photometric + "' (none, gain, affine)");
  }
  if (auto it = j.find("clutter"); it != j.end()) {
    if (!it->is_boolean()) r.Fail("likelihood.clutter", "expected true or false");
    s.clutter = it->get<bool>();
  }
  if (auto it = j.find("edges"); it != j.end()) {
    if (!it->is_boolean()) r.Fail("likelihood.edges", "expected true or false");
    s.edges = it->get<bool>();
  }
  if (auto it = j.find("sandwich_blocks"); it != j.end() &&
                                             IsWord(r, *it, "likelihood.sandwich_blocks", "auto", "8, 16, 32 or 64")) {
    s.sandwich_blocks = 0;
  } else if (it != j.end()) {
    s.sandwich_blocks = int(r.Integer(*it, "likelihood.sandwich_blocks", 8, 64));
    if (s.sandwich_blocks & (s.sandwich_blocks - 1))
      r.Fail("likelihood.sandwich_blocks", "blocks of " + std::to_string(s.sandwich_blocks) +
                                               " texels: expected 8, 16, 32, 64 or \"auto\"");
  }
  if (auto it = j.find("sandwich_adjustment"); it != j.end()) {
    s.sandwich_adjustment = r.String(*it, "likelihood.sandwich_adjustment");
    if (s.sandwich_adjustment != "magnitude" && s.sandwich_adjustment != "curvature")
      r.Fail("likelihood.sandwich_adjustment",
             "unknown adjustment '" + s.sandwich_adjustment + "' (magnitude, curvature)");
  }
  if (auto it = j.find("kappa"); it != j.end() && it->is_string() &&
                                 (*it == "sandwich" || *it == "noise")) {
    s.kappa = 0.0;
    s.kappa_estimate = it->get<std::string>();
  } else if (it != j.end() && IsWord(r, *it, "likelihood.kappa", "auto", "a number, \"sandwich\", \"noise\"")) {
    s.kappa = 0.0;
    s.kappa_estimate = "auto";
  } else if (it != j.end()) {
    s.kappa_estimate = "auto";
    s.kappa = r.Number(*it, "likelihood.kappa");
    if (!(s.kappa > 0.0 && s.kappa < 1e9)) r.Fail("likelihood.kappa", "kappa " + Num(s.kappa) + " must be > 0 (or \"auto\", \"sandwich\", \"noise\")");
  }
  if (auto it = j.find("position_sd"); it != j.end()) {
    s.position_sd = r.Number(*it, "likelihood.position_sd");
    if (!(s.position_sd >= 0.0 && s.position_sd <= 10.0))
      r.Fail("likelihood.position_sd", "position_sd " + Num(s.position_sd) + " must be in [0, 10] pixels");
  }
  // Whether k exceeds the other cameras is checked where the cameras are known
  // (ImageLikelihoodOptions::FromScene).
  if (auto it = j.find("partners"); it != j.end()) s.partners = int(r.Integer(*it, "likelihood.partners", 0, INT_MAX));
  if (auto it = j.find("partner_ranking"); it != j.end()) {
    s.partner_ranking = r.String(*it, "likelihood.partner_ranking");
    if (s.partner_ranking != "distance" && s.partner_ranking != "direction")
      r.Fail("likelihood.partner_ranking", "unknown ranking '" + s.partner_ranking + "' (distance, direction)");
  }
  if (s.edges && s.kind == "image")
    r.Fail("likelihood.edges", "the image-space likelihood has no edge term (the surface likelihood has)");
}

void ReadSampler(const Reader& r, const Json& j, SamplerSettings& s) {
  if (!j.is_object()) r.Fail("sampler", "must be an object");
  // The four every command needs are read here; the sampler's other options (optimiser/
  // SamplerOptions.h) travel as text and are checked by `vkrecon run`, which knows them.
  Json rest = j;
  for (const char* key : {"iterations", "chains", "batch", "seed", "time_limit"}) rest.erase(key);
  s.options_json = rest.dump();
  if (auto it = j.find("iterations"); it != j.end() && IsWord(r, *it, "sampler.iterations", "auto", "an integer")) {
    s.iterations_auto = true;
  } else if (it != j.end()) {
    s.iterations_auto = false;
    s.iterations = int(r.Integer(*it, "sampler.iterations", 1, INT_MAX));
  }
  if (auto it = j.find("time_limit"); it != j.end() && IsWord(r, *it, "sampler.time_limit", "none", "seconds")) {
    s.time_limit = 0.0;
  } else if (it != j.end()) {
    s.time_limit = r.Number(*it, "sampler.time_limit");
    if (!(s.time_limit > 0.0 && s.time_limit < 1e9))
      r.Fail("sampler.time_limit", "time limit " + Num(s.time_limit) + " s must be > 0 (or \"none\")");
  }
  if (auto it = j.find("chains"); it != j.end())
    s.chains = int(r.Integer(*it, "sampler.chains", 1, INT_MAX));
  // A frame proposes chains × temperatures = batch hypotheses in one submission, each with
  // its own buffers: 4,096 already take minutes per frame on lavapipe and a second on a
  // large GPU; more can never be a useful ladder, only a run that looks hung.
  if (auto it = j.find("batch"); it != j.end())
    s.batch = int(r.Integer(*it, "sampler.batch", 1, kMaxSamplerBatch));
  if (auto it = j.find("seed"); it != j.end())
    s.seed = std::uint64_t(r.Integer(*it, "sampler.seed", 0, LLONG_MAX));
}

void ReadSynth(const Reader& r, const Json& j, SynthSettings& s) {
  r.CheckObject(j, "synth", {"sun", "ambient", "exposure", "supersample"});
  if (auto it = j.find("sun"); it != j.end()) {
    if (!it->is_array() || it->size() != 2) r.Fail("synth.sun", "expected [azimuth, elevation] in degrees");
    s.sun = true;
    s.sun_azimuth = r.Number((*it)[0], "synth.sun[0]");
    s.sun_elevation = r.Number((*it)[1], "synth.sun[1]");
    if (!(s.sun_elevation > 0 && s.sun_elevation <= 90))
      r.Fail("synth.sun[1]", "elevation " + Num(s.sun_elevation) + " must be in (0, 90] degrees");
  }
  if (auto it = j.find("ambient"); it != j.end()) {
    s.ambient = r.Number(*it, "synth.ambient");
    if (!(s.ambient >= 0 && s.ambient <= 1)) r.Fail("synth.ambient", "ambient " + Num(s.ambient) + " must be in [0, 1]");
  }
  if (auto it = j.find("exposure"); it != j.end()) {
    s.exposure = r.Number(*it, "synth.exposure");
    if (!(s.exposure >= 0 && s.exposure < 1)) r.Fail("synth.exposure", "exposure spread " + Num(s.exposure) + " must be in [0, 1)");
  }
  if (auto it = j.find("supersample"); it != j.end())
    s.supersample = int(r.Integer(*it, "synth.supersample", 1, 8));
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

  if (auto it = root.find("likelihood"); it != root.end())
    ReadLikelihood(r, *it, scene.likelihood);
  if (auto it = root.find("sampler"); it != root.end()) ReadSampler(r, *it, scene.sampler);
  if (auto it = root.find("synth"); it != root.end()) ReadSynth(r, *it, scene.synth);
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
