#include "pipelines/InteriorPass.h"

#include <Eigen/LU>

#include "pipelines/PipelineBuilder.h"
#include "shaders/interior_frag.h"
#include "shaders/interior_vert.h"

namespace vkr {
namespace {

struct InteriorPush {
  uint32_t node_offset;
  uint32_t node_count;
};

}  // namespace

InteriorPass::InteriorPass(vk::Device& device, const Scene& scene, const GpuScene& gpu_scene)
    : scene_(&gpu_scene) {
  const int nodes = gpu_scene.node_count();
  node_from_world_ = vk::Buffer(device, VkDeviceSize(gpu_scene.hypothesis_slots()) * nodes * 64,
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload);
  kinds_ = vk::Buffer(device, VkDeviceSize(nodes) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Upload);
  for (int n = 0; n < nodes; ++n)
    // The shader's kind codes are PrimitiveKind's order: 0 none, 1 plane … 5 mesh.
    kinds_.data<uint32_t>()[n] = n < int(scene.nodes.size()) ? uint32_t(scene.nodes[n].primitive) : 0u;

  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
  };
  set_layout_ = CreateDescriptorSetLayout(device, bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(InteriorPush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, bindings);
  pool_ = std::move(sets.pool);
  set_ = sets.sets[0];
  WriteStorageBuffer(device, set_, 0, gpu_scene.node_matrices());
  WriteStorageBuffer(device, set_, 1, node_from_world_);
  WriteStorageBuffer(device, set_, 2, kinds_);

  const vk::ShaderModule vert = vk::CreateShaderModule(device, kInteriorVert, sizeof(kInteriorVert));
  const vk::ShaderModule frag = vk::CreateShaderModule(device, kInteriorFrag, sizeof(kInteriorFrag));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.layout = layout_;
  desc.colour_formats = {kFormat};
  desc.vertex_attributes = 0b01101;  // position, atlas_uv, node
  pipeline_ = CreateGraphicsPipeline(device, desc);
}

void InteriorPass::SetNodeMatrices(int slot, const std::vector<Eigen::Matrix4d>& world_from_node) {
  float* dst = node_from_world_.data<float>() + size_t(scene_->node_offset(slot)) * 16;
  for (const Eigen::Matrix4d& m : world_from_node) {
    // A degenerate node (a zero scale) contains nothing: its inverse is replaced by a
    // matrix that sends every point far outside the unit primitives.
    const double det = m.topLeftCorner<3, 3>().determinant();
    Eigen::Matrix4d inverse = std::abs(det) > 1e-15 ? Eigen::Matrix4d(m.inverse()) : Eigen::Matrix4d::Zero();
    if (std::abs(det) <= 1e-15) inverse(0, 3) = 1e9, inverse(3, 3) = 1.0;
    Eigen::Map<Eigen::Matrix4f> out(dst);
    out = inverse.cast<float>();
    dst += 16;
  }
}

void InteriorPass::record(VkCommandBuffer cmd, int slot, const vk::GpuImage& mask,
                          uint32_t atlas_size) const {
  const InteriorPush push{scene_->node_offset(slot), uint32_t(scene_->node_count())};
  BeginRendering(cmd, atlas_size, atlas_size, mask.view(), {{0.0f, 0.0f, 0.0f, 0.0f}}, VK_NULL_HANDLE);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(InteriorPush), &push);
  scene_->Bind(cmd);
  vkCmdDrawIndexed(cmd, scene_->index_count(), 1, 0, 0, 0);
  vkCmdEndRendering(cmd);
}

}  // namespace vkr
