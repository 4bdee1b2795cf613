#pragma once
// Move-only owners of Vulkan objects: buffers and images with their memory (asked for by
// intent, see MemoryUse), and a generic handle for everything that is just create/destroy.
// All of them are made once per run, never per hypothesis.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <utility>

#include "engine/vk/Device.h"

namespace vkr::vk {

// A VkXxx handle destroyed with vkDestroyXxx(device, handle, nullptr).
template <class H, void (*Destroy)(VkDevice, H, const VkAllocationCallbacks*)>
class Handle {
 public:
  Handle() = default;
  Handle(VkDevice device, H handle) : device_(device), handle_(handle) {}
  ~Handle() { Reset(); }
  Handle(Handle&& o) noexcept
      : device_(o.device_), handle_(std::exchange(o.handle_, VK_NULL_HANDLE)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      Reset();
      device_ = o.device_;
      handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  H get() const { return handle_; }
  operator H() const { return handle_; }
  void Reset() {
    if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
    handle_ = VK_NULL_HANDLE;
  }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  H handle_ = VK_NULL_HANDLE;
};

using ShaderModule = Handle<VkShaderModule, vkDestroyShaderModule>;
using Pipeline = Handle<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = Handle<VkPipelineLayout, vkDestroyPipelineLayout>;
using DescriptorSetLayout = Handle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = Handle<VkDescriptorPool, vkDestroyDescriptorPool>;
using Sampler = Handle<VkSampler, vkDestroySampler>;
using Fence = Handle<VkFence, vkDestroyFence>;
using CommandPool = Handle<VkCommandPool, vkDestroyCommandPool>;
using QueryPool = Handle<VkQueryPool, vkDestroyQueryPool>;
using ImageView = Handle<VkImageView, vkDestroyImageView>;

class Buffer {
 public:
  Buffer() = default;
  Buffer(Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
  ~Buffer();
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // Persistently mapped pointer for Upload and Readback buffers; null for Device ones.
  void* mapped() const { return mapped_; }
  template <class T>
  T* data() const { return static_cast<T*>(mapped_); }

 private:
  void Release();
  Device* device_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0, allocated_ = 0;
  void* mapped_ = nullptr;
};

struct GpuImageInfo {
  uint32_t width = 1, height = 1;
  uint32_t layers = 1;  // > 1 gives a 2D-array view
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkImageUsageFlags usage = 0;
  bool array_view = false;  // a 2D-array view even for one layer (shaders declaring arrays)
  uint32_t mip_levels = 1;  // mip m is max(1, width >> m) × max(1, height >> m)
};

// A 2D (array) image in device memory with one view over all its layers.
class GpuImage {
 public:
  GpuImage() = default;
  GpuImage(Device& device, const GpuImageInfo& info);
  ~GpuImage();
  GpuImage(GpuImage&& o) noexcept { *this = std::move(o); }
  GpuImage& operator=(GpuImage&& o) noexcept;
  GpuImage(const GpuImage&) = delete;
  GpuImage& operator=(const GpuImage&) = delete;

  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }
  const GpuImageInfo& info() const { return info_; }
  VkImageAspectFlags aspect() const;
  // Size of one layer's texels in bytes.
  VkDeviceSize layer_bytes() const;

 private:
  void Release();
  Device* device_ = nullptr;
  GpuImageInfo info_;
  VkImage image_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize allocated_ = 0;
};

uint32_t BytesPerTexel(VkFormat format);
bool IsDepthFormat(VkFormat format);

// A 2D view of one layer of an array image (to render into that layer).
ImageView CreateLayerView(const Device& device, const GpuImage& image, uint32_t layer);
Sampler CreateNearestClampSampler(const Device& device);
// Linear within and between mips (trilinear), for prefiltered sampling with textureLod.
Sampler CreateTrilinearClampSampler(const Device& device);

ShaderModule CreateShaderModule(const Device& device, const uint32_t* code, size_t bytes);
Sampler CreateLinearClampSampler(const Device& device);

}  // namespace vkr::vk
