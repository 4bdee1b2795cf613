#pragma once
// Image-space warp pass (thesis §4.2–4.3, docs/internals/IMAGE_SPACE.md): for a target
// camera t and a group of its source cameras s, render the hypothesis from t, and per pixel
// and source texture it by projecting r_s onto it with a shadow-map visibility test from s
// (the synthetic image s_{s,t}); write per pixel of t the sum of the pixel pairs' χ² under
// the noise model of shaders_glsl/image_warp.glsl and how many sources compared.
//
// One draw serves a whole group, so t's surface is rasterised and depth-tested once per
// group rather than once per pair (docs/internals/IMAGE_SPACE.md "Cost"). Only the surface t
// actually sees is shaded: t's depth map (DepthPass) is the pass's read-only depth attachment, with
// a depth-equal test. Output per pixel (RGBA32F): r = Σ χ² over the sources that see the surface
// point too, g = their count, b = the count of sources that do not, a = 1; all 0 where t sees no
// surface (background, or the back of a face).

#include <Eigen/Core>
#include <map>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"

namespace vkr {

class TargetWarpPass {
 public:
  static constexpr VkFormat kResultFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
  static constexpr VkFormat kSyntheticFormat = VK_FORMAT_R16G16B16A16_SFLOAT;
  // The most sources one draw takes (image_warp_push.glsl): each costs a vec4 varying.
  static constexpr int kMaxSources = 8;

  struct NoiseModel {
    double sigma_255 = 8.0;     // σ on the 0–255 scale
    double robust_cap = 9.0;    // per-dof cap of a pixel pair's χ²
    double position_sd = 0.5;   // δ in pixels (0: no gradient term)
    double depth_tolerance = 0.004;  // relative tolerance of the shadow-map test in s
  };

  // `cameras`: cameras per hypothesis; `hypothesis_slots`: hypotheses recorded per submission;
  // `bindings`: how many (group, level) image sets will be bound.
  TargetWarpPass(vk::Device& device, const GpuScene& scene, int cameras, int hypothesis_slots,
                 int bindings, const NoiseModel& noise);

  // One camera's images as the pass reads them: its reference (the mip chain = its image
  // pyramid) in SHADER_READ_ONLY_OPTIMAL, its depth map at the level in
  // DEPTH_READ_ONLY_OPTIMAL when recorded (read for sources only), and its validity
  // (ReferenceImages.h: the same mips, 1 = comparable) in SHADER_READ_ONLY_OPTIMAL, or
  // VK_NULL_HANDLE for a camera whose every pixel counts (pipelines are then specialised not
  // to read it). A pixel of t that is invalid is not compared (as if t saw no surface there);
  // a sample of r_s touching an invalid pixel counts as not seen by s.
  struct CameraViews {
    int camera = 0;  // index among the hypothesis's cameras
    VkImageView reference = VK_NULL_HANDLE, depth = VK_NULL_HANDLE, validity = VK_NULL_HANDLE;
  };
  // Binds set `index` (once, at creation of the likelihood) for target `target` and 1 to
  // kMaxSources `sources`; `synthetic`: the set's draws also write the synthetic image of
  // their first source (dumps, which bind one source per set).
  void BindImages(int index, const CameraViews& target, const std::vector<CameraViews>& sources, bool synthetic);

  // Writes one hypothesis's cameras into `slot` (host-visible memory, no submission).
  void SetCameras(int slot, const std::vector<Camera>& cameras);

  struct Target {
    VkImageView depth = VK_NULL_HANDLE;      // t's depth map at `level`, DEPTH_READ_ONLY_OPTIMAL
    VkImageView result = VK_NULL_HANDLE;     // kResultFormat, COLOR_ATTACHMENT_OPTIMAL
    VkImageView synthetic = VK_NULL_HANDLE;  // kSyntheticFormat, COLOR_ATTACHMENT_OPTIMAL, for sets bound with `synthetic`
    uint32_t width = 0, height = 0;          // t's image at `level` (the depth map's size)
  };
  // Records the draw of slot `slot`'s hypothesis with image set `binding` at `level`,
  // clearing the target's images first.
  void record(VkCommandBuffer cmd, int slot, int level, int binding, const Target& out) const;

 private:
  // What one bound set draws, and the specialisation of the pipeline that draws it.
  struct Group {
    int target = 0;
    std::vector<int> sources;
    uint32_t specialisation = 0;  // a key of pipelines_
  };
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
  std::vector<Group> groups_;  // per binding
  // Made when the likelihood is: the shaders, and per specialisation (whether t and each
  // source have a validity image, the group's size, whether it writes the synthetic image)
  // the pipeline, made by BindImages when it first occurs.
  vk::ShaderModule vert_, frag_, dump_frag_;
  std::map<uint32_t, vk::Pipeline> pipelines_;
};

}  // namespace vkr
