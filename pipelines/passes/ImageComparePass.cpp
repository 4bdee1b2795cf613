#include "pipelines/passes/ImageComparePass.h"

#include <algorithm>
#include <stdexcept>

#include "engine/vk/Commands.h"
#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/image_compare_comp.h"

namespace vkr {
namespace {

struct ImageComparePush {
  uint32_t size_offset, partial_offset;
  float sigma2;
};

constexpr uint32_t kCompareRows = 16;  // image_compare.comp's pixels per invocation (a column)

VkDescriptorSetLayoutBinding CompareBinding(uint32_t b, VkDescriptorType type) {
  return {b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
}

}  // namespace

ImageComparePass::ImageComparePass(vk::Device& device, const vk::GpuImage& results,
                                   const std::vector<std::vector<VkExtent2D>>& layer_sizes, int max_batch)
    : layer_count_(results.info().layers), lanes_(device.subgroup_size()) {
  if (layer_sizes.empty()) throw std::invalid_argument("ImageComparePass: no levels");
  std::vector<uint32_t> sizes;
  for (const std::vector<VkExtent2D>& level : layer_sizes) {
    if (level.size() != layer_count_) throw std::invalid_argument("ImageComparePass: one size per layer and level");
    VkExtent2D largest{0, 0};
    for (const VkExtent2D& e : level) {
      largest.width = std::max(largest.width, e.width);
      largest.height = std::max(largest.height, e.height);
      sizes.push_back(e.width);
      sizes.push_back(e.height);
    }
    level_extent_.push_back(largest);
  }
  const VkExtent2D groups = Groups(0);
  reduce_ = std::make_unique<ReducePass>(device, max_batch, groups.width * groups.height);
  sizes_ = vk::Buffer(device, sizes.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Upload);
  std::copy(sizes.begin(), sizes.end(), sizes_.data<uint32_t>());

  const std::vector<VkDescriptorSetLayoutBinding> compare_bindings = {
      CompareBinding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), CompareBinding(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
      CompareBinding(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)};
  compare_set_layout_ = CreateDescriptorSetLayout(device, compare_bindings);
  compare_layout_ =
      CreatePipelineLayout(device, compare_set_layout_, sizeof(ImageComparePush), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets cs = AllocateDescriptorSets(device, compare_set_layout_, compare_bindings);
  compare_pool_ = std::move(cs.pool);
  compare_set_ = cs.sets[0];
  WriteStorageImage(device, compare_set_, 0, results.view());
  WriteStorageBuffer(device, compare_set_, 1, sizes_);
  WriteStorageBuffer(device, compare_set_, 2, reduce_->partials());


  const vk::ShaderModule compare = vk::CreateShaderModule(device, kImageCompareComp, sizeof(kImageCompareComp));
  compare_pipeline_ = CreateSubgroupComputePipeline(device, compare, compare_layout_, {layer_count_});
}

VkExtent2D ImageComparePass::Groups(int level) const {
  const VkExtent2D e = level_extent_.at(size_t(level));
  // A workgroup is one subgroup of `lanes_` invocations side by side, each summing a column.
  return {(e.width + lanes_ - 1) / lanes_, (e.height + kCompareRows - 1) / kCompareRows};
}

void ImageComparePass::record(VkCommandBuffer cmd, int slot, int level, double sigma_255) const {
  const double sigma = sigma_255 / 255.0;
  const ImageComparePush push{uint32_t(level) * layer_count_, uint32_t(slot) * reduce_->partial_stride(),
                         float(sigma * sigma)};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compare_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compare_layout_, 0, 1, &compare_set_, 0, nullptr);
  vkCmdPushConstants(cmd, compare_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  const VkExtent2D groups = Groups(level);
  vkCmdDispatch(cmd, groups.width, groups.height, 1);
}

void ImageComparePass::record_reduce(VkCommandBuffer cmd, int batch, int level) const {
  const VkExtent2D groups = Groups(level);
  reduce_->record(cmd, batch, groups.width * groups.height);
}

ReducedScalars ImageComparePass::Result(int slot) const { return reduce_->Result(slot); }

}  // namespace vkr
