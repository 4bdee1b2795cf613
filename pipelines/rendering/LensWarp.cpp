#include "pipelines/rendering/LensWarp.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/common/InputError.h"

namespace vkr {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The four texels a bilinear sample at (x, y) (pixel centres at +0.5) reads, clamped.
struct Taps {
  int x0, x1, y0, y1;
  double fx, fy;
};
Taps BilinearTaps(int width, int height, double x, double y) {
  const double px = std::clamp(x - 0.5, 0.0, double(width - 1));
  const double py = std::clamp(y - 0.5, 0.0, double(height - 1));
  Taps t;
  t.x0 = int(std::floor(px));
  t.y0 = int(std::floor(py));
  t.x1 = std::min(t.x0 + 1, width - 1);
  t.y1 = std::min(t.y0 + 1, height - 1);
  t.fx = px - t.x0;
  t.fy = py - t.y0;
  return t;
}

bool MaskKeeps(const float* rgba) { return rgba[0] > 0.0f || rgba[1] > 0.0f || rgba[2] > 0.0f; }

// Whether every mask texel with a nonzero bilinear weight at (x, y) keeps its pixel.
bool MaskKeepsSample(const Image& mask, double x, double y) {
  const Taps t = BilinearTaps(mask.width, mask.height, x, y);
  const bool use_x1 = t.fx > 0.0, use_y1 = t.fy > 0.0;
  return MaskKeeps(mask.At(t.x0, t.y0)) && (!use_x1 || MaskKeeps(mask.At(t.x1, t.y0))) &&
         (!use_y1 || MaskKeeps(mask.At(t.x0, t.y1))) && (!use_x1 || !use_y1 || MaskKeeps(mask.At(t.x1, t.y1)));
}

void SetAll(float* rgba, float v) { rgba[0] = rgba[1] = rgba[2] = rgba[3] = v; }

}  // namespace

UndistortedPhoto UndistortPhotograph(const Image& photo, const Image* mask, const Eigen::Matrix3d& K,
                                     const LensDistortion& lens) {
  if (mask && (mask->width != photo.width || mask->height != photo.height))
    throw std::invalid_argument("UndistortPhotograph: the mask must have the photograph's size");
  UndistortedPhoto out;
  out.validity = Image(photo.width, photo.height, 1.0f);
  if (lens.IsNone()) {
    out.image = photo;
    if (mask)
      for (int y = 0; y < photo.height; ++y)
        for (int x = 0; x < photo.width; ++x) SetAll(out.validity.At(x, y), MaskKeeps(mask->At(x, y)) ? 1.0f : 0.0f);
    return out;
  }
  out.image = Image(photo.width, photo.height);
  const Eigen::Matrix3d K_inv = K.inverse();
  for (int y = 0; y < photo.height; ++y)
    for (int x = 0; x < photo.width; ++x) {
      const Eigen::Vector3d ray = K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0);
      const Eigen::Vector2d undistorted = ray.head<2>() / ray.z();
      const Eigen::Vector2d distorted = lens.Distort(undistorted);
      const Eigen::Vector3d p = K * distorted.homogeneous();
      const double px = p.x() / p.z(), py = p.y() / p.z();
      SampleBilinear(photo, px, py, out.image.At(x, y));
      Eigen::Vector2d back;
      const bool principal = lens.Undistort(distorted, &back) && (back - undistorted).norm() < 1e-9;
      const bool inside = px >= 0.0 && px <= photo.width && py >= 0.0 && py <= photo.height;
      const bool kept = !mask || MaskKeepsSample(*mask, px, py);
      SetAll(out.validity.At(x, y), principal && inside && kept ? 1.0f : 0.0f);
    }
  return out;
}

PinholeCover CoverDistortedFrame(const Camera& camera, double oversample) {
  if (!(oversample > 0.0)) throw std::invalid_argument("CoverDistortedFrame: oversample must be > 0");
  PinholeCover cover;
  cover.source.resize(size_t(camera.width) * camera.height);
  const Eigen::Matrix3d K_inv = camera.K.inverse();
  Eigen::AlignedBox2d box;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d ray = K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0);
      Eigen::Vector2d undistorted;
      Eigen::Vector2d& source = cover.source[size_t(y) * camera.width + x];
      if (!camera.distortion.Undistort(ray.head<2>() / ray.z(), &undistorted)) {
        source = Eigen::Vector2d(kNaN, kNaN);
        continue;
      }
      const Eigen::Vector3d p = camera.K * undistorted.homogeneous();
      source = p.head<2>() / p.z();  // in the pinhole image of K, for now
      box.extend(source);
    }
  if (box.isEmpty()) box.extend(Eigen::Vector2d(0, 0));
  // Two pixels of margin: the bilinear taps of the outermost samples stay inside.
  const Eigen::Vector2d origin = box.min() - Eigen::Vector2d(2, 2);
  const Eigen::Vector2d size = box.sizes() + Eigen::Vector2d(4, 4);
  if (size.x() > 8.0 * camera.width || size.y() > 8.0 * camera.height)
    throw InputError(camera.name, "distortion",
                     "the lens spreads the image over more than 8× its size; vkrecon cannot render it");
  cover.pinhole = camera;
  cover.pinhole.distortion = LensDistortion{};
  cover.pinhole.width = std::max(1, int(std::ceil(size.x() * oversample)));
  cover.pinhole.height = std::max(1, int(std::ceil(size.y() * oversample)));
  // pinhole pixel = s·(K·x − origin): K' = diag(s, s, 1)·[I | −origin]·K.
  Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
  shift.topRightCorner<2, 1>() = -origin;
  cover.pinhole.K = Eigen::Vector3d(oversample, oversample, 1.0).asDiagonal() * shift * camera.K;
  for (Eigen::Vector2d& s : cover.source) s = oversample * (s - origin);
  return cover;
}

Image ResampleThroughLens(const Image& pinhole_view, const PinholeCover& cover, int width, int height,
                          LensResampling resampling) {
  if (cover.source.size() != size_t(width) * height)
    throw std::invalid_argument("ResampleThroughLens: the cover is for another image size");
  Image out(width, height, 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Eigen::Vector2d& s = cover.source[size_t(y) * width + x];
      if (!s.allFinite()) continue;
      float* o = out.At(x, y);
      if (resampling == LensResampling::Bilinear) {
        SampleBilinear(pinhole_view, s.x(), s.y(), o);
        continue;
      }
      const Taps t = BilinearTaps(pinhole_view.width, pinhole_view.height, s.x(), s.y());
      for (int c = 0; c < 4; ++c)
        o[c] = std::min({pinhole_view.At(t.x0, t.y0)[c], pinhole_view.At(t.x1, t.y0)[c],
                         pinhole_view.At(t.x0, t.y1)[c], pinhole_view.At(t.x1, t.y1)[c]});
    }
  return out;
}

Image RenderThroughLens(const Camera& camera, const std::function<Image(const Camera&)>& render,
                        LensResampling resampling, double oversample) {
  if (camera.distortion.IsNone()) return render(camera);
  const PinholeCover cover = CoverDistortedFrame(camera, oversample);
  return ResampleThroughLens(render(cover.pinhole), cover, camera.width, camera.height, resampling);
}

}  // namespace vkr
