#include "pipelines/passes/TargetWarpPass.h"

#include <cstring>
#include <stdexcept>

#include "pipelines/passes/PipelineBuilder.h"
#include "pipelines/passes/Projection.h"
#include "shaders/image_warp_dump_frag.h"
#include "shaders/image_warp_frag.h"
#include "shaders/image_warp_vert.h"

namespace vkr {
namespace {

// Mirrors WarpCamera in shaders_glsl/image_warp_push.glsl (std430).
struct WarpGpuCamera {
  float clip_from_world[16];
  float centre_fx_fy[4];
};
static_assert(sizeof(WarpGpuCamera) == 80);

// Mirrors the push constants in shaders_glsl/image_warp_push.glsl.
struct WarpPush {
  uint32_t node_offset, target, source_count;
  float level, inv_sigma2, cap, position_sd_over_sigma, depth_tolerance, near, depth_equal;
  uint32_t sources[TargetWarpPass::kMaxSources];
};
static_assert(sizeof(WarpPush) <= 128, "push constants beyond the guaranteed 128 bytes");

// Relative slack of the depth-equal test: ~100 float ulps, far below any real gap between
// surfaces, far above the rounding differences between depth.vert and image_warp.vert.
constexpr float kWarpDepthEqual = 1e-5f;

// The fields of a pipeline specialisation, packed into a key of TargetWarpPass::pipelines_.
struct Specialisation {
  uint32_t check_target = 0;   // image_warp.glsl's kCheckTarget
  uint32_t check_sources = 0;  // kCheckSources: bit i for source i
  uint32_t sources = 1;        // kSources
  bool synthetic = false;      // image_warp_dump.frag

  uint32_t Key() const {
    return check_target | check_sources << 1 | sources << (1 + TargetWarpPass::kMaxSources) |
           uint32_t(synthetic) << (5 + TargetWarpPass::kMaxSources);
  }
  static Specialisation FromKey(uint32_t key) {
    constexpr uint32_t kSourceBits = (1u << TargetWarpPass::kMaxSources) - 1;
    return {key & 1u, (key >> 1) & kSourceBits, (key >> (1 + TargetWarpPass::kMaxSources)) & 15u,
            ((key >> (5 + TargetWarpPass::kMaxSources)) & 1u) != 0};
  }
};
static_assert(TargetWarpPass::kMaxSources < 16, "kSources takes 4 bits of the key");

}  // namespace

TargetWarpPass::TargetWarpPass(vk::Device& device, const GpuScene& scene, int cameras, int hypothesis_slots,
                               int bindings, const NoiseModel& noise)
    : device_(&device),
      scene_(&scene),
      cameras_(cameras),
      slots_(hypothesis_slots),
      noise_(noise),
      camera_buffer_(device, VkDeviceSize(cameras) * hypothesis_slots * sizeof(WarpGpuCamera),
                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload),
      trilinear_(vk::CreateTrilinearClampSampler(device)),
      nearest_(vk::CreateNearestClampSampler(device)) {
  constexpr VkShaderStageFlags kBoth = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  constexpr uint32_t kSources = kMaxSources;
  const std::vector<VkDescriptorSetLayoutBinding> layout_bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kBoth, nullptr},
      {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSources, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSources, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {4, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kSources, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
  };
  set_layout_ = CreateDescriptorSetLayout(device, layout_bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(WarpPush), kBoth);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, layout_bindings, uint32_t(bindings));
  pool_ = std::move(sets.pool);
  sets_ = std::move(sets.sets);
  for (VkDescriptorSet set : sets_) {
    WriteStorageBuffer(device, set, 0, scene.node_matrices());
    WriteStorageBuffer(device, set, 1, camera_buffer_);
  }
  groups_.resize(size_t(bindings));

  vert_ = vk::CreateShaderModule(device, kImageWarpVert, sizeof(kImageWarpVert));
  frag_ = vk::CreateShaderModule(device, kImageWarpFrag, sizeof(kImageWarpFrag));
  dump_frag_ = vk::CreateShaderModule(device, kImageWarpDumpFrag, sizeof(kImageWarpDumpFrag));
}

void TargetWarpPass::BindImages(int index, const CameraViews& target, const std::vector<CameraViews>& sources,
                                bool synthetic) {
  if (sources.empty() || int(sources.size()) > kMaxSources)
    throw std::invalid_argument("TargetWarpPass::BindImages: 1 to " + std::to_string(kMaxSources) + " sources");
  VkDescriptorSet set = sets_.at(size_t(index));
  Group& group = groups_.at(size_t(index));
  group.target = target.camera;
  group.sources.clear();
  Specialisation spec;
  spec.check_target = target.validity ? 1u : 0u;
  spec.sources = uint32_t(sources.size());
  spec.synthetic = synthetic;
  constexpr VkImageLayout kRead = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  // A missing validity binds the reference in its place (a view at hand): never read. Array
  // elements past the group's sources repeat its first: never read either, but bound, as
  // validation wants every element of an arrayed binding the shader declares.
  for (uint32_t i = 0; i < uint32_t(kMaxSources); ++i) {
    const CameraViews& s = sources[i < sources.size() ? i : 0];
    if (i < sources.size()) {
      group.sources.push_back(s.camera);
      if (s.validity) spec.check_sources |= 1u << i;
    }
    WriteSampledImage(*device_, set, 2, s.reference, trilinear_, kRead, i);
    WriteSampledImage(*device_, set, 3, s.depth, nearest_, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, i);
    WriteSampledImage(*device_, set, 5, s.validity ? s.validity : s.reference, trilinear_, kRead, i);
  }
  WriteSampledImage(*device_, set, 4, target.reference, trilinear_, kRead);
  WriteSampledImage(*device_, set, 6, target.validity ? target.validity : target.reference, trilinear_, kRead);

  group.specialisation = spec.Key();
  if (pipelines_.count(group.specialisation)) return;
  GraphicsPipelineDesc desc;
  desc.vertex = vert_;
  desc.fragment = synthetic ? dump_frag_ : frag_;
  desc.layout = layout_;
  desc.colour_formats = {kResultFormat};
  if (synthetic) desc.colour_formats.push_back(kSyntheticFormat);
  desc.depth_format = VK_FORMAT_D32_SFLOAT;  // DepthPass::kFormat
  desc.depth_write = false;
  desc.depth_compare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reversed depth: the visible surface only
  desc.vertex_attributes = 0b01011;                     // position, normal, node
  desc.fragment_constants = {spec.check_target, spec.check_sources, spec.sources};
  pipelines_[group.specialisation] = CreateGraphicsPipeline(*device_, desc);
}

void TargetWarpPass::SetCameras(int slot, const std::vector<Camera>& cameras) {
  if (slot < 0 || slot >= slots_ || int(cameras.size()) != cameras_)
    throw std::out_of_range("TargetWarpPass::SetCameras: slot or camera count out of range");
  WarpGpuCamera* dst = camera_buffer_.data<WarpGpuCamera>() + size_t(slot) * cameras_;
  for (const Camera& camera : cameras) {
    Eigen::Map<Eigen::Matrix4f>(dst->clip_from_world) = ClipFromWorld(camera).cast<float>();
    const Eigen::Vector3d centre = camera.Centre();
    for (int k = 0; k < 3; ++k) dst->centre_fx_fy[k] = float(centre[k]);
    dst->centre_fx_fy[3] = float(camera.K(0, 0) * camera.K(1, 1));
    ++dst;
  }
}

void TargetWarpPass::record(VkCommandBuffer cmd, int slot, int level, int binding, const Target& out) const {
  const Group& group = groups_.at(size_t(binding));
  const bool synthetic = Specialisation::FromKey(group.specialisation).synthetic;
  if (synthetic != (out.synthetic != VK_NULL_HANDLE))
    throw std::invalid_argument("TargetWarpPass::record: a synthetic image for, and only for, a set bound with one");
  const double sigma = noise_.sigma_255 / 255.0;
  WarpPush push{};
  push.node_offset = scene_->node_offset(slot);
  push.target = uint32_t(slot * cameras_ + group.target);
  push.source_count = uint32_t(group.sources.size());
  for (size_t i = 0; i < group.sources.size(); ++i) push.sources[i] = uint32_t(slot * cameras_ + group.sources[i]);
  push.level = float(level);
  push.inv_sigma2 = float(1.0 / (sigma * sigma));
  push.cap = float(noise_.robust_cap);
  push.position_sd_over_sigma = float(noise_.position_sd / sigma);
  push.depth_tolerance = float(noise_.depth_tolerance);
  push.near = float(kDefaultNear);
  push.depth_equal = kWarpDepthEqual;

  VkRenderingAttachmentInfo colour[2] = {{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO},
                                         {VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO}};
  colour[0].imageView = out.result;
  colour[1].imageView = out.synthetic;
  for (VkRenderingAttachmentInfo& c : colour) {
    c.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    c.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;  // to 0: no surface
    c.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  }
  // t's depth map, read only: the depth pass wrote it, the shadow-map tests of other
  // targets' draws sample it in the same layout.
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = out.depth;
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
  VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
  ri.renderArea = {{0, 0}, {out.width, out.height}};
  ri.layerCount = 1;
  ri.colorAttachmentCount = synthetic ? 2 : 1;
  ri.pColorAttachments = colour;
  ri.pDepthAttachment = &depth;
  vkCmdBeginRendering(cmd, &ri);
  SetViewport(cmd, out.width, out.height);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines_.at(group.specialisation));
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &sets_.at(size_t(binding)), 0,
                          nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(WarpPush),
                     &push);
  scene_->Bind(cmd);
  vkCmdDrawIndexed(cmd, scene_->index_count(), 1, 0, 0, 0);
  vkCmdEndRendering(cmd);
}

}  // namespace vkr
