#pragma once
// The boilerplate every pass shares: graphics pipelines for dynamic rendering over the
// scene's vertex layout, compute pipelines, and descriptor sets written once at creation.

#include <vulkan/vulkan.h>

#include <optional>
#include <vector>

#include "engine/vk/Resources.h"

namespace vkr {

struct GraphicsPipelineDesc {
  VkShaderModule vertex = VK_NULL_HANDLE;
  VkShaderModule fragment = VK_NULL_HANDLE;  // null for depth-only passes
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<VkFormat> colour_formats;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_GREATER;  // reversed depth (Projection.h)
  VkCullModeFlags cull = VK_CULL_MODE_NONE;
  // Which GpuVertex attributes the vertex shader reads, one bit per location
  // (0 position, 1 normal, 2 atlas_uv, 3 node, 4 face): declaring one a shader does not
  // consume draws a validation warning.
  uint32_t vertex_attributes = 0b11111;
  // The fragment shader's uint specialisation constants 0, 1, … (e.g. a feature switched off
  // at compile time, so a pipeline without it pays nothing for it).
  std::vector<uint32_t> fragment_constants;
};

// Vertex input is GpuVertex (SceneGeometry.h); viewport and scissor are dynamic.
vk::Pipeline CreateGraphicsPipeline(const vk::Device& device, const GraphicsPipelineDesc& desc);
vk::Pipeline CreateComputePipeline(const vk::Device& device, VkShaderModule shader,
                                   VkPipelineLayout layout);

// A compute pipeline whose workgroup is exactly one full subgroup of the device's default
// size: the shader declares local_size_x_id = 0 (set here to that size) and local size 1 in
// y and z, and may sum across its workgroup with subgroup operations alone. `constants`
// become the uint specialisation constants 1, 2, … (e.g. a loop count the driver can unroll).
vk::Pipeline CreateSubgroupComputePipeline(const vk::Device& device, VkShaderModule shader,
                                           VkPipelineLayout layout, const std::vector<uint32_t>& constants = {});

vk::DescriptorSetLayout CreateDescriptorSetLayout(
    const vk::Device& device, const std::vector<VkDescriptorSetLayoutBinding>& bindings);
vk::PipelineLayout CreatePipelineLayout(const vk::Device& device, VkDescriptorSetLayout set_layout,
                                        uint32_t push_constant_bytes, VkShaderStageFlags push_stages);

// A pool sized for `sets` copies of `bindings`, and those sets allocated from it.
struct DescriptorSets {
  vk::DescriptorPool pool;
  std::vector<VkDescriptorSet> sets;
};
DescriptorSets AllocateDescriptorSets(const vk::Device& device, VkDescriptorSetLayout layout,
                                      const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                      uint32_t sets = 1);
void WriteStorageBuffer(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                        const vk::Buffer& buffer);
void WriteUniformBuffer(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                        const vk::Buffer& buffer);
// `element`: the index within an arrayed binding.
void WriteSampledImage(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                       VkImageView view, VkSampler sampler, VkImageLayout layout, uint32_t element = 0);

// A storage image in GENERAL layout.
void WriteStorageImage(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkImageView view);

void SetViewport(VkCommandBuffer cmd, uint32_t width, uint32_t height);

// Begins dynamic rendering over [0,width)×[0,height) into an optional colour view (cleared
// to `clear`, or left as it was, undefined, without one) and an optional depth view
// (cleared to 0, the far end of reversed depth), and sets viewport and scissor to the same
// rectangle.
void BeginRendering(VkCommandBuffer cmd, uint32_t width, uint32_t height, VkImageView colour,
                    std::optional<VkClearColorValue> clear, VkImageView depth);

}  // namespace vkr
