// OpenEXR: round trips through the sRGB/linear conversion, and checks against OpenEXR itself
// that what lands in the file is linear light.

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <Imath/half.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "tests/common/TestFiles.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

using test::TempDir;

// Values beyond [0,1] on purpose: EXR is HDR and the conversion must invert there too.
Image RandomHdrImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> colour(0.0f, 4.0f), alpha(0.0f, 1.5f);
  Image image(w, h);
  for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = (i % 4 == 3) ? alpha(rng) : colour(rng);
  return image;
}

// Writes a HALF image whose data window is `dw` with the named channels, each pixel's
// value given by value(channel index, x, y).
template <typename Value>
void WriteHalfExr(const std::filesystem::path& file, const Imath::Box2i& dw,
                  const std::vector<std::string>& names, Value value) {
  Imf::Header header(Imath::Box2i({0, 0}, {15, 15}), dw);
  for (const std::string& n : names) header.channels().insert(n, Imf::Channel(Imf::HALF));
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  std::vector<std::vector<half>> planes(names.size(), std::vector<half>(size_t(w) * h));
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < names.size(); ++c) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) planes[c][size_t(y) * w + x] = half(value(int(c), x, y));
    frame.insert(names[c], Imf::Slice::Make(Imf::HALF, planes[c].data(), dw));
  }
  Imf::OutputFile out(file.c_str(), header);
  out.setFrameBuffer(frame);
  out.writePixels(h);
}

TEST(Exr, RoundTripRecoversEncodedValuesAndAlpha) {
  TempDir dir;
  const Image image = RandomHdrImage(19, 11, 5);
  WriteExr(dir / "a.exr", image);
  const Image back = LoadImage(dir / "a.exr");
  ASSERT_EQ(back.width, 19);
  ASSERT_EQ(back.height, 11);
  for (size_t i = 0; i < image.rgba.size(); ++i) {
    if (i % 4 == 3)
      EXPECT_EQ(back.rgba[i], image.rgba[i]) << i;  // alpha is stored untouched
    else
      EXPECT_NEAR(back.rgba[i], image.rgba[i], 2e-6f * std::max(1.0f, image.rgba[i])) << i;
  }
  int w = 0, h = 0;
  ReadImageSize(dir / "a.exr", &w, &h);
  EXPECT_EQ(w, 19);
  EXPECT_EQ(h, 11);
}

TEST(Exr, FileHoldsLinearFloatRgba) {
  TempDir dir;
  const Image image = RandomHdrImage(7, 5, 9);
  WriteExr(dir / "a.exr", image);

  Imf::InputFile in((dir / "a.exr").c_str());
  EXPECT_EQ(in.header().compression(), Imf::ZIP_COMPRESSION);
  for (const char* name : {"R", "G", "B", "A"}) {
    const Imf::Channel* channel = in.header().channels().findChannel(name);
    ASSERT_NE(channel, nullptr) << name;
    EXPECT_EQ(channel->type, Imf::FLOAT) << name;
  }
  std::vector<float> stored(image.rgba.size());
  Imf::FrameBuffer frame;
  const Imath::Box2i dw = in.header().dataWindow();
  for (int c = 0; c < 4; ++c)
    frame.insert(std::string(1, "RGBA"[c]),
                 Imf::Slice::Make(Imf::FLOAT, stored.data() + c, dw, 16, 16 * 7));
  in.setFrameBuffer(frame);
  in.readPixels(dw.min.y, dw.max.y);
  for (size_t i = 0; i < stored.size(); ++i) {
    const float expected = (i % 4 == 3) ? image.rgba[i] : SrgbToLinear(image.rgba[i]);
    EXPECT_EQ(stored[i], expected) << i;
  }
}

TEST(Exr, HalfRgbWithOffsetDataWindowLoads) {
  TempDir dir;
  const Imath::Box2i dw({3, 5}, {8, 9});  // 6 × 5 pixels, not at the origin
  auto value = [](int c, int x, int y) { return 0.05f * float(x + 2 * y) + 0.3f * float(c); };
  WriteHalfExr(dir / "h.exr", dw, {"R", "G", "B"}, value);
  const Image image = LoadImage(dir / "h.exr");
  ASSERT_EQ(image.width, 6);
  ASSERT_EQ(image.height, 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 6; ++x) {
      for (int c = 0; c < 3; ++c)
        EXPECT_FLOAT_EQ(image.At(x, y)[c], LinearToSrgb(float(half(value(c, x, y)))));
      EXPECT_EQ(image.At(x, y)[3], 1.0f);  // no A channel: opaque
    }
  int w = 0, h = 0;
  ReadImageSize(dir / "h.exr", &w, &h);
  EXPECT_EQ(w, 6);
  EXPECT_EQ(h, 5);
}

TEST(Exr, LuminanceOnlyLoadsAsGrey) {
  TempDir dir;
  const Imath::Box2i dw({0, 0}, {3, 2});
  WriteHalfExr(dir / "y.exr", dw, {"Y"}, [](int, int x, int) { return 0.25f * float(x); });
  const Image image = LoadImage(dir / "y.exr");
  const float* p = image.At(2, 1);
  EXPECT_FLOAT_EQ(p[0], LinearToSrgb(0.5f));
  EXPECT_EQ(p[1], p[0]);
  EXPECT_EQ(p[2], p[0]);
  EXPECT_EQ(p[3], 1.0f);
}

TEST(Exr, WithoutColourChannelsIsAnInputError) {
  TempDir dir;
  WriteHalfExr(dir / "z.exr", Imath::Box2i({0, 0}, {1, 1}), {"Z"}, [](int, int, int) { return 1.0f; });
  test::ExpectInputError([&] { LoadImage(dir / "z.exr"); }, dir / "z.exr", "channels: Z");
}

TEST(Exr, TruncatedOrCorruptFilesAreInputErrors) {
  TempDir dir;
  WriteExr(dir / "full.exr", RandomHdrImage(64, 64, 1));
  const std::string bytes = test::ReadText(dir / "full.exr");
  test::WriteText(dir / "half.exr", bytes.substr(0, bytes.size() / 2));
  test::ExpectInputError([&] { LoadImage(dir / "half.exr"); }, dir / "half.exr", "OpenEXR");
  test::WriteText(dir / "head.exr", bytes.substr(0, 12));  // magic, then the header breaks off
  test::ExpectInputError([&] { LoadImage(dir / "head.exr"); }, dir / "head.exr", "OpenEXR");
  test::ExpectInputError([&] { int w, h; ReadImageSize(dir / "head.exr", &w, &h); },
                         dir / "head.exr", "OpenEXR");
  std::string scrambled = bytes;  // valid header, garbage compressed pixel data
  for (size_t i = scrambled.size() / 2; i < scrambled.size(); ++i) scrambled[i] = char(i * 31);
  test::WriteText(dir / "scrambled.exr", scrambled);
  test::ExpectInputError([&] { LoadImage(dir / "scrambled.exr"); }, dir / "scrambled.exr", "");
}

}  // namespace
}  // namespace vkr
