// ReadColmapBinary and WriteColmapBinary (Colmap.h): COLMAP's binary model, the layout of its
// ReadCamerasBinary / ReadImagesBinary / ReadPoints3DBinary (src/colmap/scene/
// reconstruction_io.cc), little-endian throughout:
//   cameras.bin   u64 count, then per camera: u32 CAMERA_ID, i32 MODEL_ID, u64 WIDTH,
//                 u64 HEIGHT, f64 PARAMS[count of the model]
//   images.bin    u64 count, then per image: u32 IMAGE_ID, f64 QW QX QY QZ, f64 TX TY TZ,
//                 u32 CAMERA_ID, NAME ending in '\0', u64 POINTS2D, then per 2D point
//                 f64 X, f64 Y, u64 POINT3D_ID
//   points3D.bin  u64 count, then per point: u64 POINT3D_ID, f64 X Y Z, u8 R G B, f64 ERROR,
//                 u64 TRACK_LENGTH, then per element u32 IMAGE_ID, u32 POINT2D_IDX

#include <Eigen/Geometry>
#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>

#include "engine/common/InputError.h"
#include "engine/scene/Colmap.h"
#include "engine/scene/ColmapCameraModels.h"

static_assert(std::endian::native == std::endian::little, "COLMAP's binary model is little-endian");

namespace vkr {
namespace {

using colmap_detail::ColmapIntrinsics;

// A binary file read whole, consumed front to back; every read names the record it is in.
class BinaryFile {
 public:
  BinaryFile(const std::filesystem::path& path, std::string display, const char* record)
      : display_(std::move(display)), record_(record) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(display_, "", "cannot open file (a COLMAP binary model needs it)");
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  template <typename T>
  T Read() {
    T value;
    Need(sizeof(T));
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string ReadName() {
    const size_t end = bytes_.find('\0', at_);
    if (end == std::string::npos) Fail("the file ends inside the NAME (truncated)");
    std::string name = bytes_.substr(at_, end - at_);
    at_ = end + 1;
    return name;
  }
  // Checks that `count` items of `size` bytes follow, before they are read or skipped.
  void Expect(std::uint64_t count, size_t size) const {
    if (count > (bytes_.size() - at_) / size) Fail("the file ends inside the record (truncated)");
  }
  void Skip(std::uint64_t count, size_t size) {
    Expect(count, size);
    at_ += size_t(count) * size;
  }
  // The record count at the file's start; each record takes at least `min_size` bytes.
  std::uint64_t ReadCount(size_t min_size) {
    record_index_ = 0;
    const auto count = Read<std::uint64_t>();
    if (count > (bytes_.size() - at_) / min_size)
      Fail("the count " + std::to_string(count) + " needs more bytes than the file holds (truncated)");
    return count;
  }
  void NextRecord() { ++record_index_; }
  void End() {
    if (at_ != bytes_.size()) Fail(std::to_string(bytes_.size() - at_) + " bytes after the last record");
  }
  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(display_, record_index_ ? record_ + " " + std::to_string(record_index_) : "", problem);
  }

 private:
  void Need(size_t size) const {
    if (bytes_.size() - at_ < size)
      Fail(record_index_ ? "the file ends inside the record (truncated)" : "the file ends before the count (truncated)");
  }
  std::string display_, record_;
  std::string bytes_;
  size_t at_ = 0;
  size_t record_index_ = 0;
};

std::map<std::uint32_t, ColmapIntrinsics> ReadCamerasBin(BinaryFile f) {
  std::map<std::uint32_t, ColmapIntrinsics> cameras;
  const std::uint64_t count = f.ReadCount(24);
  for (std::uint64_t i = 0; i < count; ++i) {
    f.NextRecord();
    const auto id = f.Read<std::uint32_t>();
    const auto model_id = f.Read<std::int32_t>();
    const auto width = f.Read<std::uint64_t>(), height = f.Read<std::uint64_t>();
    const size_t n = colmap_detail::ColmapParameterCount(model_id);
    std::vector<double> params;
    for (size_t k = 0; k < n; ++k) params.push_back(f.Read<double>());
    const colmap_detail::ColmapCameraModel* known = nullptr;
    for (const auto& m : colmap_detail::kColmapCameraModels)
      if (model_id == m.id) known = &m;
    ColmapIntrinsics c;
    c.width = width > 1u << 30 ? -1 : int(width);
    c.height = height > 1u << 30 ? -1 : int(height);
    const std::string problem =
        colmap_detail::SetColmapIntrinsics(known, colmap_detail::ColmapModelName(model_id), params, c);
    if (!problem.empty()) f.Fail(problem);
    if (!cameras.emplace(id, c).second) f.Fail("camera " + std::to_string(id) + " defined twice");
  }
  f.End();
  return cameras;
}

std::vector<ColmapImage> ReadImagesBin(BinaryFile f, const std::map<std::uint32_t, ColmapIntrinsics>& cameras) {
  std::vector<ColmapImage> images;
  const std::uint64_t count = f.ReadCount(73);
  for (std::uint64_t i = 0; i < count; ++i) {
    f.NextRecord();
    f.Read<std::uint32_t>();  // IMAGE_ID: images are kept in file order
    double q[4], t[3];
    for (double& v : q) v = f.Read<double>();
    for (double& v : t) v = f.Read<double>();
    const auto camera_id = f.Read<std::uint32_t>();
    const std::string name = f.ReadName();
    f.Skip(f.Read<std::uint64_t>(), 24);  // the 2D points
    if (name.empty()) f.Fail("image without a NAME");
    const auto camera = cameras.find(camera_id);
    if (camera == cameras.end()) f.Fail("camera " + std::to_string(camera_id) + " is not in cameras.bin");
    std::string problem;
    images.push_back(colmap_detail::MakeColmapImage(name, camera->second, q, t, &problem));
    if (!problem.empty()) f.Fail(problem);
  }
  f.End();
  return images;
}

std::vector<ColmapPoint> ReadPointsBin(BinaryFile f) {
  std::vector<ColmapPoint> points;
  const std::uint64_t count = f.ReadCount(51);
  for (std::uint64_t i = 0; i < count; ++i) {
    f.NextRecord();
    ColmapPoint p;
    p.id = f.Read<std::uint64_t>();
    for (int k = 0; k < 3; ++k) p.xyz[k] = f.Read<double>();
    for (auto& c : p.rgb) c = f.Read<std::uint8_t>();
    p.error = f.Read<double>();
    const auto length = f.Read<std::uint64_t>();
    f.Expect(length, 8);
    for (std::uint64_t k = 0; k < length; ++k) {
      const auto image = f.Read<std::uint32_t>();
      p.track.emplace_back(image, f.Read<std::uint32_t>());
    }
    if (!p.xyz.allFinite()) f.Fail("point coordinates must be finite");
    points.push_back(std::move(p));
  }
  f.End();
  return points;
}

}  // namespace

ColmapReconstruction ReadColmapBinary(const std::filesystem::path& dir, const std::string& display_dir) {
  const auto shown = [&](const char* name) {
    return (std::filesystem::path(display_dir) / name).lexically_normal().string();
  };
  ColmapReconstruction model;
  const auto cameras = ReadCamerasBin(BinaryFile(dir / "cameras.bin", shown("cameras.bin"), "camera"));
  model.images = ReadImagesBin(BinaryFile(dir / "images.bin", shown("images.bin"), "image"), cameras);
  model.points = ReadPointsBin(BinaryFile(dir / "points3D.bin", shown("points3D.bin"), "point"));
  return model;
}

namespace {

// Appends the bytes of `value` (little-endian, as the machine is).
template <typename T>
void Put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

void WriteBytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  if (!out) throw InputError(file.string(), "", "cannot write the COLMAP model file");
  out << bytes;
  if (!out) throw InputError(file.string(), "", "write failed");
}

// "CAMERA_ID MODEL_ID WIDTH HEIGHT PARAMS[]" of the image's camera: the model its lens came from.
void PutCamera(std::string& out, std::uint32_t id, const ColmapImage& im) {
  const colmap_detail::ColmapCameraModel* model = &colmap_detail::kColmapCameraModels[1];  // PINHOLE
  for (const auto& m : colmap_detail::kColmapCameraModels)
    if (im.distortion.model != DistortionModel::None && m.distortion == im.distortion.model) model = &m;
  if (model->single_focal && im.fx != im.fy)
    throw InputError(im.image, "", std::string(model->name) + " has one focal length, this camera two");
  Put(out, id);
  Put(out, std::int32_t(model->id));
  Put(out, std::uint64_t(im.width));
  Put(out, std::uint64_t(im.height));
  Put(out, im.fx);
  if (!model->single_focal) Put(out, im.fy);
  Put(out, im.cx);
  Put(out, im.cy);
  for (size_t k = 0; k < CoefficientNames(model->distortion).size(); ++k) Put(out, im.distortion.coefficients[k]);
}

}  // namespace

void WriteColmapBinary(const std::filesystem::path& dir, const ColmapReconstruction& model) {
  std::filesystem::create_directories(dir);
  std::string cameras, images, points;
  Put(cameras, std::uint64_t(model.images.size()));
  Put(images, std::uint64_t(model.images.size()));
  for (size_t i = 0; i < model.images.size(); ++i) {
    const ColmapImage& im = model.images[i];
    const auto id = std::uint32_t(i + 1);
    PutCamera(cameras, id, im);
    Eigen::Quaterniond q(im.R);
    if (q.w() < 0) q.coeffs() *= -1.0;
    Put(images, id);
    for (double v : {q.w(), q.x(), q.y(), q.z(), im.t.x(), im.t.y(), im.t.z()}) Put(images, v);
    Put(images, id);
    images.append(im.image.c_str(), im.image.size() + 1);
    Put(images, std::uint64_t(0));
  }
  Put(points, std::uint64_t(model.points.size()));
  for (const ColmapPoint& p : model.points) {
    Put(points, p.id);
    for (int k = 0; k < 3; ++k) Put(points, p.xyz[k]);
    for (std::uint8_t c : p.rgb) Put(points, c);
    Put(points, p.error);
    Put(points, std::uint64_t(p.track.size()));
    for (const auto& [image, index] : p.track) Put(points, image), Put(points, index);
  }
  WriteBytes(dir / "cameras.bin", cameras);
  WriteBytes(dir / "images.bin", images);
  WriteBytes(dir / "points3D.bin", points);
}

}  // namespace vkr
