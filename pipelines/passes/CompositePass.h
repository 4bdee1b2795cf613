#pragma once
// Composite + deviation pass (thesis §6; docs/internals/LIKELIHOOD.md, "Passes, per hypothesis")
// and the final reduction: per hypothesis one ReducedScalars in host-visible memory, summed in a
// fixed order so that a hypothesis evaluates bit-identically wherever it sits in a batch.

#include <vector>

#include "engine/geometry/Atlas.h"
#include "engine/vk/Resources.h"
#include "pipelines/model/Evaluation.h"
#include "pipelines/model/Photometric.h"
#include "pipelines/passes/ReducePass.h"

namespace vkr {

class CompositePass {
 public:
  // What a hypothesis composites: `views`, the view-texture array (ViewTexturePass::kFormat),
  // and `mask`, the R32_UINT interior mask; both of side `layout.size` (level 0) and in
  // GENERAL layout when recorded.
  struct Inputs {
    const vk::GpuImage* views = nullptr;
    const vk::GpuImage* mask = nullptr;
  };
  // `inputs`: one set, or one per hypothesis slot (SlotImages), all with the same number of
  // views. Only the workgroup tiles that touch a chart of `layout` are composited, at each
  // of `levels` levels: texels off the charts are no surface and add nothing.
  CompositePass(vk::Device& device, const std::vector<Inputs>& inputs, const AtlasLayout& layout, int levels,
                int max_batch);

  // The per-camera colour correction of the next recordings' submissions (host-visible
  // memory: call between submissions).
  void SetPhotometric(const PhotometricCorrection& correction);

  // Composites slot `slot` over the chart tiles of the level whose atlas side is
  // `level_size` with the noise model of `model` (σ, δ, K)
  // and writes its per-workgroup partial sums; with `write_images`, also the composite,
  // deviation and noise images (for dumps).
  // `inputs`: which of the constructor's input sets it reads.
  void record(VkCommandBuffer cmd, int slot, int inputs, uint32_t level_size, const LikelihoodModel& model,
              bool write_images) const;
  // Sums the partials of slots [0, batch) into the results; makes them visible to the host.
  void record_reduce(VkCommandBuffer cmd, int batch, uint32_t level_size) const;

  // After the submission completed.
  ReducedScalars Result(int slot) const;

  // Texels the composite visits at the level of side `level_size` (for the bench).
  uint64_t TexelsVisited(uint32_t level_size) const;

  // The workgroup tiles (`lanes` × 16 texels) of the level-`level` atlas that touch a chart
  // of `layout`, as (x, y) tile pairs in row-major order.
  static std::vector<uint32_t> ChartTiles(const AtlasLayout& layout, int level, uint32_t lanes);

  // rgb: consensus colour, a: views; r: χ_t, g: d_t, b: interior, a: surface; and r: the
  // share of the noise variance the image texture makes (weighted over views), g: outlier
  // views, b: views, a: surface.
  const vk::GpuImage& composite() const { return composite_; }
  const vk::GpuImage& deviation() const { return deviation_; }
  const vk::GpuImage& noise() const { return noise_; }

 private:
  CompositePass(vk::Device& device, const std::vector<Inputs>& inputs,
                const std::vector<std::vector<uint32_t>>& tiles, int max_batch);
  int Level(uint32_t level_size) const;

  uint32_t view_count_;
  uint32_t lanes_;  // the device's subgroup size: one workgroup's width
  uint32_t atlas_size_;
  // Per level: the first tile in tiles_ and how many (a tile: lanes_ × 16 texels, one
  // workgroup), in row-major order so the partial sums add up as before.
  std::vector<uint32_t> tile_offset_, tile_count_;
  vk::Buffer tiles_;
  ReducePass reduce_;
  vk::Buffer photometric_;  // per view: gain (xyz, their mean in w), offset (xyz)
  vk::GpuImage composite_, deviation_, noise_;
  vk::DescriptorSetLayout composite_set_layout_;
  vk::PipelineLayout composite_layout_;
  vk::DescriptorPool composite_pool_;
  std::vector<VkDescriptorSet> composite_sets_;  // one per input set
  // The same shader with and without the dump images' stores (composite.comp kWriteImages).
  vk::Pipeline composite_pipeline_, dump_pipeline_;
};

}  // namespace vkr
