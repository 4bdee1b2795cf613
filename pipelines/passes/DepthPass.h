#pragma once
// Depth pass (docs/internals/LIKELIHOOD.md, "Passes, per hypothesis"): the hypothesis seen from one
// camera, depth only (reversed, D32F), read by the view-specific texture pass as a shadow map.

#include <Eigen/Core>

#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"

namespace vkr {

class DepthPass {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_D32_SFLOAT;

  DepthPass(vk::Device& device, const GpuScene& scene);

  // Draws slot `slot`'s hypothesis into `depth` (layout: DEPTH_ATTACHMENT_OPTIMAL on entry
  // and exit) with `clip_from_world` of the camera at the image's size.
  void record(VkCommandBuffer cmd, const Eigen::Matrix4d& clip_from_world, int slot,
              const vk::GpuImage& depth) const;

 private:
  const GpuScene* scene_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Pipeline pipeline_;
};

}  // namespace vkr
