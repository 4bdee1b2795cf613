#include "pipelines/passes/ReducePass.h"

#include "engine/vk/Commands.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/reduce_comp.h"

namespace vkr {
namespace {

// Mirrors `Scalars` in shaders_glsl/scalars.glsl (std430).
struct GpuScalars {
  float sum_squares, dof, unverified, pad_float;
  uint32_t seen_multi, seen_once, seen_none, interior, views, outlier_views, masked, pad1;
};
static_assert(sizeof(GpuScalars) == 48);

struct ReducePush {
  uint32_t partial_stride, partial_count;
};

}  // namespace

ReducePass::ReducePass(vk::Device& device, int max_batch, uint32_t partial_stride)
    : partial_stride_(partial_stride),
      partials_(device, VkDeviceSize(max_batch) * partial_stride * sizeof(GpuScalars),
                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Device),
      results_(device, VkDeviceSize(max_batch) * sizeof(GpuScalars), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               vk::MemoryUse::Readback) {
  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr}};
  set_layout_ = CreateDescriptorSetLayout(device, bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(ReducePush), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, bindings);
  pool_ = std::move(sets.pool);
  set_ = sets.sets[0];
  WriteStorageBuffer(device, set_, 0, partials_);
  WriteStorageBuffer(device, set_, 1, results_);
  const vk::ShaderModule shader = vk::CreateShaderModule(device, kReduceComp, sizeof(kReduceComp));
  pipeline_ = CreateComputePipeline(device, shader, layout_);
}

void ReducePass::record(VkCommandBuffer cmd, int batch, uint32_t partial_count) const {
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  const ReducePush push{partial_stride_, partial_count};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, uint32_t(batch), 1, 1);
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

ReducedScalars ReducePass::Result(int slot) const {
  const GpuScalars& g = results_.data<GpuScalars>()[slot];
  ReducedScalars r;
  r.sum_squares = g.sum_squares;
  r.dof = g.dof;
  r.unverified = g.unverified;
  r.seen_multi = g.seen_multi;
  r.seen_once = g.seen_once;
  r.seen_none = g.seen_none;
  r.interior = g.interior;
  r.views = g.views;
  r.outlier_views = g.outlier_views;
  r.masked = g.masked;
  return r;
}

}  // namespace vkr
