#pragma once
// Draws the scene from one camera into linear float RGBA: the atlas colour (the baked
// albedo for `synth`, the composite texture for `render`) or, for tests, the world position
// of each pixel. Alpha is 1 on the surface and 0 on the background.

#include "engine/image/Image.h"
#include "engine/scene/Scene.h"
#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"
#include "pipelines/GpuScene.h"

namespace vkr {

// Colour + depth attachments of one view size.
struct ViewTarget {
  vk::GpuImage colour;  // RGBA32F, left in TRANSFER_SRC_OPTIMAL after record()
  vk::GpuImage depth;   // D32F, reversed
  ViewTarget(vk::Device& device, uint32_t width, uint32_t height);
};

class NovelViewPass {
 public:
  enum class Output : uint32_t { Colour = 0, WorldPosition = 1 };

  // `atlas` must stay alive and in SHADER_READ_ONLY_OPTIMAL layout while the pass is used.
  NovelViewPass(vk::Device& device, const GpuScene& scene, const vk::GpuImage& atlas);

  // Records the draw of node-matrix slot `slot` seen by `camera` into `target`.
  void record(VkCommandBuffer cmd, const Camera& camera, int slot, Output output,
              ViewTarget& target) const;

  // Convenience for set-up and tools (not for sampling loops): record, submit, wait, read.
  Image Render(vk::Transfer& transfer, vk::CommandContext& context, const Camera& camera,
               int slot = 0, Output output = Output::Colour);

 private:
  vk::Device* device_;
  const GpuScene* scene_;
  vk::Sampler sampler_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Pipeline pipeline_;
  std::unique_ptr<ViewTarget> target_;  // for Render(), reallocated only when the size changes
};

}  // namespace vkr
