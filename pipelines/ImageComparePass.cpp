#include "pipelines/ImageComparePass.h"

#include <algorithm>
#include <stdexcept>

#include "engine/vk/Commands.h"
#include "pipelines/PipelineBuilder.h"
#include "shaders/image_compare_comp.h"
#include "shaders/reduce_comp.h"

namespace vkr {
namespace {

// Mirrors `Scalars` in shaders_glsl/reduction.glsl (std430).
struct CompareScalars {
  float sum_squares, dof;
  uint32_t seen_multi, seen_once, seen_none, interior, pad0, pad1;
};
static_assert(sizeof(CompareScalars) == 32);

struct ImageComparePush {
  uint32_t pair_count, size_offset, partial_offset;
  float sigma2;
};

struct ImageReducePush {
  uint32_t partial_stride, partial_count;
};

constexpr uint32_t kCompareTile = 16;  // image_compare.comp's local size

VkDescriptorSetLayoutBinding CompareBinding(uint32_t b, VkDescriptorType type) {
  return {b, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
}

}  // namespace

ImageComparePass::ImageComparePass(vk::Device& device, const vk::GpuImage& results,
                                   const std::vector<std::vector<VkExtent2D>>& pair_sizes, int max_batch)
    : pair_count_(results.info().layers) {
  if (pair_sizes.empty()) throw std::invalid_argument("ImageComparePass: no levels");
  std::vector<uint32_t> sizes;
  for (const std::vector<VkExtent2D>& level : pair_sizes) {
    if (level.size() != pair_count_) throw std::invalid_argument("ImageComparePass: one size per pair and level");
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
  partial_stride_ = groups.width * groups.height;
  sizes_ = vk::Buffer(device, sizes.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Upload);
  std::copy(sizes.begin(), sizes.end(), sizes_.data<uint32_t>());
  partials_ = vk::Buffer(device, VkDeviceSize(max_batch) * partial_stride_ * sizeof(CompareScalars),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Device);
  results_ = vk::Buffer(device, VkDeviceSize(max_batch) * sizeof(CompareScalars), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        vk::MemoryUse::Readback);

  const std::vector<VkDescriptorSetLayoutBinding> compare_bindings = {
      CompareBinding(0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE), CompareBinding(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER),
      CompareBinding(2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)};
  compare_set_layout_ = CreateDescriptorSetLayout(device, compare_bindings);
  compare_layout_ =
      CreatePipelineLayout(device, compare_set_layout_, sizeof(ImageComparePush), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets cs = AllocateDescriptorSets(device, compare_set_layout_, compare_bindings);
  compare_pool_ = std::move(cs.pool);
  compare_set_ = cs.sets[0];
  {
    VkDescriptorImageInfo info{VK_NULL_HANDLE, results.view(), VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = compare_set_;
    w.dstBinding = 0;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    w.pImageInfo = &info;
    vkUpdateDescriptorSets(device.handle(), 1, &w, 0, nullptr);
  }
  WriteStorageBuffer(device, compare_set_, 1, sizes_);
  WriteStorageBuffer(device, compare_set_, 2, partials_);

  const std::vector<VkDescriptorSetLayoutBinding> reduce_bindings = {
      CompareBinding(0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER), CompareBinding(1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)};
  reduce_set_layout_ = CreateDescriptorSetLayout(device, reduce_bindings);
  reduce_layout_ = CreatePipelineLayout(device, reduce_set_layout_, sizeof(ImageReducePush), VK_SHADER_STAGE_COMPUTE_BIT);
  DescriptorSets rs = AllocateDescriptorSets(device, reduce_set_layout_, reduce_bindings);
  reduce_pool_ = std::move(rs.pool);
  reduce_set_ = rs.sets[0];
  WriteStorageBuffer(device, reduce_set_, 0, partials_);
  WriteStorageBuffer(device, reduce_set_, 1, results_);

  const vk::ShaderModule compare = vk::CreateShaderModule(device, kImageCompareComp, sizeof(kImageCompareComp));
  const vk::ShaderModule reduce = vk::CreateShaderModule(device, kReduceComp, sizeof(kReduceComp));
  compare_pipeline_ = CreateComputePipeline(device, compare, compare_layout_);
  reduce_pipeline_ = CreateComputePipeline(device, reduce, reduce_layout_);
}

VkExtent2D ImageComparePass::Groups(int level) const {
  const VkExtent2D e = level_extent_.at(size_t(level));
  return {(e.width + kCompareTile - 1) / kCompareTile, (e.height + kCompareTile - 1) / kCompareTile};
}

void ImageComparePass::record(VkCommandBuffer cmd, int slot, int level, double sigma_255) const {
  const double sigma = sigma_255 / 255.0;
  const ImageComparePush push{pair_count_, uint32_t(level) * pair_count_, uint32_t(slot) * partial_stride_,
                         float(sigma * sigma)};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compare_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, compare_layout_, 0, 1, &compare_set_, 0, nullptr);
  vkCmdPushConstants(cmd, compare_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  const VkExtent2D groups = Groups(level);
  vkCmdDispatch(cmd, groups.width, groups.height, 1);
}

void ImageComparePass::record_reduce(VkCommandBuffer cmd, int batch, int level) const {
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  const VkExtent2D groups = Groups(level);
  const ImageReducePush push{partial_stride_, groups.width * groups.height};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_layout_, 0, 1, &reduce_set_, 0, nullptr);
  vkCmdPushConstants(cmd, reduce_layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cmd, uint32_t(batch), 1, 1);
  vk::MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

ReducedScalars ImageComparePass::Result(int slot) const {
  const CompareScalars& g = results_.data<CompareScalars>()[slot];
  ReducedScalars r;
  r.sum_squares = g.sum_squares;
  r.dof = g.dof;
  r.seen_multi = g.seen_multi;
  r.seen_once = g.seen_once;
  r.seen_none = g.seen_none;
  r.interior = g.interior;
  return r;
}

}  // namespace vkr
