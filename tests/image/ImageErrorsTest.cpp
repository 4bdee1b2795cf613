// Bad files and bad output paths: each an InputError naming the file, on one line, never a
// crash (docs/guide/SCENE_FORMAT.md, "Errors").

#include <gtest/gtest.h>
#include <stb/stb_image_write.h>

#include <string>
#include <vector>

#include "engine/image/Image.h"
#include "tests/common/TestFiles.h"
#include "tests/image/ImageTestUtil.h"

namespace vkr {
namespace {

using test::ExpectInputError;
using test::TempDir;

// Both readers must refuse the same files with the same kind of message.
void ExpectUnreadable(const std::filesystem::path& file, const std::string& needle) {
  ExpectInputError([&] { LoadImage(file); }, file, needle);
  ExpectInputError([&] { int w, h; ReadImageSize(file, &w, &h); }, file, needle);
}

TEST(ImageErrors, MissingFile) {
  TempDir dir;
  ExpectUnreadable(dir / "nope.png", "cannot open: No such file or directory");
}

TEST(ImageErrors, Directory) {
  TempDir dir;
  std::filesystem::create_directories(dir / "folder.png");
  ExpectUnreadable(dir / "folder.png", "is a directory");
}

TEST(ImageErrors, EmptyFile) {
  TempDir dir;
  test::WriteText(dir / "empty.png", "");
  ExpectUnreadable(dir / "empty.png", "empty");
}

TEST(ImageErrors, GarbageBytes) {
  TempDir dir;
  test::WriteText(dir / "page.png", "<html>\nnot an image\n</html>\n");
  ExpectUnreadable(dir / "page.png", "not a PNG/JPEG/PGM/PPM/EXR image");
  // TGA has no magic number, so stb_image would decode these 23 bytes as an 8224x8224
  // picture (tests/fuzz/regressions/image): only PNG and JPEG reach stb.
  test::WriteText(dir / "junk.png", std::string("\x01\x00\x02\x22    \x00\x02\x22      r  r\x00\n", 23));
  ExpectUnreadable(dir / "junk.png", "not a PNG/JPEG/PGM/PPM/EXR image");
}

TEST(ImageErrors, TruncatedPng) {
  TempDir dir;
  WritePng(dir / "full.png", test::RandomBytesImage(64, 64, 2));  // noise: no compression
  const std::string bytes = test::ReadText(dir / "full.png");
  test::WriteText(dir / "cut.png", bytes.substr(0, bytes.size() / 2));
  ExpectInputError([&] { LoadImage(dir / "cut.png"); }, dir / "cut.png", "PNG is truncated: chunk IDAT");
  // The size alone is in the first chunk, so a cheap size query may still succeed.
  int w = 0, h = 0;
  ReadImageSize(dir / "cut.png", &w, &h);
  EXPECT_EQ(w, 64);
  test::WriteText(dir / "stub.png", bytes.substr(0, 12));
  ExpectUnreadable(dir / "stub.png", "stb: ");
}

// stb_image 2.27 decodes a scan with whatever Huffman table its selectors name, reading an
// undefined one's uninitialised memory as indices (tests/fuzz/regressions/image): such a
// file is refused, naming the table, before stb sees it. The same file with the selector as
// it was loads.
TEST(ImageErrors, JpegScanWithAnUndefinedHuffmanTable) {
  TempDir dir;
  const int w = 16, h = 16;
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = (unsigned char)(i * 7);
  ASSERT_TRUE(stbi_write_jpg((dir / "good.jpg").c_str(), w, h, 3, rgb.data(), 90));
  std::string bytes = test::ReadText(dir / "good.jpg");
  const size_t sos = bytes.find("\xFF\xDA");
  ASSERT_NE(sos, std::string::npos);
  // SOS: marker, length (2), component count, then per component its id and DC << 4 | AC.
  ASSERT_GE(uint8_t(bytes[sos + 4]), 1);
  const uint8_t tables = uint8_t(bytes[sos + 6]);
  EXPECT_EQ(LoadImage(dir / "good.jpg").width, w);
  bytes[sos + 6] = char((tables & 0xF0) | 2);  // AC table 2: stb writes tables 0 and 1 only
  test::WriteText(dir / "bad.jpg", bytes);
  ExpectUnreadable(dir / "bad.jpg", "corrupt JPEG: scan 1 uses Huffman table AC 2, which no DHT segment before it defines");
}

TEST(ImageErrors, UnwritableOutputPaths) {
  TempDir dir;
  const Image image(4, 3, 0.5f);
  test::WriteText(dir / "file", "x");
  // A missing folder, and a regular file used as a folder (fails even for root).
  for (const std::filesystem::path& out :
       {dir / "no" / "such" / "a.png", dir / "file" / "a.png", dir / "no" / "a.exr",
        dir / "file" / "a.exr"}) {
    SCOPED_TRACE(out.string());
    ExpectInputError([&] { WriteImage(out, image); }, out, "cannot write");
  }
  ExpectInputError([&] { WritePng(dir / "no" / "a.png", image); }, dir / "no" / "a.png",
                   "No such file or directory");
  ExpectInputError([&] { WritePng(dir.path(), image); }, dir.path(), "cannot write");
  ExpectInputError([&] { WriteExr(dir.path(), image); }, dir.path(), "cannot write");
}

TEST(ImageErrors, WritingAnEmptyImageIsAProgrammerError) {
  TempDir dir;
  EXPECT_THROW(WritePng(dir / "a.png", Image()), std::invalid_argument);
  EXPECT_THROW(WriteExr(dir / "a.exr", Image()), std::invalid_argument);
}

}  // namespace
}  // namespace vkr
