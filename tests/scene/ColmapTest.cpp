// COLMAP text models and camera files (docs/guide/SCENE_FORMAT.md, "cameras";
// docs/guide/REAL_CAMERAS.md).

#include "engine/scene/Colmap.h"

#include <gtest/gtest.h>

#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

constexpr const char* kCamerasTxt =
    "# Camera list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "1 PINHOLE 4 3 100 110 2 1.5\r\n"  // written on Windows
    "2 SIMPLE_PINHOLE 4 3 120 2.1 1.4\n";

// Image 1: qw = qz = √½ (Rz 90°). Image 2: (1,1,1,1), not normalised: 120° about (1,1,1).
// Image 1 has a 2D-point line, image 2 an empty one; a hand-written third image has none.
constexpr const char* kImagesTxt =
    "# Image list with two lines of data per image:\n"
    "1 0.7071067811865476 0 0 0.7071067811865476 1 2 3 1 c1.pgm\n"
    "1.5 2.5 -1 3.5 0.5 17\n"
    "2 1 1 1 1 -1 0 4 2 sub/c2.pgm\n"
    "\n"
    "3 1 0 0 0 0 0 1 1 c3.pgm\n";

TEST(Colmap, ReadsPinholeAndSimplePinhole) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt", kCamerasTxt);
  WriteText(dir / "sparse/images.txt", kImagesTxt);
  const auto images = ReadColmapText(dir / "sparse", "sparse");
  ASSERT_EQ(images.size(), 3u);

  EXPECT_EQ(images[0].name, "c1");
  EXPECT_EQ(images[0].image, "c1.pgm");
  EXPECT_EQ(images[0].fx, 100);
  EXPECT_EQ(images[0].fy, 110);
  EXPECT_EQ(images[0].cx, 2);
  EXPECT_EQ(images[0].cy, 1.5);
  Eigen::Matrix3d rz;
  rz << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_TRUE(images[0].R.isApprox(rz, 1e-12)) << images[0].R;
  EXPECT_EQ(images[0].t, Eigen::Vector3d(1, 2, 3));

  EXPECT_EQ(images[1].name, "c2");
  EXPECT_EQ(images[1].image, "sub/c2.pgm");
  EXPECT_EQ(images[1].fx, 120);
  EXPECT_EQ(images[1].fy, 120);
  EXPECT_EQ(images[1].cx, 2.1);
  EXPECT_EQ(images[1].cy, 1.4);
  Eigen::Matrix3d cyclic;  // x ↦ y, y ↦ z, z ↦ x
  cyclic << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  EXPECT_TRUE(images[1].R.isApprox(cyclic, 1e-12)) << images[1].R;
  EXPECT_EQ(images[1].t, Eigen::Vector3d(-1, 0, 4));

  EXPECT_EQ(images[2].name, "c3");
  EXPECT_TRUE(images[2].R.isIdentity());
}

TEST(Colmap, SceneCamerasAndProjection) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt", kCamerasTxt);
  WriteText(dir / "sparse/images.txt", kImagesTxt);
  for (const char* image : {"images/c1.pgm", "images/sub/c2.pgm", "images/c3.pgm"})
    WritePgm(dir / image, 4, 3);
  Json scene = BaseScene();
  scene["images"] = "images/";
  scene["cameras"] = Json{{"colmap", "sparse"}};
  const Scene s = LoadScene(WriteScene(dir, scene));
  ASSERT_EQ(s.cameras.size(), 3u);
  EXPECT_EQ(s.cameras[1].image, (dir.path() / "images/sub/c2.pgm").lexically_normal());
  const auto cams = s.Cameras(s.InitialValues());
  EXPECT_EQ(cams[1].name, "c2");
  Eigen::Matrix3d K;
  K << 120, 0, 2.1, 0, 120, 1.4, 0, 0, 1;
  EXPECT_EQ(cams[1].K, K);
  // X = (1, 0, 0): R·X = (0, 1, 0), + t = (-1, 1, 4); pixel = (120·(-1/4) + 2.1, 120/4 + 1.4).
  const Eigen::Vector2d p = cams[1].Project({1, 0, 0});
  EXPECT_NEAR(p.x(), -27.9, 1e-12);
  EXPECT_NEAR(p.y(), 31.4, 1e-12);
  // Centre = −Rᵀt with R = Rz(90°), t = (1, 2, 3): Rᵀt = (2, −1, 3).
  EXPECT_TRUE(cams[0].Centre().isApprox(Eigen::Vector3d(-2, 1, -3)));
}

TEST(Colmap, UnsupportedModelNamesFileLineAndModel) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt",
            std::string(kCamerasTxt) + "3 OPENCV_FISHEYE 4 3 100 100 2 1.5 0 0 0 0\n");
  WriteText(dir / "sparse/images.txt", kImagesTxt);
  Json scene = BaseScene();
  scene["cameras"] = Json{{"colmap", "sparse"}};
  WriteScene(dir, scene);
  EXPECT_TRUE(FailsWith([&] { LoadScene(dir / "scene.json"); },
                        {"sparse/cameras.txt: line 5: camera model OPENCV_FISHEYE is not supported",
                         "(supported: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV)"}));
}

// Every distortion model COLMAP calibrates ordinary lenses with, parameters in its order.
TEST(Colmap, ReadsEveryDistortionModel) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt",
            "1 SIMPLE_RADIAL 4 3 100 2 1.5 -0.1\n"
            "2 RADIAL 4 3 101 2 1.5 -0.1 0.02\n"
            "3 OPENCV 4 3 102 103 2 1.5 -0.1 0.02 0.001 -0.002\n"
            "4 FULL_OPENCV 4 3 104 105 2 1.5 -0.1 0.02 0.001 -0.002 0.003 0.04 0.005 0.006\n");
  WriteText(dir / "sparse/images.txt",
            "1 1 0 0 0 0 0 1 1 a.pgm\n2 1 0 0 0 0 0 1 2 b.pgm\n3 1 0 0 0 0 0 1 3 c.pgm\n4 1 0 0 0 0 0 1 4 d.pgm\n");
  const auto images = ReadColmapText(dir / "sparse", "sparse");
  ASSERT_EQ(images.size(), 4u);
  EXPECT_EQ(images[0].distortion.model, DistortionModel::SimpleRadial);
  EXPECT_EQ(images[0].fx, 100);
  EXPECT_EQ(images[0].fy, 100);
  EXPECT_EQ(images[0].distortion.Coefficient("k"), -0.1);
  EXPECT_EQ(images[1].distortion.model, DistortionModel::Radial);
  EXPECT_EQ(images[1].distortion.Coefficient("k2"), 0.02);
  EXPECT_EQ(images[1].fy, 101);
  EXPECT_EQ(images[2].distortion.model, DistortionModel::OpenCV);
  EXPECT_EQ(images[2].fx, 102);
  EXPECT_EQ(images[2].fy, 103);
  EXPECT_EQ(images[2].cx, 2);
  EXPECT_EQ(images[2].distortion.Coefficient("p1"), 0.001);
  EXPECT_EQ(images[2].distortion.Coefficient("p2"), -0.002);
  EXPECT_EQ(images[3].distortion.model, DistortionModel::FullOpenCV);
  EXPECT_EQ(images[3].fy, 105);
  EXPECT_EQ(images[3].cy, 1.5);
  EXPECT_EQ(images[3].distortion.Coefficient("k3"), 0.003);
  EXPECT_EQ(images[3].distortion.Coefficient("k6"), 0.006);
  EXPECT_EQ(ReadColmapText(dir / "sparse", "sparse").size(), 4u);

  // Too few parameters for the model, and numbers that are not finite.
  WriteText(dir / "sparse/cameras.txt", "1 OPENCV 4 3 102 103 2 1.5 -0.1 0.02 0.001\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapText(dir / "sparse", "sparse"); },
                        {"sparse/cameras.txt: line 1", "OPENCV needs 8 parameters, not 7"}));
  WriteText(dir / "sparse/cameras.txt", "1 RADIAL 4 3 101 2 1.5 -0.1 1e999\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapText(dir / "sparse", "sparse"); }, {"sparse/cameras.txt: line 1"}));
}

// The scene's cameras carry the lens; what synth --colmap writes reads back the same.
TEST(Colmap, DistortionReachesTheCamerasAndRoundTrips) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt", "7 OPENCV 4 3 102 103 2 1.5 -0.1 0.02 0.001 -0.002\n");
  WriteText(dir / "sparse/images.txt", "1 0.7071067811865476 0 0 0.7071067811865476 1 2 3 7 sub/c1.pgm\n");
  Json scene = BaseScene();
  scene["images"] = "images";
  scene["cameras"] = Json{{"colmap", "sparse"}};
  const Scene s = LoadScene(WriteScene(dir, scene), {}, LoadOptions{false});
  const std::vector<Camera> cams = s.Cameras(s.InitialValues());
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_EQ(cams[0].distortion.model, DistortionModel::OpenCV);
  EXPECT_EQ(cams[0].distortion.Coefficient("k2"), 0.02);

  WriteColmapText(dir / "again", cams, dir / "images");
  const auto back = ReadColmapText(dir / "again", "again");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].image, "sub/c1.pgm");
  EXPECT_EQ(back[0].fx, 102);
  EXPECT_EQ(back[0].fy, 103);
  EXPECT_EQ(back[0].cy, 1.5);
  EXPECT_EQ(back[0].distortion.coefficients, cams[0].distortion.coefficients);
  EXPECT_TRUE(back[0].R.isApprox(cams[0].R(), 1e-15));
  EXPECT_EQ(back[0].t, cams[0].t());

  // RADIAL is written as the OPENCV model it is a special case of; skew has no COLMAP form.
  std::vector<Camera> radial = cams;
  radial[0].distortion = LensDistortion{DistortionModel::Radial, {-0.3, 0.05}};
  WriteColmapText(dir / "radial", radial, dir / "images");
  EXPECT_NE(ReadText(dir / "radial/cameras.txt").find("1 OPENCV 4 3 102 103 2 1.5 -0.3 0.05 0 0\n"),
            std::string::npos);
  radial[0].K(0, 1) = 0.5;
  EXPECT_TRUE(FailsWith([&] { WriteColmapText(dir / "skew", radial, dir / "images"); }, {"no skew"}));
}

TEST(Colmap, BadModels) {
  TempDir dir;
  WriteText(dir / "sparse/cameras.txt", kCamerasTxt);
  WriteText(dir / "sparse/images.txt", "1 1 0 0 0 0 0 1 7 c1.pgm\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapText(dir / "sparse", "sparse"); },
                        {"sparse/images.txt: line 1", "camera 7 is not in cameras.txt"}));
  WriteText(dir / "sparse/images.txt", "1 1 0 0 c1.pgm\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapText(dir / "sparse", "sparse"); },
                        {"sparse/images.txt: line 1", "expected IMAGE_ID"}));
  WriteText(dir / "sparse/cameras.txt", "1 PINHOLE 4 3 100 2 1.5\n");
  EXPECT_TRUE(FailsWith([&] { ReadColmapText(dir / "sparse", "sparse"); },
                        {"sparse/cameras.txt: line 1", "needs 4 parameters"}));
  Json scene = BaseScene();
  scene["cameras"] = Json{{"colmap", "nowhere"}};
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras.colmap", "nowhere not found"}));
}

TEST(CameraFile, ExtraKeysAreIgnoredAndImagesResolveAgainstTheImagesFolder) {
  TempDir dir;
  Json cam = BaseCamera("c1", "c1.pgm");
  cam["sensor"] = Json::array({0, 0, 0});  // written by another tool
  WriteText(dir / "cams/cameras.json",
            Json{{"generator", "tool 1.0"}, {"cameras", Json::array({cam})}}.dump());
  WritePgm(dir / "photos/c1.pgm", 4, 3);
  Json scene = BaseScene();
  scene["images"] = "photos";
  scene["cameras"] = "cams/cameras.json";
  const Scene s = LoadScene(WriteScene(dir, scene));
  ASSERT_EQ(s.cameras.size(), 1u);
  EXPECT_EQ(s.cameras[0].image, (dir.path() / "photos/c1.pgm").lexically_normal());
  EXPECT_EQ(s.images_dir, (dir.path() / "photos").lexically_normal());
}

TEST(CameraFile, DuplicateCameraName) {
  TempDir dir;
  WritePgm(dir / "c1.pgm", 4, 3);
  Json scene = BaseScene();
  scene["cameras"] = Json::array({BaseCamera("c1", "c1.pgm"), BaseCamera("c1", "c1.pgm")});
  EXPECT_TRUE(LoadFails(dir, scene, {"cameras[1].name", "used twice"}));
}

}  // namespace
}  // namespace vkr::test
