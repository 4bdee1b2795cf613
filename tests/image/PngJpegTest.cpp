// PNG and JPEG through stb_image: 8-bit round trips, 16-bit PNGs, sizes, write dispatch.

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "tests/common/TestFiles.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

using test::TempDir;

// ---- A minimal 16-bit PNG encoder (stb_image_write only writes 8 bits) ----
// Stored (uncompressed) deflate blocks keep it short; CRC-32 and Adler-32 by definition.

uint32_t Crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (unsigned char b : bytes) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutBe32(std::string* s, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s->push_back(char((v >> shift) & 0xff));
}

void PutChunk(std::string* png, const std::string& type, const std::string& data) {
  PutBe32(png, uint32_t(data.size()));
  const std::string body = type + data;
  *png += body;
  PutBe32(png, Crc32(body));
}

// samples: width*height*channels big-endian 16-bit values; colour type 0 (grey) or 6 (RGBA).
std::string Png16(int width, int height, int colour_type, const std::vector<uint16_t>& samples) {
  const int channels = colour_type == 6 ? 4 : 1;
  std::string raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter type None
    for (int i = 0; i < width * channels; ++i) {
      const uint16_t v = samples[size_t(y) * width * channels + i];
      raw.push_back(char(v >> 8));
      raw.push_back(char(v & 0xff));
    }
  }
  std::string zlib = "\x78\x01";
  for (size_t pos = 0; pos < raw.size() || pos == 0; pos += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - pos);
    zlib.push_back(char(pos + n >= raw.size() ? 1 : 0));  // BFINAL on the last block
    zlib.push_back(char(n & 0xff));
    zlib.push_back(char(n >> 8));
    zlib.push_back(char(~n & 0xff));
    zlib.push_back(char((~n >> 8) & 0xff));
    zlib += raw.substr(pos, n);
  }
  uint32_t a = 1, b = 0;
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  PutBe32(&zlib, (b << 16) | a);

  std::string ihdr;
  PutBe32(&ihdr, uint32_t(width));
  PutBe32(&ihdr, uint32_t(height));
  ihdr += std::string{char(16), char(colour_type), 0, 0, 0};
  std::string png = "\x89PNG\r\n\x1a\n";
  PutChunk(&png, "IHDR", ihdr);
  PutChunk(&png, "IDAT", zlib);
  PutChunk(&png, "IEND", "");
  return png;
}

TEST(Png, RoundTripIsExactFor8BitValues) {
  TempDir dir;
  const Image image = test::RandomBytesImage(37, 23, 7);  // odd sizes: no row padding luck
  WritePng(dir / "a.png", image);
  const Image back = LoadImage(dir / "a.png");
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.rgba, image.rgba);
  int w = 0, h = 0;
  ReadImageSize(dir / "a.png", &w, &h);
  EXPECT_EQ(w, 37);
  EXPECT_EQ(h, 23);
}

TEST(Png, WriteClampsAndRoundsToNearest) {
  TempDir dir;
  Image image(4, 1);
  const float values[4] = {0.5f, 1.7f, -0.3f, NAN};  // 127.5 → 128; out of range clamped
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 4; ++c) image.At(x, 0)[c] = values[x];
  WritePng(dir / "c.png", image);
  const Image back = LoadImage(dir / "c.png");
  EXPECT_EQ(back.At(0, 0)[0], 128 / 255.0f);
  EXPECT_EQ(back.At(1, 0)[1], 1.0f);
  EXPECT_EQ(back.At(2, 0)[2], 0.0f);
  EXPECT_EQ(back.At(3, 0)[3], 0.0f);
}

TEST(Png, Rgb8WithoutAlphaLoadsOpaque) {
  TempDir dir;
  const unsigned char rgb[6] = {10, 20, 30, 200, 100, 0};
  ASSERT_TRUE(stbi_write_png((dir / "rgb.png").c_str(), 2, 1, 3, rgb, 6));
  const Image back = LoadImage(dir / "rgb.png");
  EXPECT_EQ(back.At(1, 0)[0], 200 / 255.0f);
  EXPECT_EQ(back.At(0, 0)[2], 30 / 255.0f);
  EXPECT_EQ(back.At(0, 0)[3], 1.0f);
  EXPECT_EQ(back.At(1, 0)[3], 1.0f);
}

TEST(Png, SixteenBitRgbaKeepsFullPrecision) {
  TempDir dir;
  const std::vector<uint16_t> samples = {0, 1, 257, 65535, 32768, 12345, 54321, 40000};
  test::WriteText(dir / "rgba16.png", Png16(2, 1, 6, samples));
  const Image back = LoadImage(dir / "rgba16.png");
  ASSERT_EQ(back.width, 2);
  ASSERT_EQ(back.height, 1);
  for (size_t i = 0; i < samples.size(); ++i)
    EXPECT_FLOAT_EQ(back.rgba[i], samples[i] / 65535.0f) << i;
}

TEST(Png, SixteenBitGreyBecomesRgbWithAlphaOne) {
  TempDir dir;
  test::WriteText(dir / "grey16.png", Png16(3, 2, 0, {0, 100, 1000, 10000, 50000, 65535}));
  const Image back = LoadImage(dir / "grey16.png");
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  const float* p = back.At(1, 1);  // sample 4 = 50000
  EXPECT_FLOAT_EQ(p[0], 50000 / 65535.0f);
  EXPECT_EQ(p[0], p[1]);
  EXPECT_EQ(p[0], p[2]);
  EXPECT_EQ(p[3], 1.0f);
}

TEST(Jpeg, LoadsCloseToWhatWasWritten) {
  TempDir dir;
  // A smooth image: JPEG is lossy, but a gentle gradient survives within a few codes.
  const int w = 32, h = 16;
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) rgb[(size_t(y) * w + x) * 3 + c] = (unsigned char)(64 + 4 * x + c * 20);
  ASSERT_TRUE(stbi_write_jpg((dir / "a.jpg").c_str(), w, h, 3, rgb.data(), 95));
  const Image back = LoadImage(dir / "a.jpg");
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(back.At(x, y)[c] * 255.0f, rgb[(size_t(y) * w + x) * 3 + c], 4.0f);
      EXPECT_EQ(back.At(x, y)[3], 1.0f);
    }
  int rw = 0, rh = 0;
  ReadImageSize(dir / "a.jpg", &rw, &rh);
  EXPECT_EQ(rw, w);
  EXPECT_EQ(rh, h);
}

TEST(Load, FormatComesFromContentNotExtension) {
  TempDir dir;
  const Image image = test::RandomBytesImage(5, 4, 3);
  WritePng(dir / "a.png", image);
  std::filesystem::copy_file(dir / "a.png", dir / "really-a-png.exr");
  EXPECT_EQ(LoadImage(dir / "really-a-png.exr").rgba, image.rgba);
}

TEST(WriteImage, DispatchesOnExtensionCaseInsensitively) {
  TempDir dir;
  const Image image = test::RandomBytesImage(6, 5, 11);
  WriteImage(dir / "a.PNG", image);
  WriteImage(dir / "b.Exr", image);
  EXPECT_EQ(test::ReadText(dir / "a.PNG").substr(1, 3), "PNG");
  EXPECT_EQ(test::ReadText(dir / "b.Exr").substr(0, 4), std::string("\x76\x2f\x31\x01", 4));
  EXPECT_EQ(LoadImage(dir / "a.PNG").rgba, image.rgba);
  test::ExpectInputError([&] { WriteImage(dir / "c.jpg", image); }, dir / "c.jpg", ".jpg");
  test::ExpectInputError([&] { WriteImage(dir / "noext", image); }, dir / "noext", "");
}

}  // namespace
}  // namespace vkr
