#include "pipelines/passes/CompositePass.h"

#include <cstring>
#include <stdexcept>
#include <string>

#include "engine/vk/Check.h"
#include "engine/vk/Commands.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/composite_comp.h"

namespace vkr {
namespace {

// Mirrors the push constants of shaders_glsl/composite.comp.
struct CompositePush {
  uint32_t size, partial_offset, write_images;
  float sigma2, delta2, outlier;
};

constexpr uint32_t kCompositeRows = 16;  // composite.comp's texels per invocation (a column)

VkDescriptorSetLayoutBinding Binding(uint32_t b, VkDescriptorType type) {
  return {b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
}

}  // namespace

CompositePass::CompositePass(vk::Device& device, const vk::GpuImage& views, const vk::GpuImage& mask,
                             int max_batch)
    : view_count_(views.info().layers),
      lanes_(device.subgroup_size()),
      reduce_(device, max_batch, GroupCount(views.info().width)),
      photometric_(device, VkDeviceSize(views.info().layers) * 8 * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   vk::MemoryUse::Upload) {
  const uint32_t size = views.info().width;
  const VkImageUsageFlags dump_usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  composite_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  deviation_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  noise_ = vk::GpuImage(device, {size, size, 1, VK_FORMAT_R32G32B32A32_SFLOAT, dump_usage});
  SetPhotometric(PhotometricCorrection::Identity(int(view_count_)));

  const std::vector<VkDescriptorSetLayoutBinding> composite_bindings = {
      Binding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), Binding(1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
      Binding(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), Binding(3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
      Binding(4, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), Binding(5, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
      Binding(6, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)};
  composite_set_layout_ = CreateDescriptorSetLayout(device, composite_bindings);
  composite_layout_ = CreatePipelineLayout(device, composite_set_layout_, sizeof(CompositePush),
                                           VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets cs = AllocateDescriptorSets(device, composite_set_layout_, composite_bindings);
  composite_pool_ = std::move(cs.pool);
  composite_set_ = cs.sets[0];
  WriteStorageImage(device, composite_set_, 0, views.view());
  WriteStorageImage(device, composite_set_, 1, mask.view());
  WriteStorageBuffer(device, composite_set_, 2, reduce_.partials());
  WriteStorageImage(device, composite_set_, 3, composite_.view());
  WriteStorageImage(device, composite_set_, 4, deviation_.view());
  WriteStorageBuffer(device, composite_set_, 5, photometric_);
  WriteStorageImage(device, composite_set_, 6, noise_.view());


  const vk::ShaderModule composite = vk::CreateShaderModule(device, kCompositeComp, sizeof(kCompositeComp));
  composite_pipeline_ = CreateSubgroupComputePipeline(device, composite, composite_layout_, {view_count_});

  // The dump images live in GENERAL for the whole run.
  vk::CommandContext context(device);
  VkCommandBuffer cmd = context.Begin();
  for (const vk::GpuImage* image : {&composite_, &deviation_, &noise_})
    vk::ImageBarrier(cmd, *image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                     VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  context.SubmitAndWait();
}

// A workgroup is one subgroup of `lanes` invocations side by side, each summing a column.
VkExtent2D CompositePass::Groups(uint32_t level_size) const {
  return {(level_size + lanes_ - 1) / lanes_, (level_size + kCompositeRows - 1) / kCompositeRows};
}

uint32_t CompositePass::GroupCount(uint32_t level_size) const {
  const VkExtent2D g = Groups(level_size);
  return g.width * g.height;
}

void CompositePass::SetPhotometric(const PhotometricCorrection& correction) {
  if (correction.cameras() != int(view_count_))
    throw std::invalid_argument("CompositePass::SetPhotometric: a correction for " +
                                std::to_string(correction.cameras()) + " cameras, not " + std::to_string(view_count_));
  float* out = photometric_.data<float>();
  for (uint32_t i = 0; i < view_count_; ++i) {
    const auto& g = correction.gain[i];
    const auto& o = correction.offset[i];
    const float values[8] = {float(g[0]), float(g[1]), float(g[2]), float((g[0] + g[1] + g[2]) / 3.0),
                             float(o[0]), float(o[1]), float(o[2]), 0.0f};
    std::memcpy(out + 8 * i, values, sizeof values);
  }
}

void CompositePass::record(VkCommandBuffer cmd, int slot, uint32_t level_size, const LikelihoodModel& model,
                           bool write_images) const {
  const double sigma = model.sigma / 255.0;
  const CompositePush push{level_size,
                           uint32_t(slot) * reduce_.partial_stride(),
                           write_images ? 1u : 0u,
                           float(sigma * sigma),
                           float(model.position_sd * model.position_sd),
                           float(model.outlier_chi2)};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, composite_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, composite_layout_, 0, 1,
                          &composite_set_, 0, nullptr);
  vkCmdPushConstants(cmd, composite_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  const VkExtent2D groups = Groups(level_size);
  vkCmdDispatch(cmd, groups.width, groups.height, 1);
}

void CompositePass::record_reduce(VkCommandBuffer cmd, int batch, uint32_t level_size) const {
  reduce_.record(cmd, batch, GroupCount(level_size));
}

ReducedScalars CompositePass::Result(int slot) const { return reduce_.Result(slot); }

}  // namespace vkr
