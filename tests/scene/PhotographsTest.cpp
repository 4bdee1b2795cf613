// A scene's `max_side` (docs/guide/SCENE_FORMAT.md, "Large photographs"): photographs longer
// than it are used shrunk by an integer factor, the camera's size and K with them, and masks
// keep only the pixels that were wholly kept.

#include <gtest/gtest.h>

#include "engine/scene/Photographs.h"
#include "engine/scene/Scene.h"
#include "tests/scene/SceneTestUtil.h"

namespace vkr::test {
namespace {

// A binary PGM whose pixel (x, y) is `value(x, y)`.
void WriteGreyPgm(const std::filesystem::path& file, int width, int height, int (*value)(int, int)) {
  std::string pixels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) pixels += char(value(x, y));
  WriteText(file, "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n" + pixels);
}

TEST(LargePhotographs, TheFactorIsTheSmallestThatFits) {
  EXPECT_EQ(ShrinkFactor(640, 480, 0), 1);
  EXPECT_EQ(ShrinkFactor(640, 480, 640), 1);
  EXPECT_EQ(ShrinkFactor(640, 480, 639), 2);
  EXPECT_EQ(ShrinkFactor(640, 480, 320), 2);
  EXPECT_EQ(ShrinkFactor(4032, 3024, 1600), 3);
  EXPECT_EQ(ShrinkFactor(3024, 4032, 1600), 3);
}

TEST(LargePhotographs, TheCameraShrinksWithItsPhotographAndProjectsTheSamePoint) {
  TempDir dir;
  Json scene = BaseScene();
  Json big = BaseCamera("big", "big.pgm");
  big["width"] = 40, big["height"] = 29;
  big["K"] = {{32, 0, 20}, {0, 36, 14.5}, {0, 0, 1}};
  scene["cameras"] = Json::array({big, BaseCamera("small", "small.pgm")});
  scene["max_side"] = 16;
  WritePgm(dir / "big.pgm", 40, 29);
  WritePgm(dir / "small.pgm", 4, 3);
  const Scene loaded = LoadScene(WriteScene(dir, scene));
  ASSERT_EQ(loaded.max_side, 16);
  // 40 px over 16: a factor 3, 13 × 9 pixels (the 40th column and the last two rows cropped).
  EXPECT_EQ(loaded.cameras[0].shrink, 3);
  EXPECT_EQ(loaded.cameras[0].width, 13);
  EXPECT_EQ(loaded.cameras[0].height, 9);
  EXPECT_EQ(loaded.cameras[1].shrink, 1);
  EXPECT_EQ(loaded.cameras[1].width, 4);

  const std::vector<Camera> cameras = loaded.Cameras(loaded.InitialValues());
  EXPECT_EQ(cameras[0].shrink, 3);
  const Eigen::Vector3d point(0.3, -0.2, 1.0);
  // In the file's pixels the point lies at fx·X/Z + cx; in the shrunk ones at a third of that.
  const Eigen::Vector2d full(32 * 0.3 / 6 + 20, 36 * -0.2 / 6 + 14.5);
  EXPECT_NEAR((cameras[0].Project(point) - full / 3).norm(), 0.0, 1e-12);
  EXPECT_NEAR(cameras[1].K(0, 0), 2.0, 0.0);
}

TEST(LargePhotographs, APixelIsTheMeanOfThoseItCovers) {
  TempDir dir;
  WriteGreyPgm(dir / "ramp.pgm", 5, 4, [](int x, int y) { return 10 * x + 50 * y; });
  const Image shrunk = LoadPhotograph(dir / "ramp.pgm", 2);
  ASSERT_EQ(shrunk.width, 2);
  ASSERT_EQ(shrunk.height, 2);
  // Pixel (1, 1) covers x 2–3, y 2–3: (20 + 30 + 20 + 30)/4 + (100 + 100 + 150 + 150)/4.
  EXPECT_NEAR(shrunk.At(1, 1)[0] * 255.0f, 150.0f, 1e-3f);
  EXPECT_NEAR(shrunk.At(0, 0)[0] * 255.0f, 30.0f, 1e-3f);
  const Image same = LoadPhotograph(dir / "ramp.pgm", 1);
  EXPECT_EQ(same.width, 5);
}

TEST(LargePhotographs, AShrunkMaskKeepsOnlyPixelsWhollyKept) {
  TempDir dir;
  // One ignored pixel, at (3, 0), and one grey (kept: any nonzero value keeps).
  WriteGreyPgm(dir / "mask.pgm", 4, 2, [](int x, int y) { return x == 3 && y == 0 ? 0 : x == 0 ? 40 : 255; });
  const Image mask = LoadMask(dir / "mask.pgm", 2);
  ASSERT_EQ(mask.width, 2);
  ASSERT_EQ(mask.height, 1);
  EXPECT_EQ(mask.At(0, 0)[0], 1.0f);
  EXPECT_EQ(mask.At(1, 0)[0], 0.0f);
}

TEST(LargePhotographs, AMaxSideTooSmallIsRefused) {
  TempDir dir;
  Json scene = BaseScene();
  scene["max_side"] = 8;
  EXPECT_TRUE(LoadFails(dir, scene, {"max_side"}));
  scene["max_side"] = "big";
  EXPECT_TRUE(LoadFails(dir, scene, {"max_side"}));
}

}  // namespace
}  // namespace vkr::test
