#include "pipelines/passes/ViewTexturePass.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "pipelines/passes/PipelineBuilder.h"
#include "pipelines/passes/Projection.h"
#include "shaders/view_texture_frag.h"
#include "shaders/view_texture_unseen_frag.h"
#include "shaders/view_texture_vert.h"

namespace vkr {
namespace {

// Mirrors shaders_glsl/view_texture_push.glsl.
struct ViewTexturePush {
  float clip_from_world[16];
  float centre[4];  // w unused
  float params[4];  // fx·fy, depth tolerance, weights mode, near
  uint32_t node_offset;
  float level;
};
static_assert(sizeof(ViewTexturePush) <= 128, "push constants beyond the guaranteed 128 bytes");

}  // namespace

ViewTexturePass::ViewTexturePass(vk::Device& device, const GpuScene& scene, int bindings,
                                 bool angle_weights, double depth_tolerance)
    : device_(&device),
      scene_(&scene),
      angle_weights_(angle_weights),
      depth_tolerance_(depth_tolerance),
      trilinear_(vk::CreateTrilinearClampSampler(device)),
      nearest_(vk::CreateNearestClampSampler(device)) {
  const std::vector<VkDescriptorSetLayoutBinding> layout_bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
  };
  set_layout_ = CreateDescriptorSetLayout(device, layout_bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(ViewTexturePush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, layout_bindings, uint32_t(bindings));
  pool_ = std::move(sets.pool);
  sets_ = std::move(sets.sets);
  for (VkDescriptorSet set : sets_) WriteStorageBuffer(device, set, 0, scene.node_matrices());

  const vk::ShaderModule vert = vk::CreateShaderModule(device, kViewTextureVert, sizeof(kViewTextureVert));
  const vk::ShaderModule frag = vk::CreateShaderModule(device, kViewTextureFrag, sizeof(kViewTextureFrag));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.layout = layout_;
  desc.colour_formats = {kFormat};
  desc.vertex_attributes = 0b101111;  // position, normal, atlas_uv, node, texel_area
  desc.fragment_constants = {0};     // kCheckValidity: cameras where every pixel counts skip the read
  pipeline_ = CreateGraphicsPipeline(device, desc);
  desc.fragment_constants = {1};
  validity_pipeline_ = CreateGraphicsPipeline(device, desc);
  const vk::ShaderModule unseen = vk::CreateShaderModule(device, kViewTextureUnseenFrag, sizeof(kViewTextureUnseenFrag));
  desc.fragment = unseen;
  desc.fragment_constants = {};
  unseen_pipeline_ = CreateGraphicsPipeline(device, desc);
  checks_validity_.assign(size_t(bindings), false);
}

void ViewTexturePass::BindImages(int index, VkImageView reference, VkImageView depth, VkImageView validity) {
  WriteSampledImage(*device_, sets_.at(index), 1, reference, trilinear_,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  WriteSampledImage(*device_, sets_.at(index), 2, depth, nearest_,
                    VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
  // Without validity the pipeline specialised not to read binding 3 draws this set; the
  // binding still needs a view, and the reference is one at hand.
  checks_validity_.at(size_t(index)) = validity != VK_NULL_HANDLE;
  WriteSampledImage(*device_, sets_.at(index), 3, validity ? validity : reference, trilinear_,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void ViewTexturePass::record(VkCommandBuffer cmd, const ViewCamera& camera, const ViewDraws& draws, int binding,
                             int slot, VkImageView target, uint32_t atlas_size, bool clear) const {
  ViewTexturePush push{};
  const Eigen::Matrix4f clip = camera.clip_from_world.cast<float>();
  std::memcpy(push.clip_from_world, clip.data(), sizeof(push.clip_from_world));
  for (int k = 0; k < 3; ++k) push.centre[k] = float(camera.centre[k]);
  push.params[0] = float(camera.fx_fy);
  push.params[1] = float(depth_tolerance_);
  push.params[2] = angle_weights_ ? 1.0f : 0.0f;
  push.params[3] = float(kDefaultNear);
  push.node_offset = scene_->node_offset(slot);
  push.level = float(camera.level);
  // Every chart texel is written (weight 0 where the camera cannot see it) and the composite
  // reads no other, so the layer need not be cleared: on lavapipe the clear was 10 % of
  // the pass.
  VkClearColorValue nothing{};
  nothing.uint32[0] = nothing.uint32[1] = 0u;  // weight 0: no camera sees the texel
  const std::optional<VkClearColorValue> zero = clear ? std::optional<VkClearColorValue>(nothing) : std::nullopt;
  BeginRendering(cmd, atlas_size, atlas_size, target, zero, VK_NULL_HANDLE);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &sets_.at(binding), 0,
                          nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(ViewTexturePush), &push);
  scene_->Bind(cmd);
  auto draw = [&](VkPipeline pipeline, const std::vector<IndexRun>& runs) {
    if (runs.empty()) return;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
    for (const IndexRun& run : runs) vkCmdDrawIndexed(cmd, run.count, 1, run.first, 0, 0);
  };
  const VkPipeline shaded = checks_validity_.at(size_t(binding)) ? validity_pipeline_ : pipeline_;
  draw(shaded, draws.shaded);
  draw(unseen_pipeline_, draws.unseen);
  for (const PartialRun& part : draws.partial) {
    // The rectangle in whole texels, two beyond its bounds on every side: a texel outside
    // it lies outside the frustum by far more than the shader's rounding, so the full shader
    // would write weight 0 there too. Scissors split the run: shaded inside, weight 0 in the
    // bands around it; every texel of the run is drawn once.
    const auto texel = [&](double u, double shift) {
      return int32_t(std::clamp(std::floor(u * atlas_size) + shift, 0.0, double(atlas_size)));
    };
    const int32_t x0 = texel(part.u0, -2.0), y0 = texel(part.v0, -2.0);
    const int32_t x1 = texel(part.u1, 3.0), y1 = texel(part.v1, 3.0);
    const int32_t n = int32_t(atlas_size);
    const VkRect2D inside{{x0, y0}, {uint32_t(x1 - x0), uint32_t(y1 - y0)}};
    const VkRect2D bands[4] = {{{0, 0}, {uint32_t(n), uint32_t(y0)}},
                               {{0, y1}, {uint32_t(n), uint32_t(n - y1)}},
                               {{0, y0}, {uint32_t(x0), uint32_t(y1 - y0)}},
                               {{x1, y0}, {uint32_t(n - x1), uint32_t(y1 - y0)}}};
    auto draw_in = [&](VkPipeline pipeline, const VkRect2D& rect) {
      if (rect.extent.width == 0 || rect.extent.height == 0) return;
      vkCmdSetScissor(cmd, 0, 1, &rect);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
      vkCmdDrawIndexed(cmd, part.indices.count, 1, part.indices.first, 0, 0);
    };
    draw_in(shaded, inside);
    for (const VkRect2D& band : bands) draw_in(unseen_pipeline_, band);
  }
  if (!draws.partial.empty()) {
    const VkRect2D all{{0, 0}, {atlas_size, atlas_size}};
    vkCmdSetScissor(cmd, 0, 1, &all);
  }
  vkCmdEndRendering(cmd);
}

}  // namespace vkr
