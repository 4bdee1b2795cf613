#include "pipelines/passes/InteriorPass.h"

#include <Eigen/LU>

#include "pipelines/passes/PipelineBuilder.h"
#include "shaders/interior_frag.h"
#include "shaders/interior_vert.h"

namespace vkr {
namespace {

struct InteriorPush {
  uint32_t node_offset;
  uint32_t node_count;
};

// Mirrors shaders_glsl/interior_io.glsl.
constexpr int kCandidates = 4;
constexpr uint32_t kAllNodes = 0xffffffffu;
constexpr double kEps = 1e-3;  // interior.frag's tolerance, in the containing node's unit frame

bool HasVolume(PrimitiveKind k) {
  return k == PrimitiveKind::Plane || k == PrimitiveKind::Box || k == PrimitiveKind::Prism ||
         k == PrimitiveKind::Cylinder;
}

Eigen::AlignedBox3d WorldBox(const Eigen::Matrix4d& world_from_node, const Eigen::AlignedBox3d& box) {
  Eigen::AlignedBox3d out;
  for (int c = 0; c < 8; ++c)
    out.extend((world_from_node * box.corner(Eigen::AlignedBox3d::CornerType(c)).homogeneous()).head<3>());
  return out;
}

}  // namespace

InteriorPass::InteriorPass(vk::Device& device, const Scene& scene, const SceneGeometry& geometry,
                           const GpuScene& gpu_scene)
    : scene_(&gpu_scene) {
  const int nodes = gpu_scene.node_count();
  for (int n = 0; n < nodes; ++n) {
    kinds_host_.push_back(n < int(scene.nodes.size()) ? scene.nodes[n].primitive : PrimitiveKind::None);
    Eigen::AlignedBox3d box;
    if (n < int(geometry.meshes.size()))
      for (const Eigen::Vector3f& p : geometry.meshes[n].positions) box.extend(p.cast<double>());
    node_bounds_.push_back(box);
  }
  candidates_ = vk::Buffer(device, VkDeviceSize(gpu_scene.hypothesis_slots()) * nodes * 32,
                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload);
  node_from_world_ = vk::Buffer(device, VkDeviceSize(gpu_scene.hypothesis_slots()) * nodes * 64,
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload);
  kinds_ = vk::Buffer(device, VkDeviceSize(nodes) * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                      vk::MemoryUse::Upload);
  for (int n = 0; n < nodes; ++n)
    // The shader's kind codes are PrimitiveKind's order: 0 none, 1 plane … 5 mesh.
    kinds_.data<uint32_t>()[n] = n < int(scene.nodes.size()) ? uint32_t(scene.nodes[n].primitive) : 0u;

  const std::vector<VkDescriptorSetLayoutBinding> bindings = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {3, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
  };
  set_layout_ = CreateDescriptorSetLayout(device, bindings);
  layout_ = CreatePipelineLayout(device, set_layout_, sizeof(InteriorPush),
                                 VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT);
  DescriptorSets sets = AllocateDescriptorSets(device, set_layout_, bindings);
  pool_ = std::move(sets.pool);
  set_ = sets.sets[0];
  WriteStorageBuffer(device, set_, 0, gpu_scene.node_matrices());
  WriteStorageBuffer(device, set_, 1, node_from_world_);
  WriteStorageBuffer(device, set_, 2, kinds_);
  WriteStorageBuffer(device, set_, 3, candidates_);

  const vk::ShaderModule vert = vk::CreateShaderModule(device, kInteriorVert, sizeof(kInteriorVert));
  const vk::ShaderModule frag = vk::CreateShaderModule(device, kInteriorFrag, sizeof(kInteriorFrag));
  GraphicsPipelineDesc desc;
  desc.vertex = vert;
  desc.fragment = frag;
  desc.layout = layout_;
  desc.colour_formats = {kFormat};
  desc.vertex_attributes = 0b01101;  // position, atlas_uv, node
  desc.fragment_constants = {1u};
  pipeline_ = CreateGraphicsPipeline(device, desc);
  desc.fragment_constants = {0u};
  candidates_only_pipeline_ = CreateGraphicsPipeline(device, desc);
  searches_all_nodes_.assign(size_t(gpu_scene.hypothesis_slots()), true);
}

void InteriorPass::SetNodeMatrices(int slot, const std::vector<Eigen::Matrix4d>& world_from_node) {
  float* dst = node_from_world_.data<float>() + size_t(scene_->node_offset(slot)) * 16;
  std::vector<bool> degenerate;
  for (const Eigen::Matrix4d& m : world_from_node) {
    // A degenerate node (a zero scale) contains nothing: its inverse is replaced by a
    // matrix that sends every point far outside the unit primitives.
    degenerate.push_back(!(std::abs(m.topLeftCorner<3, 3>().determinant()) > 1e-15));
    Eigen::Matrix4d inverse = degenerate.back() ? Eigen::Matrix4d(Eigen::Matrix4d::Zero()) : Eigen::Matrix4d(m.inverse());
    if (degenerate.back()) inverse(0, 3) = 1e9, inverse(3, 3) = 1.0;
    Eigen::Map<Eigen::Matrix4f> out(dst);
    out = inverse.cast<float>();
    dst += 16;
  }
  WriteCandidates(slot, world_from_node, degenerate);
}

// Conservative: a primitive is a candidate unless the world box of its volume (widened by
// the shader's tolerance) misses the world box of the node's surface. Planes are solid
// below, without bound, so they are always candidates.
void InteriorPass::WriteCandidates(int slot, const std::vector<Eigen::Matrix4d>& world_from_node,
                                   const std::vector<bool>& degenerate) {
  const int nodes = int(world_from_node.size());
  const Eigen::AlignedBox3d unit_volume(Eigen::Vector3d(-0.5 - kEps, -0.5 - kEps, -kEps),
                                        Eigen::Vector3d(0.5 + kEps, 0.5 + kEps, 1.0 + kEps));
  std::vector<Eigen::AlignedBox3d> surface(nodes), volume(nodes);
  for (int n = 0; n < nodes; ++n) {
    if (!node_bounds_[n].isEmpty()) surface[n] = WorldBox(world_from_node[n], node_bounds_[n]);
    if (HasVolume(kinds_host_[n]) && !degenerate[n]) volume[n] = WorldBox(world_from_node[n], unit_volume);
  }
  uint32_t* dst = candidates_.data<uint32_t>() + size_t(scene_->node_offset(slot)) * 8;
  searches_all_nodes_.at(size_t(slot)) = false;
  for (int n = 0; n < nodes; ++n, dst += 8) {
    std::vector<uint32_t> found;
    if (!surface[n].isEmpty())
      for (int m = 0; m < nodes; ++m) {
        if (m == n || !HasVolume(kinds_host_[m]) || degenerate[m]) continue;
        // Rounding of the world boxes is far below the tolerance's widening.
        if (kinds_host_[m] == PrimitiveKind::Plane || volume[m].intersects(surface[n])) found.push_back(uint32_t(m));
      }
    std::fill(dst, dst + 8, 0u);
    if (int(found.size()) > kCandidates) {
      dst[4] = kAllNodes;
      searches_all_nodes_[size_t(slot)] = true;
      continue;
    }
    std::copy(found.begin(), found.end(), dst);
    dst[4] = uint32_t(found.size());
  }
}

void InteriorPass::record(VkCommandBuffer cmd, int slot, const vk::GpuImage& mask,
                          uint32_t atlas_size) const {
  const InteriorPush push{scene_->node_offset(slot), uint32_t(scene_->node_count())};
  // Cleared: texels outside every chart must read 0 (no surface) in the composite.
  BeginRendering(cmd, atlas_size, atlas_size, mask.view(), VkClearColorValue{{0.0f, 0.0f, 0.0f, 0.0f}},
                 VK_NULL_HANDLE);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                    searches_all_nodes_.at(size_t(slot)) ? pipeline_ : candidates_only_pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                     sizeof(InteriorPush), &push);
  scene_->Bind(cmd);
  vkCmdDrawIndexed(cmd, scene_->index_count(), 1, 0, 0, 0);
  vkCmdEndRendering(cmd);
}

}  // namespace vkr
