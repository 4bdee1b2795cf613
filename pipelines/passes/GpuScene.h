#pragma once
// The scene's geometry on the GPU, uploaded once per run, and the small buffer of node
// matrices that is all a hypothesis changes (docs/internals/OVERVIEW.md, "How a hypothesis flows").

#include <Eigen/Core>
#include <vector>

#include "engine/geometry/SceneGeometry.h"
#include "engine/vk/Commands.h"
#include "engine/vk/Resources.h"

namespace vkr {

class GpuScene {
 public:
  // `hypothesis_slots`: how many hypotheses' node matrices fit at once (the batch size).
  GpuScene(vk::Device& device, vk::Transfer& transfer, const SceneGeometry& geometry,
           int hypothesis_slots = 1);

  const vk::Buffer& vertices() const { return vertices_; }
  const vk::Buffer& indices() const { return indices_; }
  uint32_t index_count() const { return index_count_; }
  int node_count() const { return node_count_; }
  int hypothesis_slots() const { return slots_; }

  // Storage buffer of mat4 world_from_node, `node_count()` per slot, slot-major.
  const vk::Buffer& node_matrices() const { return node_matrices_; }
  // Writes one hypothesis's matrices into `slot` (host-visible memory, no submission).
  void SetNodeMatrices(int slot, const std::vector<Eigen::Matrix4d>& world_from_node);
  uint32_t node_offset(int slot) const { return uint32_t(slot * node_count_); }

  // Binds vertex and index buffers.
  void Bind(VkCommandBuffer cmd) const;

 private:
  vk::Buffer vertices_, indices_, node_matrices_;
  uint32_t index_count_ = 0;
  int node_count_ = 0, slots_ = 1;
};

}  // namespace vkr
