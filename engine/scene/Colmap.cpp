#include "engine/scene/Colmap.h"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <locale>
#include <map>
#include <sstream>

#include "engine/common/InputError.h"

namespace vkr {
namespace {

struct Intrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  LensDistortion distortion;
};

// A COLMAP model vkrecon reads: its name, whether it has one focal length (f) or two
// (fx fy), and its distortion model (None for the pinholes).
struct ColmapModel {
  const char* name;
  bool single_focal;
  DistortionModel distortion;
};
constexpr ColmapModel kColmapModels[] = {
    {"SIMPLE_PINHOLE", true, DistortionModel::None},
    {"PINHOLE", false, DistortionModel::None},
    {"SIMPLE_RADIAL", true, DistortionModel::SimpleRadial},
    {"RADIAL", true, DistortionModel::Radial},
    {"OPENCV", false, DistortionModel::OpenCV},
    {"FULL_OPENCV", false, DistortionModel::FullOpenCV},
};

std::string ColmapModelList() {
  std::string list;
  for (const ColmapModel& m : kColmapModels) list += (list.empty() ? "" : ", ") + std::string(m.name);
  return list;
}

// Numbered lines of a text file, trimmed, with CR stripped (files written on Windows).
struct TextFile {
  std::string display;
  std::vector<std::string> lines;

  TextFile(const std::filesystem::path& path, std::string shown) : display(std::move(shown)) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(display, "", "cannot open file (a COLMAP text model needs it)");
    for (std::string line; std::getline(in, line);) {
      const size_t first = line.find_first_not_of(" \t\r");
      const size_t last = line.find_last_not_of(" \t\r");
      lines.push_back(first == std::string::npos ? "" : line.substr(first, last - first + 1));
    }
  }
  static bool Skipped(const std::string& line) { return line.empty() || line[0] == '#'; }
  [[noreturn]] void Fail(size_t index, const std::string& problem) const {
    throw InputError(display, "line " + std::to_string(index + 1), problem);
  }
};

std::istringstream Stream(const std::string& line) {
  std::istringstream s(line);
  s.imbue(std::locale::classic());
  return s;
}

// A 2D-point line: "X Y POINT3D_ID" triples of numbers, or nothing.
bool IsPointsLine(const std::string& line) {
  std::istringstream s = Stream(line);
  size_t count = 0;
  for (double v; s >> v;) ++count;
  return s.eof() && count % 3 == 0;
}

std::map<long long, Intrinsics> ReadCameras(const TextFile& f) {
  std::map<long long, Intrinsics> cameras;
  for (size_t i = 0; i < f.lines.size(); ++i) {
    if (TextFile::Skipped(f.lines[i])) continue;
    std::istringstream s = Stream(f.lines[i]);
    long long id = 0;
    std::string model;
    Intrinsics c;
    if (!(s >> id >> model >> c.width >> c.height))
      f.Fail(i, "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    std::vector<double> params;
    for (double v; s >> v;) params.push_back(v);
    if (!s.eof()) f.Fail(i, "camera parameters must be numbers");
    const ColmapModel* known = nullptr;
    for (const ColmapModel& m : kColmapModels)
      if (model == m.name) known = &m;
    if (!known) f.Fail(i, "camera model " + model + " is not supported (supported: " + ColmapModelList() + ")");
    const size_t focals = known->single_focal ? 1 : 2;
    const size_t expected = focals + 2 + CoefficientNames(known->distortion).size();
    if (params.size() != expected)
      f.Fail(i, model + " needs " + std::to_string(expected) + " parameters, not " +
                    std::to_string(params.size()));
    for (double v : params)
      if (!std::isfinite(v)) f.Fail(i, "camera parameters must be finite");
    c.fx = params[0];
    c.fy = params[focals - 1];
    c.cx = params[focals];
    c.cy = params[focals + 1];
    c.distortion.model = known->distortion;
    for (size_t k = focals + 2; k < params.size(); ++k) c.distortion.coefficients[k - focals - 2] = params[k];
    if (c.width <= 0 || c.height <= 0 || !(c.fx > 0) || !(c.fy > 0))
      f.Fail(i, "camera size and focal length must be positive");
    if (!cameras.emplace(id, c).second) f.Fail(i, "camera " + std::to_string(id) + " defined twice");
  }
  return cameras;
}

}  // namespace

std::vector<ColmapImage> ReadColmapText(const std::filesystem::path& dir,
                                        const std::string& display_dir) {
  const auto shown = [&](const char* name) {
    return (std::filesystem::path(display_dir) / name).lexically_normal().string();
  };
  const std::map<long long, Intrinsics> cameras =
      ReadCameras(TextFile(dir / "cameras.txt", shown("cameras.txt")));
  const TextFile f(dir / "images.txt", shown("images.txt"));
  std::vector<ColmapImage> images;
  for (size_t i = 0; i < f.lines.size(); ++i) {
    if (TextFile::Skipped(f.lines[i])) continue;
    std::istringstream s = Stream(f.lines[i]);
    long long image_id = 0, camera_id = 0;
    double q[4], t[3];
    if (!(s >> image_id >> q[0] >> q[1] >> q[2] >> q[3] >> t[0] >> t[1] >> t[2] >> camera_id))
      f.Fail(i, "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    std::string name;
    std::getline(s >> std::ws, name);
    if (name.empty()) f.Fail(i, "image without a NAME");
    const auto camera = cameras.find(camera_id);
    if (camera == cameras.end())
      f.Fail(i, "camera " + std::to_string(camera_id) + " is not in cameras.txt");
    // The quaternion (QW, QX, QY, QZ) rotates world into camera: R = cam_from_world.
    const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
    if (!(quat.norm() > 1e-12)) f.Fail(i, "zero quaternion");
    ColmapImage im;
    im.name = std::filesystem::path(name).stem().string();
    im.image = name;
    const Intrinsics& c = camera->second;
    im.width = c.width, im.height = c.height;
    im.fx = c.fx, im.fy = c.fy, im.cx = c.cx, im.cy = c.cy;
    im.distortion = c.distortion;
    im.R = quat.normalized().toRotationMatrix();
    im.t = Eigen::Vector3d(t[0], t[1], t[2]);
    images.push_back(std::move(im));
    // Each image line is followed by its 2D points (possibly an empty line). Hand-written
    // models often leave that line out, so it is consumed only if it looks like points.
    if (i + 1 < f.lines.size() && IsPointsLine(f.lines[i + 1])) ++i;
  }
  return images;
}

}  // namespace vkr
