// COLMAP's points and binary model (Colmap.h): text ↔ binary round trips, and truncated or
// malformed files refused with one line naming the file and the record.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <filesystem>

#include "engine/scene/Colmap.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

// Two cameras (one with an OPENCV lens) looking at the origin, and three points.
struct SmallModel {
  std::vector<Camera> cameras;
  std::vector<ColmapPoint> points;
};

SmallModel MakeSmallModel(const std::filesystem::path& images_dir) {
  SmallModel m;
  for (int i = 0; i < 2; ++i) {
    Camera c;
    c.name = "c" + std::to_string(i);
    c.image = images_dir / ("sub dir/" + c.name + ".png");
    c.width = 64, c.height = 48;
    c.K << 50 + i, 0, 32.5, 0, 51, 24.25, 0, 0, 1;
    c.cam_from_world = CamFromWorldLookingAt(Eigen::Vector3d(3 * i - 1, -4, 2), Eigen::Vector3d::Zero());
    if (i == 1) {
      c.distortion.model = DistortionModel::OpenCV;
      c.distortion.coefficients = {-0.1, 0.02, 1e-3, -2e-3, 0, 0, 0, 0};
    }
    m.cameras.push_back(c);
  }
  for (int i = 0; i < 3; ++i) {
    ColmapPoint p;
    p.id = 10 + 7 * i;
    p.xyz = Eigen::Vector3d(0.1 * i, -1.0 / 3.0, 2e-7 * i);
    p.rgb = {std::uint8_t(i), 200, 255};
    p.error = 0.5 + i;
    for (int k = 0; k < i; ++k) p.track.emplace_back(k + 1, 100 + k);
    m.points.push_back(p);
  }
  return m;
}

void ExpectSameModel(const ColmapReconstruction& a, const ColmapReconstruction& b) {
  ASSERT_EQ(a.images.size(), b.images.size());
  for (size_t i = 0; i < a.images.size(); ++i) {
    const ColmapImage &x = a.images[i], &y = b.images[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.image, y.image);
    EXPECT_EQ(x.width, y.width);
    EXPECT_EQ(x.height, y.height);
    EXPECT_EQ(Eigen::Vector4d(x.fx, x.fy, x.cx, x.cy), Eigen::Vector4d(y.fx, y.fy, y.cx, y.cy));
    EXPECT_EQ(x.distortion.model, y.distortion.model);
    EXPECT_EQ(x.distortion.coefficients, y.distortion.coefficients);
    EXPECT_TRUE(x.R.isApprox(y.R, 1e-14)) << x.R << "\n" << y.R;
    EXPECT_EQ(x.t, y.t);
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].id, b.points[i].id);
    EXPECT_EQ(a.points[i].xyz, b.points[i].xyz);
    EXPECT_EQ(a.points[i].rgb, b.points[i].rgb);
    EXPECT_EQ(a.points[i].error, b.points[i].error);
    EXPECT_EQ(a.points[i].track, b.points[i].track);
  }
}

TEST(ColmapModel, TextAndBinaryRoundTrip) {
  TempDir dir;
  const SmallModel m = MakeSmallModel(dir / "images");
  WriteColmapText(dir / "text", m.cameras, dir / "images", m.points);
  const ColmapReconstruction text = ReadColmapModel(dir / "text", "text");
  ASSERT_EQ(text.images.size(), 2u);
  EXPECT_EQ(text.images[1].image, "sub dir/c1.png");
  EXPECT_TRUE(text.images[1].R.isApprox(m.cameras[1].R(), 1e-12));
  ASSERT_EQ(text.points.size(), 3u);
  EXPECT_EQ(text.points[2].xyz, m.points[2].xyz);
  EXPECT_EQ(text.points[2].track, m.points[2].track);

  WriteColmapBinary(dir / "bin", text);
  const ColmapReconstruction binary = ReadColmapModel(dir / "bin", "bin");
  ExpectSameModel(text, binary);
}

// The binary model of MakeSmallModel in dir/bin.
std::filesystem::path WriteSmallBinary(const TempDir& dir) {
  const SmallModel m = MakeSmallModel(dir / "images");
  WriteColmapText(dir / "text", m.cameras, dir / "images", m.points);
  WriteColmapBinary(dir / "bin", ReadColmapModel(dir / "text", "text"));
  return dir / "bin";
}

void Truncate(const std::filesystem::path& file, size_t drop) {
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - drop);
}

TEST(ColmapModel, TruncatedBinaryFilesNameFileAndRecord) {
  TempDir dir;
  const auto bin = WriteSmallBinary(dir);
  Truncate(bin / "points3D.bin", 3);  // inside the last point's track
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "sparse"); },
                        {"sparse/points3D.bin: point 3", "truncated"}));
  Truncate(bin / "images.bin", 20);  // inside the second image's NAME
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "sparse"); }, {"sparse/images.bin: image 2", "truncated"}));
  Truncate(bin / "cameras.bin", std::filesystem::file_size(bin / "cameras.bin") - 4);
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "sparse"); }, {"sparse/cameras.bin", "before the count"}));
}

TEST(ColmapModel, MalformedBinaryFiles) {
  TempDir dir;
  const auto bin = WriteSmallBinary(dir);
  const std::string good = ReadText(bin / "cameras.bin");
  std::string bytes = good;
  WriteText(bin / "cameras.bin", bytes + "x");
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "s"); }, {"s/cameras.bin", "1 bytes after the last record"}));
  bytes[8 + 4] = 5;  // the first camera's MODEL_ID: OPENCV_FISHEYE
  WriteText(bin / "cameras.bin", bytes);
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "s"); },
                        {"s/cameras.bin: camera 1", "OPENCV_FISHEYE is not supported"}));
  WriteText(bin / "cameras.bin", good);
  std::filesystem::remove(bin / "points3D.bin");
  EXPECT_TRUE(FailsWith([&] { ReadColmapModel(bin, "s"); }, {"s/points3D.bin", "cannot open"}));
}

TEST(ColmapModel, MalformedPointsText) {
  TempDir dir;
  WriteText(dir / "points3D.txt", "# comment\n1 0 0 0 1 2 3 0.5 1 0\n2 0 0 nan 1 2 3 0.5\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapPointsText(dir / "points3D.txt", "sp/points3D.txt"); },
                        {"sp/points3D.txt: line 3", "expected POINT3D_ID"}));
  WriteText(dir / "points3D.txt", "1 0 0 0 1 2 300 0.5\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapPointsText(dir / "points3D.txt", "p"); }, {"p: line 1", "0 to 255"}));
  WriteText(dir / "points3D.txt", "1 0 0 0 1 2 3 0.5 4 x\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapPointsText(dir / "points3D.txt", "p"); }, {"p: line 1", "TRACK[]"}));
}

}  // namespace
}  // namespace vkr::test
