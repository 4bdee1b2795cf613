// Netpbm PGM/PPM reading. We parse these ourselves rather than through stb_image (v2.27 as
// shipped by Debian): stb ignores the header's maxval (a maxval-100 file would read 2.5×
// too dark), returns 16-bit samples byte-swapped on little-endian machines, fills a
// truncated raster with garbage instead of failing, and has no ASCII (P2/P3) support. The
// format is small enough that doing it right here is cheaper than working around that.

#include <cstdint>
#include <string>

#include "engine/image/ImageFormats.h"

namespace vkr::image_detail {
namespace {

struct PnmHeader {
  int channels = 0;     // 1 for PGM, 3 for PPM
  bool binary = false;  // P5/P6 raster; P2/P3 are ASCII decimal
  int width = 0, height = 0, maxval = 0;
  size_t raster = 0;    // offset of the first sample
};

bool IsSpace(uint8_t c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\v' || c == '\f' || c == '\r';
}

// Reads tokens of the header and of ASCII rasters: decimal integers separated by
// whitespace, with '#' comments running to the end of the line.
class Reader {
 public:
  Reader(const std::filesystem::path& file, std::span<const uint8_t> bytes, size_t pos)
      : file_(file), bytes_(bytes), pos_(pos) {}

  // `what` names the value for the error message ("width", "sample").
  long long Integer(const char* what) {
    SkipSpaceAndComments();
    if (pos_ >= bytes_.size()) Fail(file_, std::string("PGM/PPM file ends before its ") + what);
    if (bytes_[pos_] < '0' || bytes_[pos_] > '9')
      Fail(file_, std::string("PGM/PPM ") + what + " is not a non-negative integer");
    long long value = 0;
    while (pos_ < bytes_.size() && bytes_[pos_] >= '0' && bytes_[pos_] <= '9') {
      value = value * 10 + (bytes_[pos_++] - '0');
      if (value > (1LL << 40)) Fail(file_, std::string("PGM/PPM ") + what + " is too large");
    }
    return value;
  }
  size_t pos() const { return pos_; }

 private:
  void SkipSpaceAndComments() {
    while (pos_ < bytes_.size()) {
      if (IsSpace(bytes_[pos_])) {
        ++pos_;
      } else if (bytes_[pos_] == '#') {
        while (pos_ < bytes_.size() && bytes_[pos_] != '\n' && bytes_[pos_] != '\r') ++pos_;
      } else {
        break;
      }
    }
  }

  const std::filesystem::path& file_;
  std::span<const uint8_t> bytes_;
  size_t pos_;
};

PnmHeader ParseHeader(const std::filesystem::path& file, std::span<const uint8_t> bytes) {
  if (!IsPnm(bytes)) Fail(file, "not a PGM/PPM image");
  PnmHeader h;
  const char kind = char(bytes[1]);
  h.channels = (kind == '2' || kind == '5') ? 1 : 3;
  h.binary = kind == '5' || kind == '6';
  Reader reader(file, bytes, 2);
  const long long w = reader.Integer("width");
  const long long hh = reader.Integer("height");
  const long long maxval = reader.Integer("maxval");
  // Each side first, so the product cannot overflow (the digits allow up to ~10^13 each).
  if (w <= 0 || hh <= 0 || w > kMaxPixels || hh > kMaxPixels || w * hh > kMaxPixels)
    Fail(file, "PGM/PPM size " + std::to_string(w) + "x" + std::to_string(hh) +
                   " is empty or too large");
  if (maxval < 1 || maxval > 65535)
    Fail(file, "PGM/PPM maxval " + std::to_string(maxval) + " is outside 1..65535");
  h.width = int(w);
  h.height = int(hh);
  h.maxval = int(maxval);
  // Exactly one whitespace byte separates maxval from a binary raster; the raster's first
  // byte may itself look like whitespace, so it must not be skipped as such.
  h.raster = reader.pos() + 1;
  if (reader.pos() >= bytes.size() || !IsSpace(bytes[reader.pos()]))
    Fail(file, "PGM/PPM header does not end with whitespace after maxval");
  return h;
}

}  // namespace

bool IsPnm(std::span<const uint8_t> head) {
  return head.size() >= 2 && head[0] == 'P' &&
         (head[1] == '2' || head[1] == '3' || head[1] == '5' || head[1] == '6');
}

void ReadPnmSize(const std::filesystem::path& file, std::span<const uint8_t> head, int* width,
                 int* height) {
  const PnmHeader h = ParseHeader(file, head);
  *width = h.width;
  *height = h.height;
}

Image DecodePnm(const std::filesystem::path& file, std::span<const uint8_t> bytes) {
  const PnmHeader h = ParseHeader(file, bytes);
  const size_t samples = size_t(h.width) * h.height * h.channels;
  // The raster must be there before the image is allocated: a 30-byte file claiming
  // 16384x16384 pixels would otherwise cost 4 GiB (tests/fuzz/regressions/image). An ASCII
  // sample takes at least a digit and a separator.
  const size_t bytes_per_sample = h.binary ? (h.maxval < 256 ? 1 : 2) : 2;
  const size_t available = bytes.size() - h.raster + (h.binary ? 0 : 1);  // + ASCII's last separator
  if (available / bytes_per_sample < samples)
    Fail(file, "PGM/PPM raster is truncated (" + std::to_string(samples) + " samples expected)");
  Image image(h.width, h.height, 1.0f);  // alpha 1; colour overwritten below
  const float maxval = float(h.maxval);
  auto store = [&](size_t i, long long value) {
    if (value > h.maxval)
      Fail(file, "PGM/PPM sample " + std::to_string(value) + " exceeds maxval " +
                     std::to_string(h.maxval));
    const size_t pixel = i / h.channels;
    float* p = &image.rgba[pixel * 4];
    // A division, not a multiply by 1/maxval: the result is then bit-identical to the PNG
    // path (byte / 255.0f), so the same picture gives the same likelihood in either format.
    const float v = float(value) / maxval;
    if (h.channels == 1)
      p[0] = p[1] = p[2] = v;  // grey becomes RGB
    else
      p[i % 3] = v;
  };

  if (h.binary) {
    // Samples wider than a byte are big-endian (Netpbm specification).
    const uint8_t* data = bytes.data() + h.raster;
    for (size_t i = 0; i < samples; ++i) {
      const long long v = bytes_per_sample == 1 ? data[i] : (data[2 * i] << 8) | data[2 * i + 1];
      store(i, v);
    }
  } else {
    Reader reader(file, bytes, h.raster - 1);
    for (size_t i = 0; i < samples; ++i) store(i, reader.Integer("sample"));
  }
  return image;
}

}  // namespace vkr::image_detail
