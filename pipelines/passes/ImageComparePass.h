#pragma once
// Reduction of the image-space likelihood (thesis §4.4): per hypothesis, the warp pass's
// result images (one layer per warp draw: per pixel the χ² sum and counts of a target's
// pixel pairs with a group of sources) summed into one ReducedScalars, in a fixed order so
// that a hypothesis evaluates bit-identically wherever it sits in a batch. The first level
// (image_compare.comp) sums over layers per pixel and over a workgroup's pixels; the second
// is the surface likelihood's reduce.comp, reused as it is.

#include <memory>
#include <vector>

#include "engine/vk/Resources.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/passes/ReducePass.h"

namespace vkr {

class ImageComparePass {
 public:
  // `results`: the RGBA32F array of TargetWarpPass results, one layer per warp draw, in
  // GENERAL layout when recorded. `layer_sizes[level][layer]`: the region of each layer its
  // draw wrote at each level (its target's image size at that level).
  ImageComparePass(vk::Device& device, const vk::GpuImage& results,
                   const std::vector<std::vector<VkExtent2D>>& layer_sizes, int max_batch);

  // Reduces slot `slot`'s results at `level` to per-workgroup partial sums.
  void record(VkCommandBuffer cmd, int slot, int level, double sigma_255) const;
  // Sums the partials of slots [0, batch) into the results; makes them visible to the host.
  void record_reduce(VkCommandBuffer cmd, int batch, int level) const;

  // After the submission completed.
  ReducedScalars Result(int slot) const;

 private:
  VkExtent2D Groups(int level) const;

  uint32_t layer_count_;
  uint32_t lanes_;  // the device's subgroup size: one workgroup's width
  std::vector<VkExtent2D> level_extent_;  // the largest layer region per level
  std::unique_ptr<ReducePass> reduce_;    // sized once the level extents are known
  vk::Buffer sizes_;
  vk::DescriptorSetLayout compare_set_layout_;
  vk::PipelineLayout compare_layout_;
  vk::DescriptorPool compare_pool_;
  VkDescriptorSet compare_set_ = VK_NULL_HANDLE;
  vk::Pipeline compare_pipeline_;
};

}  // namespace vkr
