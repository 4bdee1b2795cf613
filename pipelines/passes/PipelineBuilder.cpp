#include "pipelines/passes/PipelineBuilder.h"

#include <cstddef>

#include "engine/geometry/SceneGeometry.h"
#include "engine/vk/Check.h"

namespace vkr {

vk::Pipeline CreateGraphicsPipeline(const vk::Device& device, const GraphicsPipelineDesc& desc) {
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  VkPipelineShaderStageCreateInfo stage{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  stage.pName = "main";
  stage.stage = VK_SHADER_STAGE_VERTEX_BIT;
  stage.module = desc.vertex;
  stages.push_back(stage);
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < desc.fragment_constants.size(); ++i)
    entries.push_back({i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)});
  const VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(),
                                            desc.fragment_constants.size() * sizeof(uint32_t),
                                            desc.fragment_constants.data()};
  if (desc.fragment) {
    stage.stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stage.module = desc.fragment;
    if (!entries.empty()) stage.pSpecializationInfo = &specialization;
    stages.push_back(stage);
  }

  const VkVertexInputBindingDescription binding{0, sizeof(GpuVertex), VK_VERTEX_INPUT_RATE_VERTEX};
  const VkVertexInputAttributeDescription all_attributes[] = {
      {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GpuVertex, position)},
      {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GpuVertex, normal)},
      {2, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(GpuVertex, atlas_uv)},
      {3, 0, VK_FORMAT_R32_UINT, offsetof(GpuVertex, node)},
      {4, 0, VK_FORMAT_R32_UINT, offsetof(GpuVertex, face)},
      {5, 0, VK_FORMAT_R32_SFLOAT, offsetof(GpuVertex, texel_area)},
  };
  std::vector<VkVertexInputAttributeDescription> attributes;
  for (const auto& a : all_attributes)
    if (desc.vertex_attributes & (1u << a.location)) attributes.push_back(a);
  VkPipelineVertexInputStateCreateInfo vertex_input{
      VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertex_input.vertexBindingDescriptionCount = 1;
  vertex_input.pVertexBindingDescriptions = &binding;
  vertex_input.vertexAttributeDescriptionCount = uint32_t(attributes.size());
  vertex_input.pVertexAttributeDescriptions = attributes.data();

  VkPipelineInputAssemblyStateCreateInfo assembly{
      VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{
      VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = desc.cull;
  // Image y points down, so a face seen from outside (counter-clockwise in the world)
  // appears clockwise in framebuffer coordinates.
  raster.frontFace = VK_FRONT_FACE_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{
      VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{
      VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = desc.depth_format != VK_FORMAT_UNDEFINED;
  depth.depthWriteEnable = desc.depth_write;
  depth.depthCompareOp = desc.depth_compare;
  std::vector<VkPipelineColorBlendAttachmentState> blend(desc.colour_formats.size());
  for (auto& b : blend) b.colorWriteMask = 0xF;
  VkPipelineColorBlendStateCreateInfo blending{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blending.attachmentCount = uint32_t(blend.size());
  blending.pAttachments = blend.data();
  const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;

  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = uint32_t(desc.colour_formats.size());
  rendering.pColorAttachmentFormats = desc.colour_formats.data();
  rendering.depthAttachmentFormat = desc.depth_format;

  VkGraphicsPipelineCreateInfo ci{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  ci.pNext = &rendering;
  ci.stageCount = uint32_t(stages.size());
  ci.pStages = stages.data();
  ci.pVertexInputState = &vertex_input;
  ci.pInputAssemblyState = &assembly;
  ci.pViewportState = &viewport;
  ci.pRasterizationState = &raster;
  ci.pMultisampleState = &multisample;
  ci.pDepthStencilState = &depth;
  ci.pColorBlendState = &blending;
  ci.pDynamicState = &dynamic;
  ci.layout = desc.layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateGraphicsPipelines(device.handle(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline));
  return vk::Pipeline(device.handle(), pipeline);
}

vk::Pipeline CreateComputePipeline(const vk::Device& device, VkShaderModule shader,
                                   VkPipelineLayout layout) {
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = shader;
  ci.stage.pName = "main";
  ci.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateComputePipelines(device.handle(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline));
  return vk::Pipeline(device.handle(), pipeline);
}

vk::Pipeline CreateSubgroupComputePipeline(const vk::Device& device, VkShaderModule shader,
                                           VkPipelineLayout layout, const std::vector<uint32_t>& constants) {
  std::vector<uint32_t> values = {device.subgroup_size()};
  values.insert(values.end(), constants.begin(), constants.end());
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t id = 0; id < values.size(); ++id) entries.push_back({id, id * 4, sizeof(uint32_t)});
  const VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(), values.size() * sizeof(uint32_t),
                                            values.data()};
  const uint32_t size = values[0];
  // SPIR-V 1.6 lets the subgroup size vary unless it is required (Device.cpp checks that it
  // can be, or that the device has only one size).
  VkPipelineShaderStageRequiredSubgroupSizeCreateInfo required{
      VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_REQUIRED_SUBGROUP_SIZE_CREATE_INFO};
  required.requiredSubgroupSize = size;
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  if (device.compute_subgroup_size_can_be_required()) ci.stage.pNext = &required;
  ci.stage.flags = VK_PIPELINE_SHADER_STAGE_CREATE_REQUIRE_FULL_SUBGROUPS_BIT;
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = shader;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = &specialization;
  ci.layout = layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VK_CHECK(vkCreateComputePipelines(device.handle(), VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline));
  return vk::Pipeline(device.handle(), pipeline);
}

vk::DescriptorSetLayout CreateDescriptorSetLayout(
    const vk::Device& device, const std::vector<VkDescriptorSetLayoutBinding>& bindings) {
  VkDescriptorSetLayoutCreateInfo ci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  ci.bindingCount = uint32_t(bindings.size());
  ci.pBindings = bindings.data();
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorSetLayout(device.handle(), &ci, nullptr, &layout));
  return vk::DescriptorSetLayout(device.handle(), layout);
}

vk::PipelineLayout CreatePipelineLayout(const vk::Device& device, VkDescriptorSetLayout set_layout,
                                        uint32_t push_constant_bytes, VkShaderStageFlags push_stages) {
  VkPushConstantRange range{push_stages, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  ci.setLayoutCount = set_layout ? 1 : 0;
  ci.pSetLayouts = &set_layout;
  ci.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  ci.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VK_CHECK(vkCreatePipelineLayout(device.handle(), &ci, nullptr, &layout));
  return vk::PipelineLayout(device.handle(), layout);
}

DescriptorSets AllocateDescriptorSets(const vk::Device& device, VkDescriptorSetLayout layout,
                                      const std::vector<VkDescriptorSetLayoutBinding>& bindings,
                                      uint32_t sets) {
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& b : bindings) sizes.push_back({b.descriptorType, b.descriptorCount * sets});
  VkDescriptorPoolCreateInfo pci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pci.maxSets = sets;
  pci.poolSizeCount = uint32_t(sizes.size());
  pci.pPoolSizes = sizes.data();
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateDescriptorPool(device.handle(), &pci, nullptr, &pool));
  DescriptorSets out;
  out.pool = vk::DescriptorPool(device.handle(), pool);
  std::vector<VkDescriptorSetLayout> layouts(sets, layout);
  out.sets.resize(sets);
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pool;
  ai.descriptorSetCount = sets;
  ai.pSetLayouts = layouts.data();
  VK_CHECK(vkAllocateDescriptorSets(device.handle(), &ai, out.sets.data()));
  return out;
}

namespace {

void WriteBuffer(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                 const vk::Buffer& buffer) {
  VkDescriptorBufferInfo info{buffer.handle(), 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pBufferInfo = &info;
  vkUpdateDescriptorSets(device.handle(), 1, &w, 0, nullptr);
}

}  // namespace

void WriteStorageBuffer(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                        const vk::Buffer& buffer) {
  WriteBuffer(device, set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer);
}

void WriteUniformBuffer(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                        const vk::Buffer& buffer) {
  WriteBuffer(device, set, binding, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, buffer);
}

namespace {

void WriteImage(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                const VkDescriptorImageInfo& info, uint32_t element = 0) {
  VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  w.dstSet = set;
  w.dstBinding = binding;
  w.dstArrayElement = element;
  w.descriptorCount = 1;
  w.descriptorType = type;
  w.pImageInfo = &info;
  vkUpdateDescriptorSets(device.handle(), 1, &w, 0, nullptr);
}

}  // namespace

void WriteSampledImage(const vk::Device& device, VkDescriptorSet set, uint32_t binding,
                       VkImageView view, VkSampler sampler, VkImageLayout layout, uint32_t element) {
  WriteImage(device, set, binding, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, {sampler, view, layout}, element);
}

void WriteStorageImage(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkImageView view) {
  WriteImage(device, set, binding, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL});
}

void SetViewport(VkCommandBuffer cmd, uint32_t width, uint32_t height) {
  const VkViewport viewport{0.0f, 0.0f, float(width), float(height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, {width, height}};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

}  // namespace vkr

namespace vkr {

void BeginRendering(VkCommandBuffer cmd, uint32_t width, uint32_t height, VkImageView colour,
                    std::optional<VkClearColorValue> clear, VkImageView depth) {
  VkRenderingAttachmentInfo colour_info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  colour_info.imageView = colour;
  colour_info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  colour_info.loadOp = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  colour_info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  if (clear) colour_info.clearValue.color = *clear;
  VkRenderingAttachmentInfo depth_info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth_info.imageView = depth;
  depth_info.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth_info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth_info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth_info.clearValue.depthStencil = {0.0f, 0};
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {width, height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = colour ? 1 : 0;
  ri.pColorAttachments = colour ? &colour_info : nullptr;
  ri.pDepthAttachment = depth ? &depth_info : nullptr;
  vkCmdBeginRendering(cmd, &ri);
  SetViewport(cmd, width, height);
}

}  // namespace vkr
