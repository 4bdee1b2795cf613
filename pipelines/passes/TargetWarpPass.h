#pragma once
// Image-space warp pass (thesis §4.2–4.3, DESIGN.md "Image-space likelihood"): for an ordered
// camera pair (s, t), render the hypothesis from t, texture it by projecting r_s onto it with
// a shadow-map visibility test from s (the synthetic image s_{s,t}), and write per pixel of t
// the χ² of r_t against s_{s,t} under the noise model of shaders_glsl/image_warp.glsl.
//
// Only the surface t actually sees is shaded: t's depth map (DepthPass) is the pass's
// read-only depth attachment, with a depth-equal test. Output per pixel (R32F): χ² ≥ 0 where
// s sees the surface point too, kNotSeenBySource (−1) where only t does, kNoSurface (−2)
// where t sees none (background, or the back of a face).

#include <Eigen/Core>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"

namespace vkr {

class PairWarpPass {
 public:
  static constexpr VkFormat kResultFormat = VK_FORMAT_R32_SFLOAT;
  static constexpr VkFormat kSyntheticFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  static constexpr float kNotSeenBySource = -1.0f;
  static constexpr float kNoSurface = -2.0f;

  struct NoiseModel {
    double sigma_255 = 8.0;     // σ on the 0–255 scale
    double robust_cap = 9.0;    // per-dof cap of a pixel pair's χ²
    double position_sd = 0.5;   // δ in pixels (0: no gradient term)
    double depth_tolerance = 0.004;  // relative tolerance of the shadow-map test in s
  };

  // `cameras`: cameras per hypothesis; `hypothesis_slots`: hypotheses recorded per submission;
  // `bindings`: how many (pair, level) image sets will be bound.
  PairWarpPass(vk::Device& device, const GpuScene& scene, int cameras, int hypothesis_slots,
               int bindings, const NoiseModel& noise);

  // Binds set `index` (once, at creation of the likelihood): r_s and r_t (mip chains = the
  // image pyramids) in SHADER_READ_ONLY_OPTIMAL, s's depth map in DEPTH_READ_ONLY_OPTIMAL
  // when recorded, and the validity of r_s and r_t (ReferenceImages.h: the same mips, 1 =
  // comparable) in SHADER_READ_ONLY_OPTIMAL, or VK_NULL_HANDLE for a camera whose every pixel
  // counts (its pairs then use pipelines specialised not to read it). A pixel of t that is
  // invalid is not compared (as if t saw no surface there); a sample of r_s touching an
  // invalid pixel counts as not seen by s.
  void BindImages(int index, VkImageView source_reference, VkImageView source_depth,
                  VkImageView target_reference, VkImageView source_validity, VkImageView target_validity);

  // Writes one hypothesis's cameras into `slot` (host-visible memory, no submission).
  void SetCameras(int slot, const std::vector<Camera>& cameras);

  struct Target {
    VkImageView depth = VK_NULL_HANDLE;      // t's depth map at `level`, DEPTH_READ_ONLY_OPTIMAL
    VkImageView result = VK_NULL_HANDLE;     // R32F, COLOR_ATTACHMENT_OPTIMAL
    VkImageView synthetic = VK_NULL_HANDLE;  // optional RGBA16F for dumps, COLOR_ATTACHMENT_OPTIMAL
    uint32_t width = 0, height = 0;          // t's image at `level` (the depth map's size)
  };
  // Records pair (source, target) of slot `slot`'s hypothesis with image set `binding`,
  // clearing the target's images first.
  void record(VkCommandBuffer cmd, int slot, int source, int target, int level, int binding,
              const Target& out) const;

 private:
  vk::Device* device_;
  const GpuScene* scene_;
  int cameras_, slots_;
  NoiseModel noise_;
  vk::Buffer camera_buffer_;
  vk::Sampler trilinear_, nearest_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  std::vector<VkDescriptorSet> sets_;
  // Made when the likelihood is: the shaders, and per validity case (bit 0: t has one, bit 1:
  // s has one) the pipeline without and with the synthetic image, made by BindImages when a
  // case first occurs.
  vk::ShaderModule vert_, frag_, dump_frag_;
  std::vector<uint32_t> checks_;  // per binding
  vk::Pipeline pipelines_[4][2];
  void CreatePipelines(uint32_t checks);
};

}  // namespace vkr
