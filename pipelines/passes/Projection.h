#pragma once
// From an OpenCV-convention camera to Vulkan clip space.
//
// Pixel u = fx·x/z + s·y/z + cx over an image spanning [0,W]; Vulkan's NDC x = 2u/W − 1 and,
// since both image y and Vulkan's framebuffer y point down, y_ndc = 2v/H − 1 with no flip.
// Rasterisation samples pixel centres at (i+0.5, j+0.5), exactly the COLMAP convention of
// docs/guide/SCENE_FORMAT.md ("cameras"). Depth is reversed with an infinite far plane:
// z_ndc = near / z, so float depth keeps its precision far away and the near plane at z = near is
// the only clip plane in depth.

#include <Eigen/Core>

#include "engine/scene/Scene.h"

namespace vkr {

constexpr double kDefaultNear = 0.01;  // metres

Eigen::Matrix4d ClipFromCamera(const Eigen::Matrix3d& K, int width, int height,
                               double near = kDefaultNear);
inline Eigen::Matrix4d ClipFromWorld(const Camera& camera, double near = kDefaultNear) {
  return ClipFromCamera(camera.K, camera.width, camera.height, near) * camera.cam_from_world;
}

}  // namespace vkr
