#pragma once
// Draws the scene from one camera into linear float RGBA: the atlas colour (the baked
// albedo for `synth`, the composite texture for `render`), that colour lit by a sun with
// cast shadows (`synth`'s photographs), or, for tests, the world position of each pixel.
// Alpha is 1 on the surface and 0 on the background.

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"

namespace vkr {

// Colour + depth attachments of one view size.
struct ViewTarget {
  vk::GpuImage colour;  // RGBA32F, left in TRANSFER_SRC_OPTIMAL after record()
  vk::GpuImage depth;   // D32F, reversed
  ViewTarget(vk::Device& device, uint32_t width, uint32_t height);
};

// A directional sun and ambient sky light (pipelines/rendering/SunLight.h makes one), applied in
// linear light: colour = albedo · (ambient + strength · cos θ_sun · sunlit).
struct SunLighting {
  Eigen::Matrix4d shadow_from_world = Eigen::Matrix4d::Identity();  // world → shadow-map clip
  Eigen::Vector3d to_sun = Eigen::Vector3d::UnitZ();  // unit direction towards the sun
  double strength = 0.7;   // of the sun on a face turned to it
  double ambient = 0.3;    // of the sky, everywhere
  double depth_bias = 0.0; // shadow-map depth units
  double texel = 0.0;      // one shadow-map texel in its [0,1] coordinates
};

class NovelViewPass {
 public:
  enum class Output : uint32_t { Colour = 0, WorldPosition = 1, LitColour = 2 };

  // `atlas` must stay alive and in SHADER_READ_ONLY_OPTIMAL layout while the pass is used.
  NovelViewPass(vk::Device& device, const GpuScene& scene, const vk::GpuImage& atlas);

  // Lighting for Output::LitColour: `shadow_map` (D32F, reversed depth seen from the sun,
  // SAMPLED usage) must stay alive and in DEPTH_READ_ONLY_OPTIMAL while the pass is used.
  void SetSunLighting(const SunLighting& lighting, const vk::GpuImage& shadow_map);

  // Records the draw of node-matrix slot `slot` seen by `camera` into `target`.
  void record(VkCommandBuffer cmd, const Camera& camera, int slot, Output output,
              ViewTarget& target) const;

  // Convenience for set-up and tools (not for sampling loops): record, submit, wait, read.
  Image Render(vk::Transfer& transfer, vk::CommandContext& context, const Camera& camera,
               int slot = 0, Output output = Output::Colour);

 private:
  vk::Device* device_;
  const GpuScene* scene_;
  vk::Sampler sampler_, nearest_;
  vk::Buffer lighting_;      // the shader's Lighting block
  vk::GpuImage no_shadow_;   // bound until SetSunLighting: a 1×1 shadow map
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Pipeline pipeline_;
  std::unique_ptr<ViewTarget> target_;  // for Render(), reallocated only when the size changes
};

}  // namespace vkr
