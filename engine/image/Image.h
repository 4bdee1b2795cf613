#pragma once
// Images on the host, and their files.
//
// Colour convention (docs/reference/COLOUR.md): inside vkrecon every colour is an *encoded* value —
// what an 8-bit PNG or JPEG stores, divided by 255 — so noise σ and the likelihood work on
// the thesis's 0–255 scale. 8-bit files are read and written as they are. OpenEXR files hold
// linear light: they are sRGB-encoded when read and decoded (to linear) when written, so an
// EXR viewer shows the same picture as the PNG.

#include <filesystem>
#include <string>
#include <vector>

namespace vkr {

// RGBA, 32-bit float per channel, rows top to bottom, values nominally in [0, 1].
struct Image {
  int width = 0, height = 0;
  std::vector<float> rgba;  // width * height * 4

  Image() = default;
  Image(int w, int h, float fill = 0.0f) : width(w), height(h), rgba(size_t(w) * h * 4, fill) {}
  float* At(int x, int y) { return &rgba[(size_t(y) * width + x) * 4]; }
  const float* At(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
  bool Empty() const { return width == 0 || height == 0; }
};

float SrgbToLinear(float encoded);
float LinearToSrgb(float linear);

// PNG, JPEG, PGM/PPM (grey images become RGB with alpha 1) via stb_image, and OpenEXR.
// Throws InputError naming the file when it is missing, unreadable or not an image.
Image LoadImage(const std::filesystem::path& file);
// Reads only the size (cheap); throws like LoadImage.
void ReadImageSize(const std::filesystem::path& file, int* width, int* height);

// 8-bit RGBA PNG of the encoded values (clamped).
void WritePng(const std::filesystem::path& file, const Image& image);
// 32-bit float RGBA OpenEXR of linear values: encoded colour is decoded to linear; alpha is
// written as it is.
void WriteExr(const std::filesystem::path& file, const Image& image);
// Writes by extension: .png, .exr. Throws InputError for any other.
void WriteImage(const std::filesystem::path& file, const Image& image);

// Bilinear sample at continuous pixel coordinates (pixel centres at +0.5), clamped to edge.
void SampleBilinear(const Image& image, double x, double y, float out[4]);
// Same with texture coordinates in [0,1]², repeating (for albedo textures).
// u runs left to right and v top to bottom (v = 0 is the first row), as in glTF; texel
// centres sit at ((i+0.5)/width, (j+0.5)/height).
void SampleRepeat(const Image& image, double u, double v, float out[4]);

}  // namespace vkr
