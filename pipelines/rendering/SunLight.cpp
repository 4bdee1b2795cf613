#include "pipelines/rendering/SunLight.h"

#include <cmath>
#include <string>

#include "engine/vk/Commands.h"

namespace vkr {

Eigen::Vector3d SunLight::ToSun() const {
  const double a = azimuth_deg * M_PI / 180.0, e = elevation_deg * M_PI / 180.0;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

bool SunLight::IsValid(std::string* why) const {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (!std::isfinite(azimuth_deg)) return fail("the sun's azimuth must be finite");
  if (!(elevation_deg > 0.0 && elevation_deg <= 90.0)) return fail("the sun's elevation must be in (0, 90] degrees");
  if (!(ambient >= 0.0 && ambient <= 1.0)) return fail("ambient must be in [0, 1]");
  return true;
}

Eigen::Matrix4d ShadowFromWorld(const Eigen::Vector3d& to_sun, const Eigen::AlignedBox3d& bounds) {
  // Light frame: z along the rays (away from the sun), x and y across them.
  const Eigen::Vector3d z = -to_sun.normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d light_from_world;
  light_from_world.row(0) = x;
  light_from_world.row(1) = y;
  light_from_world.row(2) = z;
  Eigen::AlignedBox3d box;  // the scene's corners in the light frame
  for (int corner = 0; corner < 8; ++corner)
    box.extend(light_from_world * bounds.corner(Eigen::AlignedBox3d::CornerType(corner)));
  const Eigen::Vector3d centre = box.center(), half = 0.5 * box.sizes() * 1.01 + Eigen::Vector3d::Constant(1e-3);
  // x, y → [-1, 1]; depth → [0, 1], 1 nearest the sun.
  Eigen::Matrix4d clip_from_light = Eigen::Matrix4d::Zero();
  clip_from_light(0, 0) = 1.0 / half.x();
  clip_from_light(0, 3) = -centre.x() / half.x();
  clip_from_light(1, 1) = 1.0 / half.y();
  clip_from_light(1, 3) = -centre.y() / half.y();
  clip_from_light(2, 2) = -0.5 / half.z();
  clip_from_light(2, 3) = 0.5 + 0.5 * centre.z() / half.z();
  clip_from_light(3, 3) = 1.0;
  Eigen::Matrix4d light = Eigen::Matrix4d::Identity();
  light.topLeftCorner<3, 3>() = light_from_world;
  return clip_from_light * light;
}

SunShadow::SunShadow(vk::Device& device, const GpuScene& scene)
    : scene_(&scene),
      map_(device, {kSize, kSize, 1, DepthPass::kFormat,
                    VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}),
      depth_pass_(device, scene) {}

SunLighting SunShadow::Render(vk::CommandContext& context, const SunLight& sun, const Eigen::AlignedBox3d& bounds,
                              int slot) {
  SunLighting lighting;
  lighting.to_sun = sun.ToSun();
  lighting.ambient = sun.ambient;
  lighting.strength = 1.0 - sun.ambient;
  lighting.shadow_from_world = ShadowFromWorld(lighting.to_sun, bounds);
  lighting.texel = 1.0 / kSize;
  // About two texels of depth across the map's depth range, scaled up on grazing faces by
  // the shader: enough against self-shadowing (acne), small against the scene's sizes.
  const double depth_per_metre = lighting.shadow_from_world.row(2).head<3>().norm();
  const double texel_metres = 2.0 / lighting.shadow_from_world.row(0).head<3>().norm() / kSize;
  lighting.depth_bias = 2.0 * texel_metres * depth_per_metre;
  VkCommandBuffer cmd = context.Begin();
  vk::ImageBarrier(cmd, map_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, 0,
                   VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
  depth_pass_.record(cmd, lighting.shadow_from_world, slot, map_);
  vk::ImageBarrier(cmd, map_, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                   VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                   VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  context.SubmitAndWait();
  return lighting;
}

}  // namespace vkr
