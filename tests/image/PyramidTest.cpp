// Image pyramids: sizes, conservation, and the S·K alignment promised in Pyramid.h.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "engine/image/Pyramid.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

double Mean(const Image& image, int channel) {
  double sum = 0;
  for (size_t i = channel; i < image.rgba.size(); i += 4) sum += image.rgba[i];
  return sum / (double(image.width) * image.height);
}

TEST(Pyramid, SizesHalveRoundingUp) {
  const std::vector<Image> even = BuildPyramid(Image(160, 120, 0.5f), 3);
  ASSERT_EQ(even.size(), 3u);
  EXPECT_EQ(even[0].width, 160);
  EXPECT_EQ(even[1].width, 80);
  EXPECT_EQ(even[1].height, 60);
  EXPECT_EQ(even[2].width, 40);
  EXPECT_EQ(even[2].height, 30);

  const std::vector<Image> odd = BuildPyramid(Image(5, 3), 5);
  const int widths[5] = {5, 3, 2, 1, 1}, heights[5] = {3, 2, 1, 1, 1};
  for (int l = 0; l < 5; ++l) {
    EXPECT_EQ(odd[l].width, widths[l]) << l;
    EXPECT_EQ(odd[l].height, heights[l]) << l;
    EXPECT_EQ(PyramidLevelSize(5, l), widths[l]);
    EXPECT_EQ(PyramidLevelSize(3, l), heights[l]);
  }
  EXPECT_EQ(PyramidLevelSize(1001, 3), 126);  // ceil(1001 / 8)
}

TEST(Pyramid, LevelZeroIsTheImage) {
  const Image base = test::RandomBytesImage(9, 7, 4);
  const std::vector<Image> one = BuildPyramid(base, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].rgba, base.rgba);
}

TEST(Pyramid, ConstantStaysConstant) {
  Image base(33, 17);
  for (size_t i = 0; i < base.rgba.size(); ++i) base.rgba[i] = 0.1f + 0.2f * float(i % 4);
  for (const Image& level : BuildPyramid(base, 5))
    for (size_t i = 0; i < level.rgba.size(); ++i)
      EXPECT_NEAR(level.rgba[i], 0.1f + 0.2f * float(i % 4), 1e-6f);
}

TEST(Pyramid, MeanIsRoughlyPreserved) {
  const Image base = test::RandomBytesImage(128, 96, 6);
  const std::vector<Image> pyramid = BuildPyramid(base, 4);
  for (int c = 0; c < 4; ++c)
    for (size_t l = 1; l < pyramid.size(); ++l)
      EXPECT_NEAR(Mean(pyramid[l], c), Mean(base, c), 5e-3) << "level " << l << " channel " << c;
}

TEST(Pyramid, CoarseTexelCentresAlignWithScaledIntrinsics) {
  // A ramp equal to its own x coordinate at each texel centre. Under S·K, coarse texel i
  // sits at base coordinate 2(i + 0.5); away from the clamped edges the symmetric filter
  // reproduces a linear function exactly, so the coarse value must be that coordinate.
  Image base(32, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 32; ++x)
      for (int c = 0; c < 4; ++c) base.At(x, y)[c] = float(x) + 0.5f;
  const Image coarse = BuildPyramid(base, 2)[1];
  for (int i = 2; i < 14; ++i) EXPECT_FLOAT_EQ(coarse.At(i, 2)[0], 2.0f * (i + 0.5f)) << i;
}

TEST(Pyramid, BlurRemovesTheNyquistCheckerboard) {
  // Plain decimation of a one-texel checkerboard would alias to a flat 0 or 1; the blur must
  // leave the mean grey instead (the 6-tap binomial has a zero at Nyquist).
  Image base(16, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int c = 0; c < 4; ++c) base.At(x, y)[c] = float((x + y) % 2);
  const Image coarse = BuildPyramid(base, 2)[1];
  for (float v : coarse.rgba) EXPECT_NEAR(v, 0.5f, 0.07f);
  for (int y = 2; y < 6; ++y)
    for (int x = 2; x < 6; ++x) EXPECT_FLOAT_EQ(coarse.At(x, y)[0], 0.5f);
}

TEST(Pyramid, BadArgumentsThrow) {
  EXPECT_THROW(BuildPyramid(Image(4, 4), 0), std::invalid_argument);
  EXPECT_THROW(BuildPyramid(Image(), 2), std::invalid_argument);
}

}  // namespace
}  // namespace vkr
