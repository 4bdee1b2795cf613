#include "pipelines/passes/GpuScene.h"

#include <stdexcept>

namespace vkr {

GpuScene::GpuScene(vk::Device& device, vk::Transfer& transfer, const SceneGeometry& geometry,
                   int hypothesis_slots)
    : index_count_(uint32_t(geometry.indices.size())),
      node_count_(int(std::max<size_t>(1, geometry.meshes.size()))),
      slots_(hypothesis_slots) {
  if (geometry.vertices.empty() || geometry.indices.empty())
    throw std::invalid_argument("GpuScene: the scene has no geometry to draw");
  const VkDeviceSize vbytes = geometry.vertices.size() * sizeof(GpuVertex);
  const VkDeviceSize ibytes = geometry.indices.size() * sizeof(uint32_t);
  vertices_ = vk::Buffer(device, vbytes,
                         VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         vk::MemoryUse::Device);
  indices_ = vk::Buffer(device, ibytes,
                        VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        vk::MemoryUse::Device);
  transfer.UploadBuffer(vertices_, geometry.vertices.data(), vbytes);
  transfer.UploadBuffer(indices_, geometry.indices.data(), ibytes);
  // Host-visible: the sampler writes a few hundred bytes per hypothesis straight into it.
  node_matrices_ = vk::Buffer(device, VkDeviceSize(slots_) * node_count_ * sizeof(float) * 16,
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::Upload);
}

void GpuScene::SetNodeMatrices(int slot, const std::vector<Eigen::Matrix4d>& world_from_node) {
  if (slot < 0 || slot >= slots_ || int(world_from_node.size()) > node_count_)
    throw std::out_of_range("GpuScene::SetNodeMatrices: slot or node count out of range");
  float* dst = node_matrices_.data<float>() + size_t(node_offset(slot)) * 16;
  for (const Eigen::Matrix4d& m : world_from_node) {
    // Column-major, as GLSL's mat4 expects.
    Eigen::Map<Eigen::Matrix4f> out(dst);
    out = m.cast<float>();
    dst += 16;
  }
}

void GpuScene::Bind(VkCommandBuffer cmd) const {
  const VkBuffer vb = vertices_.handle();
  const VkDeviceSize offset = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &vb, &offset);
  vkCmdBindIndexBuffer(cmd, indices_.handle(), 0, VK_INDEX_TYPE_UINT32);
}

}  // namespace vkr
