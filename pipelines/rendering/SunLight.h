#pragma once
// A sun for `synth`: its direction, the orthographic shadow map of the scene seen from it
// (a depth pass), and the SunLighting the novel-view pass shades with. Photographs show
// shading and cast shadows; reference images without them test a likelihood only on what
// real photographs never are.

#include <Eigen/Geometry>
#include <string>

#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/DepthPass.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/NovelViewPass.h"

namespace vkr {

struct SunLight {
  double azimuth_deg = 135.0;   // compass angle of the sun, from +x towards +y
  double elevation_deg = 50.0;  // above the horizon, (0, 90]
  double ambient = 0.3;         // sky light on every face; the sun adds 1 − ambient at most

  Eigen::Vector3d ToSun() const;  // unit vector
  bool IsValid(std::string* why) const;
};

// World → the shadow map's clip space: an orthographic view along the sun's rays framing
// `bounds` (the whole scene), reversed depth (nearer the sun is larger, like Projection.h).
Eigen::Matrix4d ShadowFromWorld(const Eigen::Vector3d& to_sun, const Eigen::AlignedBox3d& bounds);

class SunShadow {
 public:
  static constexpr uint32_t kSize = 2048;  // texels per side of the shadow map

  SunShadow(vk::Device& device, const GpuScene& scene);

  // Draws node-matrix slot `slot` of the scene (which must lie within `bounds`) from the sun
  // and returns the lighting that reads the result; map() is then in DEPTH_READ_ONLY_OPTIMAL.
  SunLighting Render(vk::CommandContext& context, const SunLight& sun, const Eigen::AlignedBox3d& bounds,
                     int slot = 0);
  const vk::GpuImage& map() const { return map_; }

 private:
  const GpuScene* scene_;
  vk::GpuImage map_;
  DepthPass depth_pass_;
};

}  // namespace vkr
