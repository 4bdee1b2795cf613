// The sRGB transfer function and bilinear sampling of host images.

#include <cmath>

#include "engine/image/Image.h"

namespace vkr {
namespace {

// Blends the four texels (x0|x1, y0|y1) with weights from the fractions fx, fy.
void Blend(const Image& image, int x0, int x1, int y0, int y1, double fx, double fy,
           float out[4]) {
  const float* a = image.At(x0, y0);
  const float* b = image.At(x1, y0);
  const float* c = image.At(x0, y1);
  const float* d = image.At(x1, y1);
  for (int k = 0; k < 4; ++k) {
    const double top = a[k] + fx * (b[k] - a[k]);
    const double bottom = c[k] + fx * (d[k] - c[k]);
    out[k] = float(top + fy * (bottom - top));
  }
}

// A texel index and the fraction towards the next one, for a continuous coordinate whose
// texel centres sit at +0.5 (the [0,W] convention of docs/guide/SCENE_FORMAT.md, "cameras"). The
// coordinate is first clamped to [lo, hi] so that floor() of a huge or NaN value cannot overflow an
// int.
void Split(double coord, double lo, double hi, int* index, double* frac) {
  double p = coord - 0.5;
  if (!(p >= lo)) p = lo;  // also catches NaN
  if (p > hi) p = hi;
  const double f = std::floor(p);
  *index = int(f);
  *frac = p - f;
}

}  // namespace

float SrgbToLinear(float encoded) {
  // IEC 61966-2-1, applied to all reals: the linear toe also serves negative values and the
  // power segment continues above 1, so LinearToSrgb inverts it everywhere (EXR values can
  // exceed 1 and must survive a round trip).
  const double e = encoded;
  if (e <= 0.04045) return float(e / 12.92);
  return float(std::pow((e + 0.055) / 1.055, 2.4));
}

float LinearToSrgb(float linear) {
  const double l = linear;
  if (l <= 0.0031308) return float(l * 12.92);
  return float(1.055 * std::pow(l, 1.0 / 2.4) - 0.055);
}

void SampleBilinear(const Image& image, double x, double y, float out[4]) {
  if (image.Empty()) {
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    return;
  }
  // Clamp to edge: outside the outermost centres the edge texel is repeated, which is what
  // a GPU sampler with CLAMP_TO_EDGE returns, so CPU references agree with the passes.
  int x0, y0;
  double fx, fy;
  Split(x, 0.0, image.width - 1, &x0, &fx);
  Split(y, 0.0, image.height - 1, &y0, &fy);
  const int x1 = x0 + 1 < image.width ? x0 + 1 : x0;
  const int y1 = y0 + 1 < image.height ? y0 + 1 : y0;
  Blend(image, x0, x1, y0, y1, fx, fy, out);
}

void SampleRepeat(const Image& image, double u, double v, float out[4]) {
  if (image.Empty()) {
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    return;
  }
  // Reduce to [0,1) first: the wrap is exact and large u (a tiled ground plane) keeps its
  // precision. NaN falls through to the clamp in Split.
  u -= std::floor(u);
  v -= std::floor(v);
  int x0, y0;
  double fx, fy;
  // In pixel units the reduced coordinate lies in [-0.5, W-0.5); a texel index of -1 is the
  // last column, reached by wrapping.
  Split(u * image.width, -1.0, image.width - 1, &x0, &fx);
  Split(v * image.height, -1.0, image.height - 1, &y0, &fy);
  const int xa = (x0 + image.width) % image.width, xb = (x0 + 1) % image.width;
  const int ya = (y0 + image.height) % image.height, yb = (y0 + 1) % image.height;
  Blend(image, xa, xb, ya, yb, fx, fy, out);
}

}  // namespace vkr
