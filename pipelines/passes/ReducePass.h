#pragma once
// The second level of every likelihood's reduction: per hypothesis, the per-workgroup partial
// sums a first-level pass wrote (composite.comp, image_compare.comp) summed in a fixed order
// into one ReducedScalars in host-visible memory, so that a hypothesis evaluates
// bit-identically wherever it sits in a batch.

#include "engine/vk/Resources.h"
#include "pipelines/model/Evaluation.h"

namespace vkr {

class ReducePass {
 public:
  // Room for `max_batch` hypotheses of `partial_stride` partials each.
  ReducePass(vk::Device& device, int max_batch, uint32_t partial_stride);

  // Where first-level passes write: slot k's partials start at k · partial_stride().
  const vk::Buffer& partials() const { return partials_; }
  uint32_t partial_stride() const { return partial_stride_; }

  // Sums `partial_count` partials of each of slots [0, batch); orders the first-level writes
  // before and makes the results visible to the host after.
  void record(VkCommandBuffer cmd, int batch, uint32_t partial_count) const;
  // After the submission completed.
  ReducedScalars Result(int slot) const;

 private:
  uint32_t partial_stride_;
  vk::Buffer partials_, results_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Pipeline pipeline_;
};

}  // namespace vkr
