// Netpbm PGM/PPM files, written by hand so every header variant is under test control.

#include <gtest/gtest.h>

#include <string>

#include "engine/image/Image.h"
#include "tests/common/TestFiles.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

using test::TempDir;

std::string Bytes(std::initializer_list<int> values) {
  std::string s;
  for (int v : values) s.push_back(char(v));
  return s;
}

TEST(Pnm, BinaryPgmLoadsAsGreyRgbWithAlphaOne) {
  TempDir dir;
  // The first raster byte is 10 ('\n'): it must not be eaten as header whitespace.
  test::WriteText(dir / "a.pgm", "P5\n3 2\n255\n" + Bytes({10, 0, 255, 128, 7, 200}));
  const Image image = LoadImage(dir / "a.pgm");
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  const int expected[6] = {10, 0, 255, 128, 7, 200};
  for (int i = 0; i < 6; ++i) {
    const float* p = image.At(i % 3, i / 3);
    EXPECT_EQ(p[0], expected[i] / 255.0f) << i;
    EXPECT_EQ(p[1], p[0]);
    EXPECT_EQ(p[2], p[0]);
    EXPECT_EQ(p[3], 1.0f);
  }
  int w = 0, h = 0;
  ReadImageSize(dir / "a.pgm", &w, &h);
  EXPECT_EQ(w, 3);
  EXPECT_EQ(h, 2);
}

TEST(Pnm, BinaryPpmLoadsRgb) {
  TempDir dir;
  test::WriteText(dir / "a.ppm",
                  "P6 # a comment in the header\n2 1 255\n" + Bytes({255, 0, 0, 1, 2, 3}));
  const Image image = LoadImage(dir / "a.ppm");
  ASSERT_EQ(image.width, 2);
  ASSERT_EQ(image.height, 1);
  EXPECT_EQ(image.At(0, 0)[0], 1.0f);
  EXPECT_EQ(image.At(0, 0)[1], 0.0f);
  EXPECT_EQ(image.At(1, 0)[0], 1 / 255.0f);
  EXPECT_EQ(image.At(1, 0)[1], 2 / 255.0f);
  EXPECT_EQ(image.At(1, 0)[2], 3 / 255.0f);
  EXPECT_EQ(image.At(1, 0)[3], 1.0f);
}

TEST(Pnm, SixteenBitSamplesAreBigEndianAndScaledByMaxval) {
  TempDir dir;
  // 0x0102 = 258 and 0xFFFF: a little-endian reader would get 513 and still 65535.
  test::WriteText(dir / "a.pgm", "P5\n2 1\n65535\n" + Bytes({0x01, 0x02, 0xff, 0xff}));
  const Image image = LoadImage(dir / "a.pgm");
  EXPECT_FLOAT_EQ(image.At(0, 0)[0], 258 / 65535.0f);
  EXPECT_EQ(image.At(1, 0)[0], 1.0f);
}

TEST(Pnm, SmallMaxvalIsScaled) {
  TempDir dir;
  test::WriteText(dir / "a.pgm", "P5 2 1 100\n" + Bytes({50, 100}));
  const Image image = LoadImage(dir / "a.pgm");
  EXPECT_FLOAT_EQ(image.At(0, 0)[0], 0.5f);
  EXPECT_EQ(image.At(1, 0)[0], 1.0f);
}

TEST(Pnm, AsciiVariantsLoad) {
  TempDir dir;
  test::WriteText(dir / "a.pgm", "P2\n# grey\n2 2\n15\n0 15\n# mid-raster comment\n5 10\n");
  const Image grey = LoadImage(dir / "a.pgm");
  EXPECT_FLOAT_EQ(grey.At(1, 0)[2], 1.0f);
  EXPECT_FLOAT_EQ(grey.At(0, 1)[1], 5 / 15.0f);
  test::WriteText(dir / "a.ppm", "P3 1 1 255 10 20 30");
  const Image colour = LoadImage(dir / "a.ppm");
  EXPECT_EQ(colour.At(0, 0)[1], 20 / 255.0f);
}

TEST(Pnm, BadFilesAreInputErrors) {
  TempDir dir;
  struct Case {
    const char* name;
    std::string bytes;
    const char* needle;
  };
  const Case cases[] = {
      {"truncated.pgm", "P5\n4 4\n255\n" + Bytes({1, 2, 3}), "truncated"},
      {"nosize.pgm", "P5\n", "width"},
      {"zero.pgm", "P5 0 4 255\n", "empty"},
      {"huge.ppm", "P6 100000 100000 255\n", "too large"},
      {"maxval.pgm", "P5 1 1 70000\n" + Bytes({1}), "maxval"},
      {"over.pgm", "P2 1 1 10 11", "exceeds maxval"},
      {"letters.pgm", "P5 x 1 255\n", "width"},
      {"short.ppm", "P3 2 1 255 1 2 3", "sample"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    test::WriteText(dir / c.name, c.bytes);
    test::ExpectInputError([&] { LoadImage(dir / c.name); }, dir / c.name, c.needle);
  }
  // ReadImageSize parses the same header.
  test::ExpectInputError([&] { int w, h; ReadImageSize(dir / "zero.pgm", &w, &h); },
                         dir / "zero.pgm", "empty");
}

}  // namespace
}  // namespace vkr
