// WriteColmapText (Colmap.h): the text model `colmap model_converter --output_type TXT`
// writes, so that what `synth --colmap` makes reads back through {"colmap": …} exactly as a
// calibration by COLMAP would.

#include <Eigen/Geometry>
#include <charconv>
#include <fstream>

#include "engine/common/InputError.h"
#include "engine/scene/Colmap.h"
#include "engine/scene/Scene.h"

namespace vkr {
namespace {

// The shortest text that reads back to the same double, locale-free.
std::string Full(double v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

// "MODEL WIDTH HEIGHT PARAMS[]" of one camera.
std::string ColmapCameraLine(const Camera& c, const std::filesystem::path& file) {
  if (c.K(0, 1) != 0.0)
    throw InputError(file.string(), c.name, "COLMAP cameras have no skew, this K has " + Full(c.K(0, 1)));
  std::string line = c.distortion.model == DistortionModel::None         ? "PINHOLE"
                     : c.distortion.model == DistortionModel::FullOpenCV ? "FULL_OPENCV"
                                                                         : "OPENCV";
  line += " " + std::to_string(c.width) + " " + std::to_string(c.height);
  for (double v : {c.K(0, 0), c.K(1, 1), c.K(0, 2), c.K(1, 2)}) line += " " + Full(v);
  if (c.distortion.IsNone()) return line;
  // OPENCV's k1 k2 p1 p2 (FULL_OPENCV's eight) by name: SIMPLE_RADIAL's k is k1.
  const char* names[] = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
  const size_t count = c.distortion.model == DistortionModel::FullOpenCV ? 8 : 4;
  for (size_t i = 0; i < count; ++i) {
    double v = 0.0;
    for (const std::string& have : CoefficientNames(c.distortion.model))
      if (have == names[i] || (have == "k" && i == 0)) v = c.distortion.Coefficient(have);
    line += " " + Full(v);
  }
  return line;
}

void WriteFile(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string(), "", "cannot write the COLMAP model file");
  out << text;
  if (!out) throw InputError(file.string(), "", "write failed");
}

}  // namespace

void WriteColmapText(const std::filesystem::path& dir, const std::vector<Camera>& cameras,
                     const std::filesystem::path& images_dir,
                     const std::vector<ColmapPoint>& points) {
  std::filesystem::create_directories(dir);
  std::string cameras_txt =
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      "# Number of cameras: " + std::to_string(cameras.size()) + "\n";
  std::string images_txt =
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      "# Number of images: " + std::to_string(cameras.size()) + "\n";
  const std::filesystem::path base = std::filesystem::absolute(images_dir).lexically_normal();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    const std::string id = std::to_string(i + 1);
    cameras_txt += id + " " + ColmapCameraLine(c, dir / "cameras.txt") + "\n";
    // COLMAP's quaternion is cam_from_world's rotation, scalar first; w ≥ 0 by convention.
    Eigen::Quaterniond q(c.R());
    q.normalize();
    if (q.w() < 0) q.coeffs() *= -1.0;
    const Eigen::Vector3d t = c.t();
    const std::string name =
        std::filesystem::absolute(c.image).lexically_normal().lexically_relative(base).generic_string();
    images_txt += id + " " + Full(q.w()) + " " + Full(q.x()) + " " + Full(q.y()) + " " + Full(q.z()) + " " +
                  Full(t.x()) + " " + Full(t.y()) + " " + Full(t.z()) + " " + id + " " + name + "\n\n";
  }
  WriteFile(dir / "cameras.txt", cameras_txt);
  WriteFile(dir / "images.txt", images_txt);
  std::string points_txt =
      "# 3D point list with one line of data per point:\n"
      "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      "# Number of points: " + std::to_string(points.size()) + "\n";
  for (const ColmapPoint& p : points) {
    points_txt += std::to_string(p.id) + " " + Full(p.xyz.x()) + " " + Full(p.xyz.y()) + " " + Full(p.xyz.z());
    for (std::uint8_t c : p.rgb) points_txt += " " + std::to_string(int(c));
    points_txt += " " + Full(p.error);
    for (const auto& [image, index] : p.track) points_txt += " " + std::to_string(image) + " " + std::to_string(index);
    points_txt += "\n";
  }
  WriteFile(dir / "points3D.txt", points_txt);
}

}  // namespace vkr
