#include "pipelines/passes/Projection.h"

namespace vkr {

Eigen::Matrix4d ClipFromCamera(const Eigen::Matrix3d& K, int width, int height, double near) {
  const double W = width, H = height;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = 2.0 * K(0, 0) / W;
  m(0, 1) = 2.0 * K(0, 1) / W;
  m(0, 2) = 2.0 * K(0, 2) / W - 1.0;
  m(1, 1) = 2.0 * K(1, 1) / H;
  m(1, 2) = 2.0 * K(1, 2) / H - 1.0;
  m(2, 3) = near;  // clip.z = near, clip.w = z → z_ndc = near / z
  m(3, 2) = 1.0;
  return m;
}

}  // namespace vkr
