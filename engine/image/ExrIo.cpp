// OpenEXR reading and writing. EXR holds linear light; the Image convention is sRGB-encoded
// values, so RGB is converted on the way in and out (Image.h), alpha never.

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/openexr.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/common/InputError.h"
#include "engine/image/Image.h"
#include "engine/image/ImageFormats.h"

namespace vkr::image_detail {
namespace {

void DataWindowSize(const std::filesystem::path& file, const Imf::Header& header, int* width,
                    int* height) {
  const Imath::Box2i& dw = header.dataWindow();
  const long long w = (long long)dw.max.x - dw.min.x + 1;
  const long long h = (long long)dw.max.y - dw.min.y + 1;
  if (w <= 0 || h <= 0 || w * h > kMaxPixels)
    Fail(file, "OpenEXR data window of " + std::to_string(w) + "x" + std::to_string(h) +
                   " pixels is empty or too large");
  *width = int(w);
  *height = int(h);
}

// OpenEXR 3.1's C++ reader trusts the header: a 20 KB file made it allocate 1.2-1.9 GB
// for an attribute (fuzz_image found three such headers, each read differently). Its C core
// library, written to be fuzzed, parses the header with every size checked; in strict mode
// it refuses those files and takes the good ones. So the core reads each header first and
// the C++ reader only sees headers it accepted.
thread_local std::string g_core_message;

void KeepCoreMessage(exr_const_context_t, exr_result_t, const char* message) {
  if (g_core_message.empty() && message) g_core_message = message;  // the first says most
}

// The C++ reader also sizes its decompression buffers by the header, before it reads a
// pixel: a chunk of 16 scan lines of a 7,208,964-pixel-wide, 2-row image made it allocate
// 1.8 GB from an 887-byte file (fuzz_image found it). A chunk or tile that would take more
// than this decoded is refused; a 16384-wide RGBA float image needs 64 MiB even with DWAB's
// 256 lines per chunk.
constexpr uint64_t kMaxChunkBytes = uint64_t(256) << 20;

// Decoded bytes of one chunk (scan-line block or tile) of `part`; 0 when unknown.
uint64_t ChunkBytes(exr_const_context_t context, int part) {
  const exr_attr_chlist_t* channels = nullptr;
  exr_attr_box2i_t window{};
  exr_storage_t storage = EXR_STORAGE_SCANLINE;
  if (exr_get_channels(context, part, &channels) != EXR_ERR_SUCCESS || !channels ||
      exr_get_data_window(context, part, &window) != EXR_ERR_SUCCESS ||
      exr_get_storage(context, part, &storage) != EXR_ERR_SUCCESS)
    return 0;
  uint64_t bytes_per_pixel = 0;
  for (int c = 0; c < channels->num_channels; ++c)
    bytes_per_pixel += channels->entries[c].pixel_type == EXR_PIXEL_HALF ? 2 : 4;
  uint32_t tile_x = 0, tile_y = 0;
  exr_tile_level_mode_t level{};
  exr_tile_round_mode_t round{};
  if (storage != EXR_STORAGE_SCANLINE &&
      exr_get_tile_descriptor(context, part, &tile_x, &tile_y, &level, &round) == EXR_ERR_SUCCESS)
    return uint64_t(tile_x) * tile_y * bytes_per_pixel;
  int32_t lines = 0;
  if (exr_get_scanlines_per_chunk(context, part, &lines) != EXR_ERR_SUCCESS || lines <= 0) return 0;
  const uint64_t width = uint64_t(int64_t(window.max.x) - window.min.x + 1);
  return width * bytes_per_pixel * uint64_t(lines);
}

void CheckHeaderWithCore(const std::filesystem::path& file) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.flags |= EXR_CONTEXT_FLAG_STRICT_HEADER;
  init.error_handler_fn = &KeepCoreMessage;  // instead of printing to stderr
  g_core_message.clear();
  exr_context_t context = nullptr;
  const exr_result_t result = exr_start_read(&context, file.c_str(), &init);
  uint64_t chunk_bytes = 0;
  int parts = 0;
  if (result == EXR_ERR_SUCCESS && exr_get_count(context, &parts) == EXR_ERR_SUCCESS)
    for (int part = 0; part < parts; ++part) chunk_bytes = std::max(chunk_bytes, ChunkBytes(context, part));
  if (context) exr_finish(&context);
  if (result != EXR_ERR_SUCCESS)
    Fail(file, "invalid OpenEXR header: " +
                   (g_core_message.empty() ? std::string(exr_get_default_error_message(result))
                                           : g_core_message));
  if (chunk_bytes > kMaxChunkBytes)
    Fail(file, "OpenEXR chunks of " + std::to_string(chunk_bytes >> 20) +
                   " MiB decoded are too large (a header claiming a huge width, or a broken file)");
}

std::string ChannelNames(const Imf::ChannelList& channels) {
  std::string names;
  for (auto it = channels.begin(); it != channels.end(); ++it)
    names += (names.empty() ? "" : ", ") + std::string(it.name());
  return names.empty() ? "none" : names;
}

Image ReadExrPixels(const std::filesystem::path& file) {
  CheckHeaderWithCore(file);
  Imf::InputFile in(file.c_str());
  const Imf::Header& header = in.header();
  int width = 0, height = 0;
  DataWindowSize(file, header, &width, &height);

  const Imf::ChannelList& channels = header.channels();
  const bool has_rgb = channels.findChannel("R") || channels.findChannel("G") ||
                       channels.findChannel("B");
  const bool has_y = channels.findChannel("Y") != nullptr;
  if (!has_rgb && !has_y)
    Fail(file, "OpenEXR image has no R, G, B or Y channel (channels: " +
                   ChannelNames(channels) + ")");
  // The FrameBuffer slices below assume one sample per pixel; chroma-subsampled (RY/BY)
  // images would need OpenEXR's RgbaInputFile reconstruction, which we do not need.
  for (auto it = channels.begin(); it != channels.end(); ++it)
    if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
      Fail(file, "OpenEXR channel '" + std::string(it.name()) +
                     "' is subsampled; only full-resolution channels are supported");
  if (!in.isComplete()) Fail(file, "OpenEXR image is truncated or incomplete");

  // OpenEXR converts HALF/UINT to FLOAT while filling the slices, and fills a channel the
  // file lacks with the slice's fill value: that is how a missing A becomes 1.
  Image image(width, height);
  const size_t x_stride = 4 * sizeof(float);
  const size_t y_stride = x_stride * size_t(width);
  const Imath::Box2i dw = header.dataWindow();
  auto slice = [&](int c, double fill) {
    // Slice::Make offsets the base pointer by the data window origin for us, so a window
    // that does not start at (0,0) lands at pixel (0,0) of the Image.
    return Imf::Slice::Make(Imf::FLOAT, image.rgba.data() + c, dw, x_stride, y_stride, 1, 1,
                            fill);
  };
  Imf::FrameBuffer frame;
  if (has_rgb) {
    frame.insert("R", slice(0, 0.0));
    frame.insert("G", slice(1, 0.0));
    frame.insert("B", slice(2, 0.0));
  } else {
    frame.insert("Y", slice(0, 0.0));  // luminance only: copied to G and B below
  }
  frame.insert("A", slice(3, 1.0));
  in.setFrameBuffer(frame);
  in.readPixels(dw.min.y, dw.max.y);

  for (size_t i = 0; i < image.rgba.size(); i += 4) {
    float* p = &image.rgba[i];
    if (!has_rgb) p[1] = p[2] = p[0];
    for (int c = 0; c < 3; ++c) p[c] = LinearToSrgb(p[c]);
  }
  return image;
}

}  // namespace

bool IsExr(std::span<const uint8_t> head) {
  static constexpr uint8_t kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  return head.size() >= 4 && std::memcmp(head.data(), kMagic, 4) == 0;
}

Image LoadExr(const std::filesystem::path& file) {
  try {
    return ReadExrPixels(file);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    // Iex exceptions (corrupt header, bad compression data, short file) derive from
    // std::exception in OpenEXR 3; a bad file must never escape as anything but InputError.
    Fail(file, std::string("cannot read OpenEXR image: ") + e.what());
  }
}

void ReadExrSize(const std::filesystem::path& file, int* width, int* height) {
  try {
    CheckHeaderWithCore(file);
    Imf::InputFile in(file.c_str());  // parses the header only; pixels are read on demand
    DataWindowSize(file, in.header(), width, height);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    Fail(file, std::string("cannot read OpenEXR header: ") + e.what());
  }
}

}  // namespace vkr::image_detail

namespace vkr {

void WriteExr(const std::filesystem::path& file, const Image& image) {
  if (image.Empty() || image.rgba.size() != size_t(image.width) * image.height * 4)
    throw std::invalid_argument("WriteExr: image is empty or its pixel buffer has the wrong size");
  // Linear copy: the file stores light, the Image stores encoded values.
  std::vector<float> linear(image.rgba.size());
  for (size_t i = 0; i < linear.size(); i += 4) {
    for (int c = 0; c < 3; ++c) linear[i + c] = SrgbToLinear(image.rgba[i + c]);
    linear[i + 3] = image.rgba[i + 3];
  }
  try {
    // 32-bit FLOAT, not HALF: composites and reprojections are compared numerically, and
    // half's 11-bit mantissa would be visible in those comparisons. ZIP is lossless.
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    static const char* const kNames[4] = {"R", "G", "B", "A"};
    for (const char* name : kNames) header.channels().insert(name, Imf::Channel(Imf::FLOAT));

    const size_t x_stride = 4 * sizeof(float);
    const size_t y_stride = x_stride * size_t(image.width);
    Imf::FrameBuffer frame;
    for (int c = 0; c < 4; ++c)
      frame.insert(kNames[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(linear.data() + c),
                                         x_stride, y_stride));
    Imf::OutputFile out(file.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(image.height);
  } catch (const std::exception& e) {
    image_detail::Fail(file, std::string("cannot write OpenEXR image: ") + e.what());
  }
}

}  // namespace vkr
