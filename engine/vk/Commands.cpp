#include "engine/vk/Commands.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "engine/vk/Check.h"

namespace vkr::vk {

CommandContext::CommandContext(Device& device) : device_(&device) {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = device.queue_family();
  VkCommandPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateCommandPool(device.handle(), &pci, nullptr, &pool));
  pool_ = CommandPool(device.handle(), pool);
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(device.handle(), &ai, &cmd_));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  VK_CHECK(vkCreateFence(device.handle(), &fci, nullptr, &fence));
  fence_ = Fence(device.handle(), fence);
}

CommandContext::~CommandContext() {
  // A pending submission must finish before its buffer and fence go away.
  if (pending_) {
    VkFence fence = fence_;
    vkWaitForFences(device_->handle(), 1, &fence, VK_TRUE, UINT64_MAX);
  }
}

VkCommandBuffer CommandContext::Begin() {
  if (pending_) Wait();
  if (recording_) throw std::logic_error("CommandContext::Begin while already recording");
  VK_CHECK(vkResetCommandBuffer(cmd_, 0));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(cmd_, &bi));
  recording_ = true;
  return cmd_;
}

void CommandContext::Submit() {
  if (!recording_) throw std::logic_error("CommandContext::Submit without Begin");
  VK_CHECK(vkEndCommandBuffer(cmd_));
  recording_ = false;
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  VkFence fence = fence_;
  VK_CHECK(vkResetFences(device_->handle(), 1, &fence));
  VK_CHECK(vkQueueSubmit(device_->queue(), 1, &si, fence_));
  pending_ = true;
}

void CommandContext::Wait() {
  if (!pending_) return;
  VkFence fence = fence_;
  VK_CHECK(vkWaitForFences(device_->handle(), 1, &fence, VK_TRUE, UINT64_MAX));
  pending_ = false;
}

void ImageBarrier(VkCommandBuffer cmd, const GpuImage& image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                  VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image.handle();
  b.subresourceRange = {image.aspect(), 0, image.info().mip_levels, 0, image.info().layers};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void MemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkMemoryBarrier2 b{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &b;
  vkCmdPipelineBarrier2(cmd, &dep);
}

Transfer::Transfer(Device& device) : device_(&device), context_(device) {}

Buffer& Transfer::Staging(Buffer& buffer, VkDeviceSize bytes, MemoryUse use) {
  if (buffer.size() < bytes) {
    const VkBufferUsageFlags usage =
        VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    buffer = Buffer(*device_, bytes, usage, use);
  }
  return buffer;
}

void Transfer::UploadBuffer(const Buffer& dst, const void* data, VkDeviceSize bytes,
                            VkDeviceSize offset) {
  if (dst.mapped()) {
    std::memcpy(static_cast<char*>(dst.mapped()) + offset, data, bytes);
    return;
  }
  Buffer& staging = Staging(upload_, bytes, MemoryUse::Upload);
  std::memcpy(staging.mapped(), data, bytes);
  VkCommandBuffer cmd = context_.Begin();
  VkBufferCopy region{0, offset, bytes};
  vkCmdCopyBuffer(cmd, staging.handle(), dst.handle(), 1, &region);
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  context_.SubmitAndWait();
}

void Transfer::UploadImage(const GpuImage& dst, uint32_t layer, const void* data,
                           VkImageLayout final_layout) {
  const VkDeviceSize bytes = dst.layer_bytes();
  Buffer& staging = Staging(upload_, bytes, MemoryUse::Upload);
  std::memcpy(staging.mapped(), data, bytes);
  VkCommandBuffer cmd = context_.Begin();
  // Only whole-image transitions: every layer goes through TRANSFER_DST. Layers not being
  // written keep their content only if they were already defined, so callers upload all
  // layers or none (the usual case: layer count 1).
  ImageBarrier(cmd, dst, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_COPY_BIT,
               VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {dst.aspect(), 0, layer, 1};
  region.imageExtent = {dst.info().width, dst.info().height, 1};
  vkCmdCopyBufferToImage(cmd, staging.handle(), dst.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         1, &region);
  ImageBarrier(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout,
               VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  context_.SubmitAndWait();
}

void Transfer::UploadMipChain(const GpuImage& dst, const std::vector<const void*>& mips,
                              VkImageLayout final_layout) {
  const GpuImageInfo& info = dst.info();
  if (mips.size() != info.mip_levels || info.layers != 1)
    throw std::invalid_argument("Transfer::UploadMipChain: one buffer per mip of a one-layer image");
  std::vector<VkBufferImageCopy> regions;
  VkDeviceSize total = 0;
  for (uint32_t m = 0; m < info.mip_levels; ++m) {
    VkBufferImageCopy r{};
    r.bufferOffset = total;
    r.imageSubresource = {dst.aspect(), m, 0, 1};
    r.imageExtent = {std::max(1u, info.width >> m), std::max(1u, info.height >> m), 1};
    regions.push_back(r);
    total += VkDeviceSize(r.imageExtent.width) * r.imageExtent.height * BytesPerTexel(info.format);
  }
  Buffer& staging = Staging(upload_, total, MemoryUse::Upload);
  for (uint32_t m = 0; m < info.mip_levels; ++m) {
    const VkDeviceSize next = m + 1 < info.mip_levels ? regions[m + 1].bufferOffset : total;
    std::memcpy(staging.data<char>() + regions[m].bufferOffset, mips[m], next - regions[m].bufferOffset);
  }
  VkCommandBuffer cmd = context_.Begin();
  ImageBarrier(cmd, dst, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_COPY_BIT,
               VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdCopyBufferToImage(cmd, staging.handle(), dst.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         uint32_t(regions.size()), regions.data());
  ImageBarrier(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout,
               VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  context_.SubmitAndWait();
}

void Transfer::ReadImage(const GpuImage& src, uint32_t layer, VkImageLayout layout, void* out) {
  const VkDeviceSize bytes = src.layer_bytes();
  Buffer& staging = Staging(readback_, bytes, MemoryUse::Readback);
  VkCommandBuffer cmd = context_.Begin();
  ImageBarrier(cmd, src, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
               VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
               VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {src.aspect(), 0, layer, 1};
  region.imageExtent = {src.info().width, src.info().height, 1};
  vkCmdCopyImageToBuffer(cmd, src.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.handle(),
                         1, &region);
  ImageBarrier(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout,
               VK_PIPELINE_STAGE_2_COPY_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
               VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  context_.SubmitAndWait();
  std::memcpy(out, staging.mapped(), bytes);
}

void Transfer::ReadBuffer(const Buffer& src, VkDeviceSize offset, VkDeviceSize bytes, void* out) {
  Buffer& staging = Staging(readback_, bytes, MemoryUse::Readback);
  VkCommandBuffer cmd = context_.Begin();
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferCopy region{offset, 0, bytes};
  vkCmdCopyBuffer(cmd, src.handle(), staging.handle(), 1, &region);
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  context_.SubmitAndWait();
  std::memcpy(out, staging.mapped(), bytes);
}

TimestampQueries::TimestampQueries(Device& device, uint32_t count) : device_(&device), count_(count) {
  VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
  qi.queryCount = count;
  VkQueryPool pool = VK_NULL_HANDLE;
  VK_CHECK(vkCreateQueryPool(device.handle(), &qi, nullptr, &pool));
  pool_ = QueryPool(device.handle(), pool);
}

void TimestampQueries::Reset(VkCommandBuffer cmd) { vkCmdResetQueryPool(cmd, pool_, 0, count_); }

void TimestampQueries::Write(VkCommandBuffer cmd, uint32_t index, VkPipelineStageFlags2 stage) {
  vkCmdWriteTimestamp2(cmd, stage, pool_, index);
}

std::vector<double> TimestampQueries::ReadMs(uint32_t count) {
  std::vector<uint64_t> ticks(count);
  VK_CHECK(vkGetQueryPoolResults(device_->handle(), pool_, 0, count, count * sizeof(uint64_t),
                                 ticks.data(), sizeof(uint64_t),
                                 VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  std::vector<double> ms(count);
  for (uint32_t i = 0; i < count; ++i)
    ms[i] = double(ticks[i] - ticks[0]) * device_->timestamp_period_ns() * 1e-6;
  return ms;
}

}  // namespace vkr::vk
