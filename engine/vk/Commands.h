#pragma once
// Command recording and submission (one-shot and batched), barriers, the one upload /
// readback helper, and GPU timestamps.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "engine/vk/Device.h"
#include "engine/vk/Resources.h"

namespace vkr::vk {

// One primary command buffer and its fence, reused for every submission: Begin() →
// record → Submit() → … → Wait(), or SubmitAndWait(). Recording again waits for the last
// submission first, so a context never races itself.
class CommandContext {
 public:
  explicit CommandContext(Device& device);
  ~CommandContext();
  CommandContext(const CommandContext&) = delete;
  CommandContext& operator=(const CommandContext&) = delete;

  VkCommandBuffer Begin();
  void Submit();
  void Wait();
  void SubmitAndWait() {
    Submit();
    Wait();
  }
  Device& device() const { return *device_; }

 private:
  Device* device_;
  CommandPool pool_;
  Fence fence_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  bool recording_ = false, pending_ = false;
};

// A layout transition / execution dependency on every layer of `image`.
void ImageBarrier(VkCommandBuffer cmd, const GpuImage& image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                  VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);
// A global memory dependency (buffers, or images whose layout does not change).
void MemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// Moves data between host and device outside the sampling loop (set-up, dumps, tests):
// barrier → copy → fence → map, in one place. Its staging buffers grow on demand.
class Transfer {
 public:
  explicit Transfer(Device& device);

  void UploadBuffer(const Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  // Fills one layer of `dst` (tightly packed texels of its format) and leaves it in `final_layout`,
  // visible to fragment and compute shaders.
  void UploadImage(const GpuImage& dst, uint32_t layer, const void* data, VkImageLayout final_layout);
  // Copies one layer of `src`, which is in `layout` and was last written by any stage, to
  // `out` (layer_bytes()); the image stays in `layout`.
  // Fills every mip of a one-layer image; mips[m] holds mip m's texels tightly packed.
  void UploadMipChain(const GpuImage& dst, const std::vector<const void*>& mips, VkImageLayout final_layout);
  void ReadImage(const GpuImage& src, uint32_t layer, VkImageLayout layout, void* out);
  void ReadBuffer(const Buffer& src, VkDeviceSize offset, VkDeviceSize bytes, void* out);

 private:
  Buffer& Staging(Buffer& buffer, VkDeviceSize bytes, MemoryUse use);
  Device* device_;
  CommandContext context_;
  Buffer upload_, readback_;
};

// A pool of GPU timestamps. Write() after the work to time and a barrier, Read() after the
// submission completed; ticks are converted to milliseconds.
class TimestampQueries {
 public:
  TimestampQueries(Device& device, uint32_t count);
  void Reset(VkCommandBuffer cmd);
  void Write(VkCommandBuffer cmd, uint32_t index,
             VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT);
  // Milliseconds of each timestamp relative to the first.
  std::vector<double> ReadMs(uint32_t count);
  uint32_t capacity() const { return count_; }

 private:
  Device* device_;
  QueryPool pool_;
  uint32_t count_;
};

}  // namespace vkr::vk
