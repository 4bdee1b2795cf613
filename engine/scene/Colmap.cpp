#include "engine/scene/Colmap.h"

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <locale>
#include <map>
#include <sstream>

#include "engine/common/InputError.h"
#include "engine/scene/ColmapCameraModels.h"

namespace vkr {
namespace {

using colmap_detail::ColmapIntrinsics;

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

std::map<long long, ColmapIntrinsics> ReadCameras(const TextFile& f) {
  std::map<long long, ColmapIntrinsics> cameras;
  for (size_t i = 0; i < f.lines.size(); ++i) {
    if (TextFile::Skipped(f.lines[i])) continue;
    std::istringstream s = Stream(f.lines[i]);
    long long id = 0;
    std::string model;
    ColmapIntrinsics c;
    if (!(s >> id >> model >> c.width >> c.height))
      f.Fail(i, "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    std::vector<double> params;
    for (double v; s >> v;) params.push_back(v);
    if (!s.eof()) f.Fail(i, "camera parameters must be numbers");
    const colmap_detail::ColmapCameraModel* known = nullptr;
    for (const auto& m : colmap_detail::kColmapCameraModels)
      if (model == m.name) known = &m;
    const std::string problem = colmap_detail::SetColmapIntrinsics(known, model, params, c);
    if (!problem.empty()) f.Fail(i, problem);
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
  const std::map<long long, ColmapIntrinsics> cameras =
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
    std::string problem;
    ColmapImage im = colmap_detail::MakeColmapImage(name, camera->second, q, t, &problem);
    if (!problem.empty()) f.Fail(i, problem);
    images.push_back(std::move(im));
    // Each image line is followed by its 2D points (possibly an empty line). Hand-written
    // models often leave that line out, so it is consumed only if it looks like points.
    if (i + 1 < f.lines.size() && IsPointsLine(f.lines[i + 1])) ++i;
  }
  return images;
}

std::vector<ColmapPoint> ReadColmapPointsText(const std::filesystem::path& file,
                                              const std::string& display) {
  const TextFile f(file, display);
  std::vector<ColmapPoint> points;
  for (size_t i = 0; i < f.lines.size(); ++i) {
    if (TextFile::Skipped(f.lines[i])) continue;
    std::istringstream s = Stream(f.lines[i]);
    ColmapPoint p;
    int rgb[3];
    if (!(s >> p.id >> p.xyz.x() >> p.xyz.y() >> p.xyz.z() >> rgb[0] >> rgb[1] >> rgb[2] >> p.error))
      f.Fail(i, "expected POINT3D_ID X Y Z R G B ERROR TRACK[]");
    if (!p.xyz.allFinite()) f.Fail(i, "point coordinates must be finite");
    for (int c = 0; c < 3; ++c) {
      if (rgb[c] < 0 || rgb[c] > 255) f.Fail(i, "colours are 0 to 255");
      p.rgb[c] = std::uint8_t(rgb[c]);
    }
    for (std::uint32_t image, index; s >> image >> index;) p.track.emplace_back(image, index);
    if (!s.eof()) f.Fail(i, "TRACK[] must be (IMAGE_ID, POINT2D_IDX) pairs of whole numbers");
    points.push_back(std::move(p));
  }
  return points;
}

ColmapReconstruction ReadColmapModel(const std::filesystem::path& dir, const std::string& display_dir) {
  if (std::filesystem::exists(dir / "cameras.bin")) return ReadColmapBinary(dir, display_dir);
  ColmapReconstruction model;
  model.images = ReadColmapText(dir, display_dir);
  model.points = ReadColmapPointsText(
      dir / "points3D.txt", (std::filesystem::path(display_dir) / "points3D.txt").lexically_normal().string());
  return model;
}

}  // namespace vkr
