// The scene's `cameras`: a camera file, an inline list, or a COLMAP text model
// (docs/guide/SCENE_FORMAT.md, "cameras"). Camera files are written by other tools, so their
// unknown keys are ignored — except `distortion`, which changes the geometry and is read or
// refused, never dropped; inline cameras are part of the scene file, where unknown keys are errors.

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/common/InputError.h"
#include "engine/scene/Colmap.h"
#include "engine/scene/Expression.h"
#include "engine/image/Image.h"
#include "engine/scene/SceneJson.h"

namespace vkr::scene_detail {
namespace {

// The image must exist and have the camera's size (docs/guide/SCENE_FORMAT.md, "Errors":
// "image of the wrong size"). Skipped when the images are yet to be made (synth).
void CheckImage(const Reader& r, const std::string& field, const std::filesystem::path& image,
                int width, int height, const Reader& scene_reader) {
  const std::string shown = scene_reader.Display(image);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(image, ec)) r.Fail(field, "image " + shown + " not found");
  int w = 0, h = 0;
  try {
    ReadImageSize(image, &w, &h);
  } catch (const InputError& e) {
    r.Fail(field, "cannot read the size of " + shown + ": " + e.problem());
  }
  if (w != width || h != height)
    r.Fail(field, shown + " is " + std::to_string(w) + "×" + std::to_string(h) +
                      " but the camera says " + std::to_string(width) + "×" +
                      std::to_string(height));
}

// ‖RᵀR − I‖ < 1e-4 and det R ≈ +1: a mirror (det −1) is a common sign-convention mistake.
void CheckRotation(const Reader& r, const std::string& field, const Eigen::Matrix3d& R) {
  const double orthogonality = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  const double det = R.determinant();
  if (orthogonality < 1e-4 && std::abs(det - 1.0) < 1e-4) return;
  char text[96];
  std::snprintf(text, sizeof text, "not a rotation (det %.2f, |R^T R - I| = %.2g)", det,
                orthogonality);
  r.Fail(field, text);
}

void CheckUniqueName(const Reader& r, const std::string& field, const std::string& name,
                     const Scene& scene) {
  for (const CameraModel& other : scene.cameras)
    if (other.name == name) r.Fail(field, "camera name '" + name + "' is used twice");
}

bool IsConstant(const Scalar& s, double value) { return s.IsConstant() && s.constant == value; }

// `"distortion": {"model": "OPENCV", "k1": …, "k2": …, "p1": …, "p2": …}` (LensDistortion.h):
// every coefficient of the model and no other, each a constant.
LensDistortion ReadDistortion(const Reader& r, const Json& j, const std::string& path) {
  const std::string models = DistortionModelList();
  if (!j.is_object())
    r.Fail(path, "expected {\"model\": NAME, coefficients…} with NAME one of " + models);
  LensDistortion d;
  const std::string model_path = Join(path, "model");
  const std::string model = r.String(r.Require(j, path, "model"), model_path);
  if (!FromString(model, &d.model)) r.Fail(model_path, "unknown distortion model '" + model + "' (" + models + ")");
  const std::vector<std::string>& names = CoefficientNames(d.model);
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  for (const auto& [key, value] : j.items())
    if (key != "model" && std::find(names.begin(), names.end(), key) == names.end())
      r.Fail(Join(path, key), model + " has no coefficient '" + key + "' (it takes " + list + ")");
  for (size_t i = 0; i < names.size(); ++i) {
    const auto it = j.find(names[i]);
    if (it == j.end()) r.Fail(Join(path, names[i]), "missing (" + model + " takes " + list + ")");
    d.coefficients[i] = r.Number(*it, Join(path, names[i]),
                                 "lens distortion is constant: a photograph is undistorted once, when loaded");
  }
  return d;
}

CameraModel ReadCamera(const Reader& r, const Json& j, const std::string& path,
                       const std::filesystem::path& images_dir) {
  r.CheckObject(j, path, {"name", "image", "width", "height", "K", "R", "t", "pose", "distortion"});
  CameraModel cam;
  cam.name = r.String(r.Require(j, path, "name"), Join(path, "name"));
  if (cam.name.empty()) r.Fail(Join(path, "name"), "empty camera name");
  const std::string image = r.String(r.Require(j, path, "image"), Join(path, "image"));
  if (image.empty()) r.Fail(Join(path, "image"), "empty image name");
  cam.image = (images_dir / image).lexically_normal();
  cam.width = int(r.Integer(r.Require(j, path, "width"), Join(path, "width"), 1, 1 << 16));
  cam.height = int(r.Integer(r.Require(j, path, "height"), Join(path, "height"), 1, 1 << 16));

  const std::string k_path = Join(path, "K");
  const Json& K = r.Require(j, path, "K");
  if (!K.is_array() || K.size() != 3) r.Fail(k_path, "expected a 3×3 matrix (3 rows of 3)");
  for (size_t row = 0; row < 3; ++row) {
    const std::string row_path = Index(k_path, row);
    if (!K[row].is_array() || K[row].size() != 3) r.Fail(row_path, "expected a row of 3 values");
    for (size_t col = 0; col < 3; ++col)
      cam.K[row * 3 + col] = r.ParseScalar(K[row][col], Index(row_path, col));
  }
  for (int k : {3, 6, 7})
    if (!IsConstant(cam.K[k], 0.0))
      r.Fail(Index(Index(k_path, size_t(k / 3)), size_t(k % 3)),
             "K must be upper triangular: this entry must be the constant 0");
  if (!IsConstant(cam.K[8], 1.0)) r.Fail(k_path + "[2][2]", "must be the constant 1");

  const char* fixed = "R and t are fixed; use \"pose\" to estimate a camera's position";
  const std::string r_path = Join(path, "R");
  const Json& R = r.Require(j, path, "R");
  if (!R.is_array() || R.size() != 3) r.Fail(r_path, "expected a 3×3 matrix (3 rows of 3)");
  for (size_t row = 0; row < 3; ++row) {
    if (!R[row].is_array() || R[row].size() != 3)
      r.Fail(Index(r_path, row), "expected a row of 3 numbers");
    for (size_t col = 0; col < 3; ++col)
      cam.R(Eigen::Index(row), Eigen::Index(col)) =
          r.Number(R[row][col], Index(Index(r_path, row), col), fixed);
  }
  CheckRotation(r, r_path, cam.R);
  const std::string t_path = Join(path, "t");
  const Json& t = r.Require(j, path, "t");
  if (!t.is_array() || t.size() != 3) r.Fail(t_path, "expected a list of 3 numbers");
  for (size_t k = 0; k < 3; ++k) cam.t[Eigen::Index(k)] = r.Number(t[k], Index(t_path, k), fixed);

  if (auto it = j.find("pose"); it != j.end())
    cam.pose = r.Transforms(*it, Join(path, "pose"), /*allow_scale=*/false);
  if (auto it = j.find("distortion"); it != j.end()) {
    cam.distortion = ReadDistortion(r, *it, Join(path, "distortion"));
    // The photograph is resampled to the pinhole of K once, at load: K cannot change later.
    for (int k : {0, 1, 2, 4, 5})
      if (!cam.K[k].IsConstant())
        r.Fail(Index(Index(k_path, size_t(k / 3)), size_t(k % 3)),
               "a camera with lens distortion needs a constant K (its photograph is undistorted "
               "once, with K, when loaded)");
  }
  return cam;
}

void ReadColmap(const Json& value, const Reader& sr, bool require_images, Scene& scene) {
  sr.CheckObject(value, "cameras", {"colmap"});
  const std::string folder = sr.String(sr.Require(value, "cameras", "colmap"), "cameras.colmap");
  const std::filesystem::path dir = (sr.dir / folder).lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    sr.Fail("cameras.colmap", "COLMAP model folder " + sr.Display(dir) + " not found");
  const std::string display_dir =
      (std::filesystem::path(sr.file).parent_path() / folder).lexically_normal().string();
  for (const ColmapImage& im : ReadColmapText(dir, display_dir)) {
    CameraModel cam;
    cam.name = im.name;
    cam.image = (scene.images_dir / im.image).lexically_normal();
    cam.width = im.width;
    cam.height = im.height;
    const double K[9] = {im.fx, 0, im.cx, 0, im.fy, im.cy, 0, 0, 1};
    for (int k = 0; k < 9; ++k) cam.K[k].constant = K[k];
    cam.distortion = im.distortion;
    cam.R = im.R;
    cam.t = im.t;
    if (require_images)
      CheckImage(sr, "cameras.colmap", cam.image, cam.width, cam.height, sr);
    CheckUniqueName(sr, "cameras.colmap", cam.name, scene);
    scene.cameras.push_back(std::move(cam));
  }
}

}  // namespace

void ReadCameras(const Json& value, const Reader& scene_reader, bool require_images,
                 Scene& scene) {
  const Reader& sr = scene_reader;
  if (value.is_object()) {
    ReadColmap(value, sr, require_images, scene);
  } else {
    // An inline list reads with the scene's rules; a file name with lenient ones.
    Reader file_reader = sr;
    const Json* list = &value;
    Json file_json;
    if (value.is_string()) {
      const std::string name = value.get<std::string>();
      const std::filesystem::path path = (sr.dir / name).lexically_normal();
      file_reader.file =
          (std::filesystem::path(sr.file).parent_path() / name).lexically_normal().string();
      file_reader.strict = false;
      file_reader.overridden = nullptr;
      std::error_code ec;
      if (!std::filesystem::is_regular_file(path, ec))
        sr.Fail("cameras", "camera file " + sr.Display(path) + " not found");
      file_json = ParseJsonFile(path, file_reader.file);
      if (!file_json.is_object() || !file_json.contains("cameras"))
        file_reader.Fail("", "expected an object {\"cameras\": [...]}");
      list = &file_json["cameras"];
    } else if (!value.is_array()) {
      sr.Fail("cameras", "expected a camera file name, a list of cameras or {\"colmap\": "
                         "\"folder\"}");
    }
    if (!list->is_array()) file_reader.Fail("cameras", "expected a list of cameras");
    for (size_t i = 0; i < list->size(); ++i) {
      const std::string path = Index("cameras", i);
      CameraModel cam = ReadCamera(file_reader, (*list)[i], path, scene.images_dir);
      if (require_images)
        CheckImage(file_reader, Join(path, "image"), cam.image, cam.width, cam.height, sr);
      CheckUniqueName(file_reader, Join(path, "name"), cam.name, scene);
      scene.cameras.push_back(std::move(cam));
    }
  }
}

}  // namespace vkr::scene_detail
