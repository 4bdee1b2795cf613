#pragma once
// Interior (occlusion) pass (thesis §7.1.1–7.1.4): rasterises the faces in atlas space and
// marks each texel 0 (no surface), 1 (exterior) or 2 (inside, or on the boundary of, another
// primitive). Interior texels are left out of the photo-consistency comparison.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "engine/scene/Scene.h"
#include "engine/vk/Resources.h"
#include "pipelines/passes/GpuScene.h"

namespace vkr {

class InteriorPass {
 public:
  static constexpr VkFormat kFormat = VK_FORMAT_R32_UINT;

  InteriorPass(vk::Device& device, const Scene& scene, const SceneGeometry& geometry,
               const GpuScene& gpu_scene);

  // Writes node_from_world of slot `slot` and, per node, the primitives whose volume may
  // hold part of its surface (host-visible; no submission).
  void SetNodeMatrices(int slot, const std::vector<Eigen::Matrix4d>& world_from_node);

  // Renders into `mask` (COLOR_ATTACHMENT_OPTIMAL) over [0, atlas_size)².
  void record(VkCommandBuffer cmd, int slot, const vk::GpuImage& mask, uint32_t atlas_size) const;

 private:
  void WriteCandidates(int slot, const std::vector<Eigen::Matrix4d>& world_from_node,
                       const std::vector<bool>& degenerate);

  const GpuScene* scene_;
  std::vector<PrimitiveKind> kinds_host_;
  std::vector<Eigen::AlignedBox3d> node_bounds_;  // each node's surface, node frame; empty: none
  vk::Buffer node_from_world_, kinds_, candidates_;
  vk::DescriptorSetLayout set_layout_;
  vk::PipelineLayout layout_;
  vk::DescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  // With and without the fragment stage's search over every node (interior.frag
  // kSearchAllNodes): per slot, whether any node of its hypothesis has more candidates than
  // the vertices carry (set by SetNodeMatrices; recorded draws must follow it).
  vk::Pipeline pipeline_, candidates_only_pipeline_;
  std::vector<bool> searches_all_nodes_;
};

}  // namespace vkr
