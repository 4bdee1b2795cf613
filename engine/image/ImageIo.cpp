// Image files: open, sniff the format from the magic bytes (never trust the extension on
// input: a ".png" that is really a JPEG loads fine, a ".png" that is HTML fails clearly),
// and dispatch to OpenEXR, the PGM/PPM reader or stb_image. Every failure of a file
// becomes an InputError naming it (bad input never crashes: docs/guide/SCENE_FORMAT.md, "Errors").

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"
#include "engine/image/ImageFormats.h"

namespace vkr::image_detail {

void Fail(const std::filesystem::path& file, const std::string& problem) {
  throw InputError(file.string(), "", problem);
}

}  // namespace vkr::image_detail

namespace vkr {
namespace {

using image_detail::Fail;
using FilePtr = std::unique_ptr<FILE, int (*)(FILE*)>;

// Enough for any PGM/PPM header; EXR and stb formats re-read the file themselves.
constexpr size_t kHeadBytes = 64 * 1024;

FilePtr OpenForReading(const std::filesystem::path& file) {
  // fopen() happily opens a directory on Linux and the first read fails with EISDIR;
  // saying so up front reads better than a decoder's complaint.
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) Fail(file, "cannot open: is a directory");
  FILE* f = std::fopen(file.c_str(), "rb");
  if (!f) Fail(file, std::string("cannot open: ") + std::strerror(errno));
  return FilePtr(f, &std::fclose);
}

// Reads up to `limit` more bytes (the rest of the file by default).
std::vector<uint8_t> ReadBytes(const std::filesystem::path& file, FILE* f,
                               size_t limit = SIZE_MAX) {
  std::vector<uint8_t> bytes;
  uint8_t chunk[64 * 1024];
  while (bytes.size() < limit) {
    const size_t want = std::min(sizeof(chunk), limit - bytes.size());
    const size_t got = std::fread(chunk, 1, want, f);
    bytes.insert(bytes.end(), chunk, chunk + got);
    if (got < want) {
      if (std::ferror(f)) Fail(file, std::string("cannot read: ") + std::strerror(errno));
      break;  // end of file
    }
  }
  return bytes;
}

[[noreturn]] void FailStb(const std::filesystem::path& file) {
  const char* reason = stbi_failure_reason();
  Fail(file, std::string("not a PNG/JPEG/PGM/PPM/EXR image (stb: ") +
                 (reason ? reason : "unknown error") + ")");
}

// Two faults of stb_image 2.27 (Debian 12) in JPEG Huffman tables, found by fuzz_image (stb
// 2.28 checks both): it builds a table before checking that the DHT segment declares at
// most 256 codes, and writes past the table's arrays when it declares more; and it decodes a
// scan with whatever table its selectors name, defined or not, reading an undefined table's
// uninitialised memory as indices (out of bounds: a crash or garbage). Both are checked here
// first, walking the file as stb does: a marker is 0xFF and a byte other than 0x00
// (stuffed), 0xFF (fill) or a restart; anything else, such as entropy-coded data, is passed
// over byte by byte; a segment is as long as its length field says (stb fails where it is
// not, so walking on checks more than stb reads, never less), except that DHT tables are
// read while the length has bytes left, even past the end of the file (where stb reads
// zeros). A scan uses, per component, its DC table unless it only refines DC bits or codes
// AC coefficients (progressive), and its AC table unless it codes DC only.
void CheckJpegHuffmanTables(const std::filesystem::path& file, const std::vector<uint8_t>& bytes) {
  bool defined[2][4] = {};  // [class: 0 DC, 1 AC][table id]
  bool progressive = false;
  int scan = 0;
  size_t pos = 2;  // after SOI
  while (pos + 1 < bytes.size()) {
    const uint8_t marker = bytes[pos + 1];
    if (bytes[pos] != 0xFF || marker == 0xFF) {
      ++pos;
      continue;
    }
    if (marker == 0x00 || (marker >= 0xD0 && marker <= 0xD7)) {
      pos += 2;
      continue;
    }
    if (marker == 0xD9 || pos + 3 >= bytes.size()) return;  // EOI, or the file ends
    const size_t length = size_t(bytes[pos + 2]) << 8 | bytes[pos + 3];
    if (marker == 0xC2) progressive = true;  // SOF2, the one progressive frame stb reads
    if (marker == 0xDA) {  // SOS: count, per component its id and DC << 4 | AC, then Ss, Se, Ah << 4 | Al
      ++scan;
      const auto byte = [&](size_t i) -> uint8_t { return i < bytes.size() ? bytes[i] : 0; };  // stb: 0 past the end
      const size_t count = byte(pos + 4), spectral = pos + 5 + 2 * count;
      const bool dc_only = byte(spectral) == 0;
      const bool uses_dc = !progressive || (dc_only && (byte(spectral + 2) >> 4) == 0);
      const bool uses_ac = !progressive || !dc_only;
      const auto require = [&](bool used, int table_class, int id) {
        if (used && id <= 3 && !defined[table_class][id])  // ids above 3: stb refuses them
          Fail(file, "corrupt JPEG: scan " + std::to_string(scan) + " uses Huffman table " +
                         (table_class == 0 ? "DC " : "AC ") + std::to_string(id) +
                         ", which no DHT segment before it defines");
      };
      for (size_t c = 0; c < count && c < 4; ++c) {  // more than 4: stb refuses the scan
        const uint8_t tables = byte(pos + 6 + 2 * c);
        require(uses_dc, 0, tables >> 4);
        require(uses_ac, 1, tables & 15);
      }
    }
    if (marker != 0xC4) {
      pos += 2 + length;
      continue;
    }
    long left = long(length) - 2;
    pos += 4;
    while (left > 0 && pos < bytes.size()) {
      const int table_class = bytes[pos] >> 4, id = bytes[pos] & 15;
      if (table_class <= 1 && id <= 3) defined[table_class][id] = true;  // stb refuses others
      size_t codes = 0;  // stb reads 0 past the end of the file
      for (size_t i = pos + 1; i <= pos + 16 && i < bytes.size(); ++i) codes += bytes[i];
      if (codes > 256)
        Fail(file, "corrupt JPEG: a Huffman table declares " + std::to_string(codes) +
                       " codes (at most 256)");
      pos += 17 + codes;
      left -= long(17 + codes);
    }
  }
}

bool IsPng(std::span<const uint8_t> head) {
  static constexpr uint8_t kMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  return head.size() >= 8 && std::memcmp(head.data(), kMagic, 8) == 0;
}
bool IsJpeg(std::span<const uint8_t> head) {
  return head.size() >= 3 && head[0] == 0xFF && head[1] == 0xD8 && head[2] == 0xFF;
}

// stb_image also reads BMP, GIF, PSD, HDR, PIC and TGA, which vkrecon does not promise, and
// TGA has no magic number: any 20 bytes of junk could become an 8224x8224 picture that took
// 20 s to fill (fuzz_image found it). Only PNG and JPEG go to stb.
void RequirePngOrJpeg(const std::filesystem::path& file, std::span<const uint8_t> head) {
  if (!IsPng(head) && !IsJpeg(head)) Fail(file, "not a PNG/JPEG/PGM/PPM/EXR image");
}

// stb_image 2.27 grows its IDAT buffer to the length a chunk claims before reading the
// chunk: 107 bytes claiming a 1.2 GB chunk made it allocate 1.2 GB (fuzz_image found it).
// stb walks a PNG chunk by chunk, by their lengths, as this does; a chunk longer than what
// is left of the file means the file is cut short (or forged).
void CheckPngChunkLengths(const std::filesystem::path& file, const std::vector<uint8_t>& bytes) {
  for (size_t pos = 8; pos + 8 <= bytes.size();) {
    const uint32_t length = uint32_t(bytes[pos]) << 24 | uint32_t(bytes[pos + 1]) << 16 |
                            uint32_t(bytes[pos + 2]) << 8 | bytes[pos + 3];
    std::string type(bytes.begin() + long(pos) + 4, bytes.begin() + long(pos) + 8);
    for (char& c : type)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '?';
    const size_t left = bytes.size() - pos - 8;
    if (length > left)
      Fail(file, "PNG is truncated: chunk " + type + " claims " + std::to_string(length) +
                     " bytes, " + std::to_string(left) + " remain");
    if (type == "IEND") return;
    pos += 12 + size_t(length);
  }
}

// Every 8x8 block of a JPEG's full-resolution component costs at least one bit (its DC
// code, in baseline and progressive files alike), so a JPEG with fewer than w*h/512 bytes
// is truncated or forged. stb would decode it anyway, inventing the missing data: 810 bytes
// claiming 8200x4104 pixels took 5 s (fuzz_image found it).
void CheckJpegDataForSize(const std::filesystem::path& file, const std::vector<uint8_t>& bytes) {
  int w = 0, h = 0, comp = 0;
  if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &w, &h, &comp)) return;  // stb says why
  if (double(bytes.size()) * 512.0 < double(w) * double(h))
    Fail(file, "corrupt JPEG: " + std::to_string(bytes.size()) + " bytes cannot hold " +
                   std::to_string(w) + "x" + std::to_string(h) + " pixels");
}

// PNG and JPEG. Four channels are requested so stb expands grey to RGB and adds alpha 1
// (opaque) where the file has none.
Image DecodeWithStb(const std::filesystem::path& file, const std::vector<uint8_t>& bytes) {
  if (bytes.size() > size_t(INT_MAX)) Fail(file, "file is too large for stb_image (> 2 GiB)");
  RequirePngOrJpeg(file, bytes);
  const int len = int(bytes.size());
  if (IsJpeg(bytes)) {
    CheckJpegHuffmanTables(file, bytes);
    CheckJpegDataForSize(file, bytes);
  } else {
    CheckPngChunkLengths(file, bytes);
  }
  int w = 0, h = 0, channels_in_file = 0;
  Image image;
  // 16-bit PNGs keep their precision; stbi_load would round them to 8 bits.
  if (stbi_is_16_bit_from_memory(bytes.data(), len)) {
    std::unique_ptr<uint16_t, void (*)(void*)> data(
        stbi_load_16_from_memory(bytes.data(), len, &w, &h, &channels_in_file, 4),
        &stbi_image_free);
    if (!data) FailStb(file);
    image = Image(w, h);
    for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = data.get()[i] / 65535.0f;
  } else {
    std::unique_ptr<uint8_t, void (*)(void*)> data(
        stbi_load_from_memory(bytes.data(), len, &w, &h, &channels_in_file, 4), &stbi_image_free);
    if (!data) FailStb(file);
    image = Image(w, h);
    for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = data.get()[i] / 255.0f;
  }
  return image;
}

// The 8-bit code of an encoded value: clamped, rounded to nearest; NaN becomes 0.
uint8_t ToByte(float v) {
  const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
  return uint8_t(std::lround(c * 255.0f));
}

struct PngSink {
  FILE* f;
  bool failed = false;
  int error = 0;
};

void WriteToFile(void* context, void* data, int size) {
  auto* sink = static_cast<PngSink*>(context);
  if (sink->failed || size <= 0) return;
  if (std::fwrite(data, 1, size_t(size), sink->f) != size_t(size)) {
    sink->failed = true;
    sink->error = errno;
  }
}

void CheckImage(const Image& image, const char* who) {
  if (image.Empty() || image.rgba.size() != size_t(image.width) * image.height * 4)
    throw std::invalid_argument(std::string(who) +
                                ": image is empty or its pixel buffer has the wrong size");
}

}  // namespace

Image LoadImage(const std::filesystem::path& file) {
  FilePtr f = OpenForReading(file);
  // EXR goes through OpenEXR's own file reader, so only its magic is read here.
  std::vector<uint8_t> head = ReadBytes(file, f.get(), 4);
  if (head.empty()) Fail(file, "file is empty");
  if (image_detail::IsExr(head)) {
    f.reset();
    return image_detail::LoadExr(file);
  }
  std::vector<uint8_t> rest = ReadBytes(file, f.get());
  head.insert(head.end(), rest.begin(), rest.end());
  if (image_detail::IsPnm(head)) return image_detail::DecodePnm(file, head);
  return DecodeWithStb(file, head);
}

void ReadImageSize(const std::filesystem::path& file, int* width, int* height) {
  FilePtr f = OpenForReading(file);
  const std::vector<uint8_t> head = ReadBytes(file, f.get(), kHeadBytes);
  if (head.empty()) Fail(file, "file is empty");
  if (image_detail::IsExr(head)) {
    f.reset();
    image_detail::ReadExrSize(file, width, height);
    return;
  }
  if (image_detail::IsPnm(head)) {
    image_detail::ReadPnmSize(file, head, width, height);
    return;
  }
  RequirePngOrJpeg(file, head);
  // From memory, never stbi_info_from_file: once stb has refilled its file buffer it cannot
  // rewind to the file's start, so when a PNG's header did not satisfy it, it tried the
  // other formats on bytes from the middle of the file (fuzz_image found a PNM reading of
  // them overflowing an int). A PNG's header (IHDR; for a palette, the chunks up to the
  // first IDAT) is nearly always in `head`; where it is not, the whole file is read.
  int comp = 0;
  if (!IsJpeg(head) && stbi_info_from_memory(head.data(), int(head.size()), width, height, &comp)) return;
  std::vector<uint8_t> bytes = head;
  const std::vector<uint8_t> rest = ReadBytes(file, f.get());
  bytes.insert(bytes.end(), rest.begin(), rest.end());
  if (bytes.size() > size_t(INT_MAX)) Fail(file, "file is too large for stb_image (> 2 GiB)");
  // stb reads a JPEG's Huffman tables on its way to the size (they may come first), so they
  // are checked here too, in the whole file: the headers may be longer than `head`.
  if (IsJpeg(bytes)) CheckJpegHuffmanTables(file, bytes);
  if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), width, height, &comp)) FailStb(file);
}

void WritePng(const std::filesystem::path& file, const Image& image) {
  CheckImage(image, "WritePng");
  std::vector<uint8_t> bytes(image.rgba.size());
  std::transform(image.rgba.begin(), image.rgba.end(), bytes.begin(), ToByte);

  // We open the file ourselves rather than call stbi_write_png(path): stb reports only
  // "failed", and a user with a mistyped output folder deserves the errno text.
  FILE* f = std::fopen(file.c_str(), "wb");
  if (!f) Fail(file, std::string("cannot write: ") + std::strerror(errno));
  PngSink sink{f};
  const int ok = stbi_write_png_to_func(&WriteToFile, &sink, image.width, image.height, 4,
                                        bytes.data(), image.width * 4);
  if (!sink.failed && std::fflush(f) != 0) {
    sink.failed = true;
    sink.error = errno;
  }
  const bool close_failed = std::fclose(f) != 0;
  if (!ok || sink.failed || close_failed) {
    const int error = sink.failed ? sink.error : errno;
    std::error_code ec;
    std::filesystem::remove(file, ec);  // no half-written PNG left behind to confuse a reader
    Fail(file, !ok ? std::string("PNG encoding failed")
                   : std::string("cannot write: ") + std::strerror(error));
  }
}

void WriteImage(const std::filesystem::path& file, const Image& image) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".png") return WritePng(file, image);
  if (ext == ".exr") return WriteExr(file, image);
  Fail(file, "cannot write an image with extension '" + ext + "' (use .png or .exr)");
}

}  // namespace vkr
