#pragma once
// Which points of the model a camera sees, on the host: a z-buffer of the scene's triangles
// in the camera's pinhole image (its lens undone). The wireframe overlays use it to leave out
// edges that other surfaces hide (WireframeOverlay.h), as the photographs do.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "engine/scene/Scene.h"

namespace vkr {

using WorldTriangle = std::array<Eigen::Vector3d, 3>;

class DepthBuffer {
 public:
  // The nearest depth (camera z) of `triangles` at every pixel of `camera`'s pinhole image,
  // with a margin of a quarter of the image on each side (a lens may show more than the
  // pinhole's frame). Triangles are clipped at the near plane.
  DepthBuffer(const Camera& camera, const std::vector<WorldTriangle>& triangles);

  // Whether a point given in the camera's frame is in front of every surface around its
  // pixel. Hidden where the nearest surface of the 3×3 pixels about it lies further in front
  // than the depths of those pixels spread (a face seen at a grazing angle, a concave crease),
  // plus a thousandth of its depth; points outside the buffer count as seen.
  bool Visible(const Eigen::Vector3d& x_cam) const;

 private:
  void Rasterise(const std::array<Eigen::Vector3d, 3>& cam);
  float At(int x, int y) const { return depth_[size_t(y) * size_t(width_) + size_t(x)]; }

  Eigen::Matrix3d K_;
  int margin_x_ = 0, margin_y_ = 0, width_ = 0, height_ = 0;
  std::vector<float> depth_;  // +inf where no triangle is
};

}  // namespace vkr
