#include "recon/SceneInit.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <locale>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"
#include "engine/scene/CameraWriter.h"
#include "engine/scene/Colmap.h"
#include "recon/AtomicWrite.h"
#include "recon/GroundPlane.h"
#include "recon/StarterScene.h"

namespace vkr::recon {
namespace {

namespace fs = std::filesystem;
using Vec3 = Eigen::Vector3d;

// The fewest points above the ground a template is fitted to.
constexpr size_t kMinAbove = 20;
// Fewer ground inliers than this fix its tilt poorly: init warns.
constexpr int kFewGroundInliers = 50;

double Percentile(std::vector<double> v, double q) {
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

std::string Shown(const fs::path& p) { return p.lexically_normal().string(); }

ColmapReconstruction ReadModel(const InitOptions& o) {
  if (!fs::is_directory(o.sparse))
    throw InputError(Shown(o.sparse), "", "not a folder (a COLMAP sparse model: cameras, images, points3D)");
  ColmapReconstruction model = ReadColmapModel(o.sparse, Shown(o.sparse));
  if (model.images.size() < 2)
    throw InputError(Shown(o.sparse), "", "the model has " + std::to_string(model.images.size()) +
                                              " registered image(s); init needs at least two");
  if (model.points.size() < kMinAbove)
    throw InputError(Shown(o.sparse), "points3D", "the model has " + std::to_string(model.points.size()) +
                                                      " points; init needs at least " + std::to_string(kMinAbove) +
                                                      " to find the ground");
  return model;
}

// --images, else the folder beside SPARSE (project/sparse) or beside its parent
// (project/sparse/0, what `colmap mapper` writes).
fs::path ImagesFolder(const InitOptions& o) {
  if (!o.images.empty()) return fs::absolute(o.images).lexically_normal();
  fs::path sparse = fs::absolute(o.sparse).lexically_normal();
  if (sparse.filename().empty()) sparse = sparse.parent_path();
  const fs::path beside = sparse.parent_path() / "images";
  if (fs::is_directory(beside) || sparse.parent_path().filename() != "sparse") return beside;
  return sparse.parent_path().parent_path() / "images";
}

void CheckPhotographs(const ColmapReconstruction& model, const fs::path& images) {
  for (const ColmapImage& im : model.images) {
    const fs::path file = images / im.image;
    if (!fs::is_regular_file(file))
      throw InputError(Shown(file), "", "photograph missing (the model's image " + im.image + "; --images names the folder)");
    int w = 0, h = 0;
    ReadImageSize(file, &w, &h);
    if (w != im.width || h != im.height)
      throw InputError(Shown(file), "", "photograph is " + std::to_string(w) + "x" + std::to_string(h) +
                                            ", its COLMAP camera " + std::to_string(im.width) + "x" +
                                            std::to_string(im.height));
  }
}

// The sum of the cameras' up directions: COLMAP's image y points down, so up is -R^T·(0,1,0).
Vec3 CamerasUp(const ColmapReconstruction& model) {
  Vec3 sum = Vec3::Zero();
  for (const ColmapImage& im : model.images) sum -= im.R.row(1).transpose();
  return sum;
}

Vec3 UpHint(const InitOptions& o, const ColmapReconstruction& model) {
  if (o.up) {
    if (!(o.up->norm() > 0.0) || !o.up->allFinite()) throw InputError("", "--up", "needs a non-zero direction");
    return o.up->normalized();
  }
  const Vec3 sum = CamerasUp(model);
  if (sum.norm() < 0.2 * double(model.images.size()))
    throw InputError(Shown(o.sparse), "", "the cameras' up directions disagree, so the ground's side is unknown: give --up X,Y,Z");
  return sum.normalized();
}

// The cloud's size: the median distance of the points from their coordinate-wise median.
double CloudSize(const std::vector<Vec3>& points) {
  Vec3 median;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> c;
    for (const Vec3& x : points) c.push_back(x[k]);
    median[k] = Percentile(c, 0.5);
  }
  std::vector<double> d;
  for (const Vec3& x : points) d.push_back((x - median).norm());
  return Percentile(d, 0.5);
}

// The point nearest to the cameras' optical axes (least squares), or none when the axes are
// near parallel: what the photographs are of.
std::optional<Vec3> LookedAt(const ColmapReconstruction& model) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Vec3 b = Vec3::Zero();
  for (const ColmapImage& im : model.images) {
    const Vec3 axis = im.R.row(2).transpose(), centre = -im.R.transpose() * im.t;
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - axis * axis.transpose();
    A += across, b += across * centre;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  if (!(eig.eigenvalues()(0) > 0.05 * eig.eigenvalues()(2))) return std::nullopt;
  return A.ldlt().solve(b);
}

// The points above the ground that belong to the object: within 0.6 of the cameras' median
// distance (along the ground) of the point they look at, so that a building or trees behind it
// do not set its priors. All of them when the cameras look at no one point.
std::vector<Vec3> NearTheObject(std::vector<Vec3> above, const ColmapReconstruction& model, const Vec3& normal) {
  const std::optional<Vec3> at = LookedAt(model);
  if (!at) return above;
  const auto along_ground = [&](const Vec3& x) {
    const Vec3 d = x - *at;
    return (d - normal.dot(d) * normal).norm();
  };
  std::vector<double> distance;
  for (const ColmapImage& im : model.images) distance.push_back(along_ground(-im.R.transpose() * im.t));
  const double reach = 0.6 * Percentile(distance, 0.5);
  std::erase_if(above, [&](const Vec3& x) { return along_ground(x) > reach; });
  return above;
}

// Without the isolated points: those whose mean distance to their 6 nearest neighbours is over
// 3 times the median's. A sparse model holds stray triangulations (the sky, a mismatch) that
// would stretch the percentiles the priors come from; the object's surfaces are dense.
// Neighbours are sought among at most 4,000 evenly picked points, so large models stay fast.
std::vector<Vec3> DropIsolated(std::vector<Vec3> points) {
  constexpr int kNeighbours = 6;
  if (points.size() <= size_t(2 * kNeighbours)) return points;
  const size_t stride = (points.size() + 3999) / 4000;
  std::vector<double> spacing;
  for (const Vec3& x : points) {
    std::vector<double> d;
    for (size_t j = 0; j < points.size(); j += stride) d.push_back((points[j] - x).norm());
    std::partial_sort(d.begin(), d.begin() + kNeighbours + 1, d.end());
    double sum = 0.0;
    for (int k = 1; k <= kNeighbours; ++k) sum += d[size_t(k)];  // d[0]: itself, or its nearest
    spacing.push_back(sum / kNeighbours);
  }
  const double limit = 3.0 * Percentile(spacing, 0.5);
  std::vector<Vec3> kept;
  for (size_t i = 0; i < points.size(); ++i)
    if (spacing[i] <= limit) kept.push_back(points[i]);
  return kept;
}

}  // namespace

namespace {

// X_scene = scale · R · (X_model − origin): the rows of R are the scene's x, y and z (the
// ground's normal) in the model's frame; the origin lies on the ground.
struct SceneFrame {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Vec3 origin = Vec3::Zero();
  double scale = 1.0;
  Vec3 Apply(const Vec3& x) const { return scale * (R * (x - origin)); }
  Eigen::Matrix4d Matrix() const {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.topLeftCorner<3, 3>() = scale * R;
    m.topRightCorner<3, 1>() = -scale * (R * origin);
    return m;
  }
};

// The frame on `ground` under the median of the footprint of `above`, +x along the footprint's
// principal axis (of the points within three median radii, so that stray points far out do not
// turn it), signed so that it points along the ground's first basis vector.
SceneFrame FrameOnGround(const GroundPlane& ground, const std::vector<Vec3>& above) {
  const Vec3 n = ground.normal, e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::vector<double> u, v, r;
  for (const Vec3& x : above) u.push_back(e1.dot(x)), v.push_back(e2.dot(x));
  const double cu = Percentile(u, 0.5), cv = Percentile(v, 0.5);
  for (size_t i = 0; i < u.size(); ++i) r.push_back(std::hypot(u[i] - cu, v[i] - cv));
  const double reach = 3.0 * Percentile(r, 0.5);
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (size_t i = 0; i < u.size(); ++i)
    if (r[i] <= reach) {
      const Eigen::Vector2d d(u[i] - cu, v[i] - cv);
      scatter += d * d.transpose();
    }
  Eigen::Vector2d axis = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(1);
  if (axis.x() < 0.0) axis = -axis;
  const Vec3 x_axis = axis.x() * e1 + axis.y() * e2;
  SceneFrame f;
  f.R.row(0) = x_axis.transpose();
  f.R.row(1) = n.cross(x_axis).transpose();
  f.R.row(2) = n.transpose();
  f.origin = ground.offset * n + cu * e1 + cv * e2;
  return f;
}

double ScaleFrom(const InitOptions& o, const ColmapReconstruction& model) {
  if (!o.scale) return 1.0;
  const auto find = [&](std::uint64_t id) {
    for (const ColmapPoint& p : model.points)
      if (p.id == id) return p.xyz;
    throw InputError("", "--scale-points", "point " + std::to_string(id) + " is not in the model's points3D");
  };
  const Vec3 a = find(o.scale->a), b = find(o.scale->b);  // in this order: the error names the first missing
  const double distance = (a - b).norm();
  if (!(distance > 0.0) || !(o.scale->length > 0.0))
    throw InputError("", "--scale-points", "needs two distinct points and a positive length");
  return o.scale->length / distance;
}

std::string NoGround(const InitOptions& o, const GroundPlaneOptions& g) {
  return "no ground found: no plane within " + std::to_string(int(g.max_tilt_deg)) + "° of " +
         (o.up ? "--up" : "the cameras' up") + " holds " + std::to_string(int(100 * g.min_inlier_share)) +
         "% of the points with at most " + std::to_string(int(100 * g.max_below)) +
         "% below it (give --up, or photograph more of the ground)";
}

// The robust box (2nd–98th percentiles) of `points`.
void RobustBox(const std::vector<Vec3>& points, Vec3& lo, Vec3& hi) {
  for (int k = 0; k < 3; ++k) {
    std::vector<double> c;
    for (const Vec3& x : points) c.push_back(x[k]);
    lo[k] = Percentile(c, 0.02);
    hi[k] = Percentile(c, 0.98);
  }
}

}  // namespace

namespace {

// The cameras in the scene frame: x_cam = R·X + t with X = Rᵀ_f·X'/s + origin, times s.
// `image` is NAME under OUTPUT so that WriteCamerasJson writes NAME, which the scene resolves
// against its "images" folder.
std::vector<Camera> SceneCameras(const ColmapReconstruction& model, const SceneFrame& f, const fs::path& output) {
  std::vector<Camera> cameras;
  for (const ColmapImage& im : model.images) {
    Camera c;
    c.name = im.name;
    c.image = fs::absolute(output) / im.image;
    c.width = im.width, c.height = im.height;
    c.K << im.fx, 0.0, im.cx, 0.0, im.fy, im.cy, 0.0, 0.0, 1.0;
    c.cam_from_world.topLeftCorner<3, 3>() = im.R * f.R.transpose();
    c.cam_from_world.topRightCorner<3, 1>() = f.scale * (im.R * f.origin + im.t);
    c.distortion = im.distortion;
    cameras.push_back(std::move(c));
  }
  return cameras;
}

nlohmann::ordered_json Vector(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// init.json: the effective options and what was found, so a run can be repeated and checked.
std::string InitJson(const InitOptions& o, const InitResult& r) {
  nlohmann::ordered_json j{{"sparse", fs::absolute(o.sparse).lexically_normal().string()},
                           {"images", r.images.string()},
                           {"template", ToString(o.template_kind)},
                           {"up", o.up ? Vector(*o.up) : nullptr},
                           {"ground_tolerance", o.ground_tolerance},
                           {"seed", o.seed},
                           {"max_side", o.max_side}};
  if (o.scale) j["scale_points"] = {{"a", o.scale->a}, {"b", o.scale->b}, {"length", o.scale->length}};
  nlohmann::ordered_json matrix = nlohmann::ordered_json::array();
  for (int i = 0; i < 4; ++i) matrix.push_back({r.scene_from_model(i, 0), r.scene_from_model(i, 1), r.scene_from_model(i, 2), r.scene_from_model(i, 3)});
  j["found"] = {{"points", r.points},           {"ground_inliers", r.ground_inliers},
                {"above_ground", r.above},      {"ground_normal_in_model", Vector(r.up)},
                {"up_vs_cameras_deg", r.up_vs_cameras_deg}, {"scale", r.scale},
                {"metres", r.metres},           {"scene_from_model", matrix},
                {"robust_lo", Vector(r.lo)},    {"robust_hi", Vector(r.hi)}};
  return j.dump(2) + "\n";
}

std::string RelativeFolder(const fs::path& folder, const fs::path& output) {
  const std::string relative = folder.lexically_relative(fs::absolute(output).lexically_normal()).generic_string();
  return relative.ends_with('/') ? relative : relative + "/";  // `--images photos/` ends in one already
}

// `"max_side"` right after `"images"`, where a reader looks for how the photographs are used.
nlohmann::ordered_json WithMaxSide(nlohmann::ordered_json scene, int max_side) {
  nlohmann::ordered_json out;
  for (auto& [key, value] : scene.items()) {
    out[key] = std::move(value);
    if (key == "images") out["max_side"] = max_side;
  }
  return out;
}

void WriteOutputs(const InitOptions& o, const ColmapReconstruction& model, const SceneFrame& f,
                  const StarterExtents& extents, InitResult& r) {
  fs::create_directories(o.output);
  WriteCamerasJson(o.output / "cameras.json", SceneCameras(model, f, o.output));
  std::vector<Vec3> xyz;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  for (const ColmapPoint& p : model.points) xyz.push_back(f.Apply(p.xyz)), rgb.push_back(p.rgb);
  WriteAtomically(o.output / "points.ply", PointsPly(xyz, rgb));
  std::optional<std::string> masks;
  if (r.masks) masks = RelativeFolder(*r.masks, o.output);
  auto scene = StarterSceneJson(o.template_kind, extents, RelativeFolder(r.images, o.output), masks);
  if (r.max_side > 0) scene = WithMaxSide(std::move(scene), r.max_side);
  WriteAtomically(o.output / "scene.json", scene.dump(2) + "\n");
  WriteAtomically(o.output / "init.json", InitJson(o, r));
  for (const char* name : {"cameras.json", "points.ply", "scene.json", "init.json"}) r.written.push_back(o.output / name);
}

// The ground node's side: twice the reach of the ground's inliers (98th percentile), at least
// twice the footprint and at most six times, so the ground the likelihood models stays near.
double GroundSize(const std::vector<Vec3>& ground, const Vec3& lo, const Vec3& hi) {
  std::vector<double> reach;
  for (const Vec3& x : ground) reach.push_back(std::max(std::abs(x.x()), std::abs(x.y())));
  const double footprint = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  return std::clamp(2.0 * Percentile(reach, 0.98), 2.0 * footprint, 6.0 * footprint);
}

// The corner template's walls, from the points below half the top (above the eaves, roofs
// lean back over the walls and would blur their lines in the footprint).
CornerFit FitCornerOrRefuse(const InitOptions& o, const ColmapReconstruction& model, const SceneFrame& f,
                            const std::vector<Vec3>& above, double top, double model_tolerance) {
  std::vector<Eigen::Vector2d> footprint, cameras;
  for (const Vec3& x : above)
    if (x.z() <= 0.5 * top) footprint.push_back(x.head<2>());
  for (const ColmapImage& im : model.images) cameras.push_back(f.Apply(-im.R.transpose() * im.t).head<2>());
  const CornerResult c = FitCorner(footprint, cameras, model_tolerance * f.scale, o.seed);
  if (!c.fit) throw InputError(Shown(o.sparse), "points3D", "the corner template does not fit: " + c.why_not);
  return *c.fit;
}

}  // namespace

InitResult InitScene(const InitOptions& o) {
  if (fs::exists(o.output / "scene.json"))
    throw InputError(Shown(o.output / "scene.json"), "", "exists: init does not overwrite a scene (remove it, or choose another -o)");
  const ColmapReconstruction model = ReadModel(o);
  InitResult r;
  r.images = ImagesFolder(o);
  if (fs::is_directory(r.images.parent_path() / "masks")) r.masks = r.images.parent_path() / "masks";
  CheckPhotographs(model, r.images);
  for (const ColmapImage& im : model.images) r.largest_side = std::max({r.largest_side, im.width, im.height});
  if (o.max_side > 0 && r.largest_side > o.max_side) r.max_side = o.max_side;
  std::vector<Vec3> points;
  for (const ColmapPoint& p : model.points) points.push_back(p.xyz);
  GroundPlaneOptions go;
  go.up = UpHint(o, model);
  go.tolerance = o.ground_tolerance * CloudSize(points);
  go.seed = o.seed;
  const std::optional<GroundPlane> ground = FitGroundPlane(points, go);
  if (!ground) throw InputError(Shown(o.sparse), "points3D", NoGround(o, go));
  std::vector<Vec3> above, on;
  for (const Vec3& x : points) {
    if (ground->Height(x) > 3.0 * go.tolerance) above.push_back(x);
    if (std::abs(ground->Height(x)) <= go.tolerance) on.push_back(x);
  }
  above = DropIsolated(NearTheObject(std::move(above), model, ground->normal));
  if (above.size() < kMinAbove)
    throw InputError(Shown(o.sparse), "points3D", std::string("the ") + ToString(o.template_kind) +
        " template does not fit: " + std::to_string(above.size()) + " of " + std::to_string(points.size()) +
        " points lie above the ground near what the cameras look at, it needs " + std::to_string(kMinAbove));
  SceneFrame f = FrameOnGround(*ground, above);
  f.scale = ScaleFrom(o, model);
  for (Vec3& x : above) x = f.Apply(x);
  for (Vec3& x : on) x = f.Apply(x);
  RobustBox(above, r.lo, r.hi);
  if ((r.hi - r.lo).minCoeff() <= 3.0 * go.tolerance * f.scale)
    throw InputError(Shown(o.sparse), "points3D", std::string("the ") + ToString(o.template_kind) +
        " template does not fit: the points above the ground span no volume (a wall or a line?)");
  r.images_count = int(model.images.size());
  r.points = int(points.size());
  r.ground_inliers = ground->inliers;
  r.above = int(above.size());
  r.up = ground->normal;
  r.up_vs_cameras_deg = std::acos(std::clamp(ground->normal.dot(CamerasUp(model).normalized()), -1.0, 1.0)) * 180.0 / M_PI;
  r.scale = f.scale;
  r.metres = o.scale.has_value();
  r.scene_from_model = f.Matrix();
  StarterExtents extents{r.lo, r.hi, GroundSize(on, r.lo, r.hi), std::nullopt, std::nullopt};
  if (o.template_kind == InitTemplate::Corner) extents.corner = FitCornerOrRefuse(o, model, f, above, r.hi.z(), go.tolerance);
  if (o.template_kind == InitTemplate::Stairs && !(extents.stairs = FitStairs(above)))
    throw InputError(Shown(o.sparse), "points3D", "the stairs template does not fit: the points above the ground do not rise one way");
  WriteOutputs(o, model, f, extents, r);
  return r;
}

const char* ToString(InitTemplate t) {
  switch (t) {
    case InitTemplate::Box: return "box";
    case InitTemplate::House: return "house";
    case InitTemplate::Cylinder: return "cylinder";
    case InitTemplate::Stairs: return "stairs";
    case InitTemplate::Corner: return "corner";
  }
  return "?";
}

bool FromString(const std::string& text, InitTemplate* t) {
  for (InitTemplate k : {InitTemplate::Box, InitTemplate::House, InitTemplate::Cylinder, InitTemplate::Stairs,
                         InitTemplate::Corner})
    if (text == ToString(k)) return *t = k, true;
  return false;
}

ScalePoints ParseScalePoints(const std::string& text) {
  ScalePoints s;
  char comma = 0, equals = 0;
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  if (!(in >> s.a >> comma >> s.b >> equals >> s.length) || comma != ',' || equals != '=' || !(in >> std::ws).eof() ||
      !(s.length > 0.0) || !std::isfinite(s.length))
    throw InputError("", "--scale-points", "expected ID1,ID2=LENGTH (two POINT3D_IDs and their distance in metres), not '" + text + "'");
  return s;
}

std::string InitResult::BriefReport() const {
  char line[256];
  std::string out;
  std::snprintf(line, sizeof line, "model: %d images, %d points\n", images_count, points);
  out += line;
  std::snprintf(line, sizeof line, "ground: %d inliers (%.0f%%), its normal %.2f° from the cameras' mean up\n",
                ground_inliers, 100.0 * ground_inliers / std::max(points, 1), up_vs_cameras_deg);
  out += line;
  // A ground passed FitGroundPlane's tests; it is weak when it leans from how the photographs
  // were held, or too few points fix its tilt. A building's ground holds few of the points.
  if (up_vs_cameras_deg > 20.0 || ground_inliers < kFewGroundInliers)
    out += "warning: a weak ground (few inliers, or far from the cameras' up): check points.ply, or give --up\n";
  out += "frame: z up, ground at z = 0, origin under the centre of the points above it, +x along their footprint's principal axis\n";
  std::snprintf(line, sizeof line, metres ? "units: metres (%.6g per model unit, from --scale-points)\n"
                                          : "units: the model's own (scale %.6g: no --scale-points, so not metres)\n", scale);
  out += line;
  std::snprintf(line, sizeof line, "above the ground, near what the cameras look at: %d points, x %.3g to %.3g, y %.3g to %.3g, z up to %.3g (2nd-98th percentiles)\n",
                above, lo.x(), hi.x(), lo.y(), hi.y(), hi.z());
  out += line;
  out += "photographs: " + images.string() + (masks ? ", masks: " + masks->string() : ", no masks folder beside them") + "\n";
  if (max_side > 0) {
    std::snprintf(line, sizeof line, "size: the largest photograph is %d px; the scene uses them shrunk to at most %d (\"max_side\")\n",
                  largest_side, max_side);
    out += line;
  }
  out += "wrote:";
  for (const auto& file : written) out += " " + file.string();
  if (written.empty()) return out + "\n";
  const std::string scene = written.front().parent_path().string() + "/scene.json";
  return out + "\nnext: check the starter scene over the photographs with `vkrecon preview " + scene +
         " -o preview/`, edit its priors, then `vkrecon run " + scene + " -o run/`\n";
}

}  // namespace vkr::recon
