#pragma once
// Composite + deviation pass (thesis §6, DESIGN.md steps 3–4) and the final reduction: per
// hypothesis one ReducedScalars in host-visible memory, summed in a fixed order so that a
// hypothesis evaluates bit-identically wherever it sits in a batch.

#include "engine/vk/Resources.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/model/Photometric.h"
#include "pipelines/passes/ReducePass.h"

namespace vkr {

class CompositePass {
 public:
  // `views`: the view-texture array (ViewTexturePass::kFormat); `mask`: the R32_UINT interior
  // mask; both of side `atlas_size` (level 0) and in GENERAL layout when recorded.
  CompositePass(vk::Device& device, const vk::GpuImage& views, const vk::GpuImage& mask,
                int max_batch);

  // The per-camera colour correction of the next recordings' submissions (host-visible
  // memory: call between submissions).
  void SetPhotometric(const PhotometricCorrection& correction);

  // Composites slot `slot` over [0, level_size)² with the noise model of `model` (σ, δ, K)
  // and writes its per-workgroup partial sums; with `write_images`, also the composite,
  // deviation and noise images (for dumps).
  void record(VkCommandBuffer cmd, int slot, uint32_t level_size, const LikelihoodModel& model,
              bool write_images) const;
  // Sums the partials of slots [0, batch) into the results; makes them visible to the host.
  void record_reduce(VkCommandBuffer cmd, int batch, uint32_t level_size) const;

  // After the submission completed.
  ReducedScalars Result(int slot) const;

  // rgb: consensus colour, a: views; r: χ_t, g: d_t, b: interior, a: surface; and r: the
  // share of the noise variance the image texture makes (weighted over views), g: outlier
  // views, b: views, a: surface.
  const vk::GpuImage& composite() const { return composite_; }
  const vk::GpuImage& deviation() const { return deviation_; }
  const vk::GpuImage& noise() const { return noise_; }

 private:
  VkExtent2D Groups(uint32_t level_size) const;
  uint32_t GroupCount(uint32_t level_size) const;

  uint32_t view_count_;
  uint32_t lanes_;  // the device's subgroup size: one workgroup's width
  ReducePass reduce_;
  vk::Buffer photometric_;  // per view: gain (xyz, their mean in w), offset (xyz)
  vk::GpuImage composite_, deviation_, noise_;
  vk::DescriptorSetLayout composite_set_layout_;
  vk::PipelineLayout composite_layout_;
  vk::DescriptorPool composite_pool_;
  VkDescriptorSet composite_set_ = VK_NULL_HANDLE;
  vk::Pipeline composite_pipeline_;
};

}  // namespace vkr
