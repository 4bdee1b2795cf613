#include "pipelines/passes/NovelViewPass.h"

#include <cstring>

#include "pipelines/passes/PipelineBuilder.h"
#include "pipelines/passes/Projection.h"
#include "shaders/novel_view_frag.h"
#include "shaders/novel_view_vert.h"

namespace vkr {
namespace {

// Mirrors shaders_glsl/novel_view_push.glsl.
struct NovelViewPush {
  float clip_from_world[16];
  uint32_t node_offset;
  uint32_t mode;
};

// Mirrors the Lighting block of shaders_glsl/novel_view.frag (std140).
struct LightingBlock {
  float shadow_from_world[16];
  float to_sun[4];  // xyz, strength
  float params[4];  // ambient, depth bias, texel
};

constexpr VkFormat kColourFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

}  // namespace

ViewTarget::ViewTarget(vk::Device& device, uint32_t width, uint32_t height)
    : colour(device, {width, height, 1, kColourFormat,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT}),
      depth(device, {width, height, 1, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT}) {}

NovelViewPass::NovelViewPass(vk::Device& device, const GpuScene& scene, const vk::GpuImage& atlas)
    : device_(&device),
      scene_(&scene),
      sampler_(vk::CreateLinearClampSampler(device)),
      nearest_(vk::CreateNearestClampSampler(device)),
      lighting_(device, sizeof(LightingBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::Upload),
      no_shadow_(device, {1, 1, 1, kDepthFormat,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT}) {
  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {3, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
  };
  set_layout_ = CreateDescriptorSetLayout(device, bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(NovelViewPush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, bindings);
  pool_ = std::move(sets.pool);
  set_ = sets.sets[0];
  WriteStorageBuffer(device, set_, 0, scene.node_matrices());
  WriteSampledImage(device, set_, 1, atlas.view(), sampler_, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  std::memset(lighting_.mapped(), 0, sizeof(LightingBlock));
  WriteUniformBuffer(device, set_, 3, lighting_);
  {  // Until a sun is set, binding 2 holds a valid (never read) shadow map.
    vk::CommandContext context(device);
    VkCommandBuffer cmd = context.Begin();
    vk::ImageBarrier(cmd, no_shadow_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    context.SubmitAndWait();
  }
  WriteSampledImage(device, set_, 2, no_shadow_.view(), nearest_, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);

  const vk::ShaderModule vert = vk::CreateShaderModule(device, kNovelViewVert, sizeof(kNovelViewVert));
  const vk::ShaderModule frag = vk::CreateShaderModule(device, kNovelViewFrag, sizeof(kNovelViewFrag));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.layout = layout_;
  desc.colour_formats = {kColourFormat};
  desc.depth_format = kDepthFormat;
  desc.vertex_attributes = 0b01111;  // position, normal, atlas_uv, node
  pipeline_ = CreateGraphicsPipeline(device, desc);
}

void NovelViewPass::SetSunLighting(const SunLighting& lighting, const vk::GpuImage& shadow_map) {
  LightingBlock block{};
  const Eigen::Matrix4f m = lighting.shadow_from_world.cast<float>();
  std::memcpy(block.shadow_from_world, m.data(), sizeof(block.shadow_from_world));
  const Eigen::Vector3d to_sun = lighting.to_sun.normalized();
  for (int k = 0; k < 3; ++k) block.to_sun[k] = float(to_sun[k]);
  block.to_sun[3] = float(lighting.strength);
  block.params[0] = float(lighting.ambient);
  block.params[1] = float(lighting.depth_bias);
  block.params[2] = float(lighting.texel);
  std::memcpy(lighting_.mapped(), &block, sizeof(block));
  WriteSampledImage(*device_, set_, 2, shadow_map.view(), nearest_, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
}

void NovelViewPass::record(VkCommandBuffer cmd, const Camera& camera, int slot, Output output,
                           ViewTarget& target) const {
  const uint32_t w = target.colour.info().width, h = target.colour.info().height;
  vk::ImageBarrier(cmd, target.colour, VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  vk::ImageBarrier(cmd, target.depth, VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0,
                   VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                   VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                       VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);

  VkRenderingAttachmentInfo colour{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  colour.imageView = target.colour.view();
  colour.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  colour.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  colour.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = target.depth.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  depth.clearValue.depthStencil = {0.0f, 0};  // reversed depth: 0 is infinitely far
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {w, h}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = 1;
  ri.pColorAttachments = &colour;
  ri.pDepthAttachment = &depth;

  NovelViewPush push{};
  const Eigen::Matrix4f clip = ClipFromWorld(camera).cast<float>();
  std::memcpy(push.clip_from_world, clip.data(), sizeof(push.clip_from_world));
  push.node_offset = scene_->node_offset(slot);
  push.mode = uint32_t(output);

  vkCmdBeginRendering(cmd, &ri);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(NovelViewPush), &push);
  SetViewport(cmd, w, h);
  scene_->Bind(cmd);
  vkCmdDrawIndexed(cmd, scene_->index_count(), 1, 0, 0, 0);
  vkCmdEndRendering(cmd);

  vk::ImageBarrier(cmd, target.colour, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                   VK_ACCESS_2_TRANSFER_READ_BIT);
}

Image NovelViewPass::Render(vk::Transfer& transfer, vk::CommandContext& context,
                            const Camera& camera, int slot, Output output) {
  if (!target_ || target_->colour.info().width != uint32_t(camera.width) ||
      target_->colour.info().height != uint32_t(camera.height))
    target_ = std::make_unique<ViewTarget>(*device_, camera.width, camera.height);
  VkCommandBuffer cmd = context.Begin();
  record(cmd, camera, slot, output, *target_);
  context.SubmitAndWait();
  Image image(camera.width, camera.height);
  transfer.ReadImage(target_->colour, 0, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.rgba.data());
  return image;
}

}  // namespace vkr
