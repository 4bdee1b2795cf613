// Gaussian pyramid: separable blur + 2× decimation, aligned with the S·K convention of
// Pyramid.h.

#include <algorithm>
#include <cmath>
#include "engine/image/Pyramid.h"

#include <stdexcept>

namespace vkr {
namespace {

// Binomial weights ≈ a Gaussian of σ = sqrt(5)/2 ≈ 1.12 fine texels. The taps sit at fine
// texels 2i-2 … 2i+3; their centre of mass is texel index 2i+0.5, i.e. coordinate 2i+1 in
// the [0,W] convention, which is coarse coordinate i+0.5 — the centre of coarse texel i.
// The weights sum to exactly 1, so a constant image stays constant (to float rounding).
constexpr float kTaps[6] = {1 / 32.f, 5 / 32.f, 10 / 32.f, 10 / 32.f, 5 / 32.f, 1 / 32.f};
constexpr int kFirstTap = -2;  // offset of kTaps[0] from 2i

int Clamp(int v, int hi) { return v < 0 ? 0 : (v > hi ? hi : v); }

}  // namespace

int PyramidLevelSize(int n, int level) {
  if (n <= 0) return 0;
  for (int l = 0; l < level && n > 1; ++l) n = (n + 1) / 2;
  return n;
}

Image Downsample2x(const Image& fine) {
  if (fine.Empty()) throw std::invalid_argument("Downsample2x: empty image");
  const int w = PyramidLevelSize(fine.width, 1), h = PyramidLevelSize(fine.height, 1);

  // Horizontal pass straight into the decimated columns: w × fine.height. Decimating inside
  // the filter computes only the texels that are kept.
  Image half(w, fine.height);
  for (int y = 0; y < fine.height; ++y) {
    for (int i = 0; i < w; ++i) {
      float acc[4] = {0, 0, 0, 0};
      for (int t = 0; t < 6; ++t) {
        const float* p = fine.At(Clamp(2 * i + kFirstTap + t, fine.width - 1), y);
        for (int c = 0; c < 4; ++c) acc[c] += kTaps[t] * p[c];
      }
      float* q = half.At(i, y);
      for (int c = 0; c < 4; ++c) q[c] = acc[c];
    }
  }

  // Vertical pass: w × h.
  Image coarse(w, h);
  for (int j = 0; j < h; ++j) {
    const float* rows[6];
    for (int t = 0; t < 6; ++t) rows[t] = half.At(0, Clamp(2 * j + kFirstTap + t, fine.height - 1));
    float* out = coarse.At(0, j);
    for (int k = 0; k < w * 4; ++k) {
      float acc = 0;
      for (int t = 0; t < 6; ++t) acc += kTaps[t] * rows[t][k];
      out[k] = acc;
    }
  }
  return coarse;
}

Image BoxShrink(const Image& image, int factor) {
  if (factor <= 1) return image;
  Image out(std::max(1, image.width / factor), std::max(1, image.height / factor), 0.0f);
  const float weight = 1.0f / float(factor * factor);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      float* o = out.At(x, y);
      for (int dy = 0; dy < factor; ++dy)
        for (int dx = 0; dx < factor; ++dx) {
          const float* p = image.At(std::min(x * factor + dx, image.width - 1), std::min(y * factor + dy, image.height - 1));
          for (int c = 0; c < 4; ++c) o[c] += p[c] * weight;
        }
    }
  return out;
}

std::vector<Image> BuildPyramid(const Image& base, int levels) {
  if (levels < 1) throw std::invalid_argument("BuildPyramid: levels must be >= 1");
  if (base.Empty()) throw std::invalid_argument("BuildPyramid: empty image");
  std::vector<Image> pyramid;
  pyramid.reserve(levels);
  pyramid.push_back(base);
  for (int l = 1; l < levels; ++l) pyramid.push_back(Downsample2x(pyramid.back()));
  return pyramid;
}

}  // namespace vkr

namespace vkr {

void StoreGradientInAlpha(Image& image) {
  const int w = image.width, h = image.height;
  std::vector<float> gradient(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int x0 = std::max(0, x - 1), x1 = std::min(w - 1, x + 1);
      const int y0 = std::max(0, y - 1), y1 = std::min(h - 1, y + 1);
      double sum = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double gx = x1 > x0 ? (image.At(x1, y)[c] - image.At(x0, y)[c]) / (x1 - x0) : 0.0;
        const double gy = y1 > y0 ? (image.At(x, y1)[c] - image.At(x, y0)[c]) / (y1 - y0) : 0.0;
        sum += gx * gx + gy * gy;
      }
      gradient[size_t(y) * w + x] = float(std::round(std::min(1.0, std::sqrt(sum / 3.0)) * 255.0) / 255.0);
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image.At(x, y)[3] = gradient[size_t(y) * w + x];
}

}  // namespace vkr
