#pragma once
// View-specific texture pass (thesis §5.2–5.5, docs/internals/LIKELIHOOD.md): for camera i,
// rasterise every face in atlas space and write, per texel, the colour r_i shows at the texel's
// projection, a weight (§6.3) and the image's texture there (shaders_glsl/view_texel.glsl), or
// weight 0 where camera i cannot see the texel.

#include <Eigen/Core>
#include <vector>

#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"
#include "pipelines/passes/ViewCulling.h"

namespace vkr {

// One camera as the pass needs it. All of it is at full resolution: normalised image
// coordinates do not depend on the pyramid level, and neither does a texel's footprint in
// pixels (a level halves both the texels and the pixels).
struct ViewCamera {
  Eigen::Matrix4d clip_from_world;
  Eigen::Vector3d centre;
  double fx_fy = 1.0;       // K(0,0)·K(1,1), for the footprint (a texel's area is its chart's: GpuVertex)
  int level = 0;            // pyramid level: the reference is sampled at LOD ≥ level
};

class ViewTexturePass {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_R32G32_UINT;  // view_texel.glsl, ViewTexel.h

  // `bindings`: how many (reference image, depth map, validity) sets will be bound, one per camera
  // and pyramid level. `angle_weights` false: every visible texel weighs 1.
  ViewTexturePass(vk::Device& device, const GpuScene& scene, int bindings, bool angle_weights,
                  double depth_tolerance);

  // Binds pair `index` (once, at creation of the likelihood): `reference` (a mip chain, the
  // image pyramid) in SHADER_READ_ONLY_OPTIMAL, `depth` in DEPTH_READ_ONLY_OPTIMAL when recorded,
  // and `validity` (ReferenceImages.h: the same mips, 1 where comparable) in
  // SHADER_READ_ONLY_OPTIMAL, or VK_NULL_HANDLE where every pixel counts (then a pipeline
  // specialised without the validity read draws it: such cameras cost nothing extra). A
  // texel whose sample touches an invalid pixel gets weight 0.
  void BindImages(int index, VkImageView reference, VkImageView depth, VkImageView validity);

  // Renders into `target` (one layer of the view-texture array, COLOR_ATTACHMENT_OPTIMAL)
  // over [0, atlas_size)²: `draws.shaded` in full, `draws.unseen` as weight 0, `draws.partial`
  // in full inside their rectangles and as weight 0 around them (ViewCulling.h). Texels
  // outside every chart keep whatever they held (undefined) unless `clear` (for dumps)
  // zeroes the layer first.
  void record(VkCommandBuffer cmd, const ViewCamera& camera, const ViewDraws& draws, int binding, int slot,
              VkImageView target, uint32_t atlas_size, bool clear) const;

 private:
  vk::Device* device_;
  const GpuScene* scene_;
  bool angle_weights_;
  double depth_tolerance_;
  vk::Sampler trilinear_, nearest_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  std::vector<VkDescriptorSet> sets_;
  std::vector<bool> checks_validity_;  // per binding: draw with validity_pipeline_
  vk::Pipeline pipeline_, validity_pipeline_, unseen_pipeline_;
};

}  // namespace vkr
