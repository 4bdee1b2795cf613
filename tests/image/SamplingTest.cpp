// The sRGB transfer function and bilinear sampling.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "engine/image/Image.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

TEST(Srgb, KnownValues) {
  EXPECT_NEAR(SrgbToLinear(0.5f), 0.214041f, 1e-6f);
  EXPECT_NEAR(LinearToSrgb(0.18f), 0.461356f, 1e-6f);  // mid grey
  EXPECT_EQ(SrgbToLinear(0.0f), 0.0f);
  EXPECT_NEAR(SrgbToLinear(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(LinearToSrgb(1.0f), 1.0f, 1e-6f);
  // The linear toe below the thresholds.
  EXPECT_FLOAT_EQ(SrgbToLinear(0.02f), 0.02f / 12.92f);
  EXPECT_FLOAT_EQ(LinearToSrgb(0.002f), 0.002f * 12.92f);
  // Both pieces meet at the threshold (continuity to float precision).
  EXPECT_NEAR(SrgbToLinear(0.04045f), std::pow((0.04045 + 0.055) / 1.055, 2.4), 1e-7);
}

TEST(Srgb, RoundTripOverTheWholeHdrRange) {
  float previous = -std::numeric_limits<float>::infinity();
  for (int i = -100; i <= 4000; ++i) {
    const float e = i / 1000.0f;  // encoded values from -0.1 to 4
    const float l = SrgbToLinear(e);
    EXPECT_GT(l, previous) << e;  // strictly increasing
    previous = l;
    EXPECT_NEAR(LinearToSrgb(l), e, 1e-6f * std::max(1.0f, std::abs(e))) << e;
  }
}

// 3 × 2 image whose channel c of pixel (x, y) is 10y + x + 100c.
Image Ramp() {
  Image image(3, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 4; ++c) image.At(x, y)[c] = float(10 * y + x + 100 * c);
  return image;
}

TEST(SampleBilinear, PixelCentresAndMidpoints) {
  const Image image = Ramp();
  float out[4];
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      SampleBilinear(image, x + 0.5, y + 0.5, out);
      for (int c = 0; c < 4; ++c) EXPECT_EQ(out[c], image.At(x, y)[c]);
    }
  SampleBilinear(image, 1.0, 0.5, out);  // between (0,0) and (1,0)
  EXPECT_FLOAT_EQ(out[0], 0.5f);
  SampleBilinear(image, 2.0, 1.0, out);  // the corner of four pixels: their mean
  EXPECT_FLOAT_EQ(out[0], (1 + 2 + 11 + 12) / 4.0f);
  EXPECT_FLOAT_EQ(out[3], 300 + (1 + 2 + 11 + 12) / 4.0f);
}

TEST(SampleBilinear, ClampsToEdge) {
  const Image image = Ramp();
  float out[4];
  SampleBilinear(image, -5.0, -5.0, out);
  EXPECT_EQ(out[0], 0.0f);
  SampleBilinear(image, 0.2, 0.5, out);  // left of the first centre
  EXPECT_EQ(out[0], 0.0f);
  SampleBilinear(image, 3.0, 2.0, out);  // the far corner [0,W]×[0,H]
  EXPECT_EQ(out[0], 12.0f);
  SampleBilinear(image, 1e300, 1.5, out);
  EXPECT_EQ(out[0], 12.0f);
  SampleBilinear(image, std::nan(""), 0.5, out);  // no crash, some edge value
  EXPECT_TRUE(std::isfinite(out[0]));
}

TEST(SampleRepeat, TexelCentresTopRowFirstAndWrap) {
  const Image image = Ramp();
  float out[4];
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      const double u = (x + 0.5) / 3, v = (y + 0.5) / 2;
      for (double shift : {0.0, 1.0, -3.0, 1e6}) {
        SampleRepeat(image, u + shift, v - shift, out);
        EXPECT_NEAR(out[0], image.At(x, y)[0], 1e-4f) << x << "," << y << " shift " << shift;
      }
    }
  SampleRepeat(image, 0.5 / 3, 0.01, out);  // v near 0 is near the top row (y = 0)
  EXPECT_LT(out[0], 6.0f);
  SampleRepeat(image, 0.0, 0.25, out);  // u = 0: halfway between last and first column
  EXPECT_FLOAT_EQ(out[0], (2 + 0) / 2.0f);
  SampleRepeat(image, 0.5 / 3, 0.0, out);  // v = 0: halfway between bottom and top row
  EXPECT_FLOAT_EQ(out[0], (0 + 10) / 2.0f);
}

TEST(Sampling, EmptyImageGivesZeros) {
  float out[4] = {1, 1, 1, 1};
  SampleBilinear(Image(), 0.5, 0.5, out);
  EXPECT_EQ(out[0], 0.0f);
  out[0] = 1;
  SampleRepeat(Image(), 0.5, 0.5, out);
  EXPECT_EQ(out[0], 0.0f);
}

}  // namespace
}  // namespace vkr
