#include "pipelines/passes/DepthPass.h"

#include <cstring>

#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/depth_vert.h"

namespace vkr {
namespace {

struct DepthPush {
  float clip_from_world[16];
  uint32_t node_offset;
};

}  // namespace

DepthPass::DepthPass(vk::Device& device, const GpuScene& scene) : scene_(&scene) {
  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr}};
  set_layout_ = CreateDescriptorSetLayout(device, bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(DepthPush), VK_SHADER_STAGE_VERTEX_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, bindings);
  pool_ = std::move(sets.pool);
  set_ = sets.sets[0];
  WriteStorageBuffer(device, set_, 0, scene.node_matrices());
  const vk::ShaderModule vert = vk::CreateShaderModule(device, kDepthVert, sizeof(kDepthVert));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.layout = layout_;
  desc.depth_format = kFormat;
  desc.vertex_attributes = 0b01001;  // position, node
  pipeline_ = CreateGraphicsPipeline(device, desc);
}

void DepthPass::record(VkCommandBuffer cmd, const Eigen::Matrix4d& clip_from_world, int slot,
                       const vk::GpuImage& depth) const {
  DepthPush push{};
  const Eigen::Matrix4f clip = clip_from_world.cast<float>();
  std::memcpy(push.clip_from_world, clip.data(), sizeof(push.clip_from_world));
  push.node_offset = scene_->node_offset(slot);
  BeginRendering(cmd, depth.info().width, depth.info().height, VK_NULL_HANDLE, std::nullopt, depth.view());
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(DepthPush), &push);
  scene_->Bind(cmd);
  vkCmdDrawIndexed(cmd, scene_->index_count(), 1, 0, 0, 0);
  vkCmdEndRendering(cmd);
}

}  // namespace vkr
