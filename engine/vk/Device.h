#pragma once
// The one headless Vulkan device of a run: instance, physical-device choice (a GPU first,
// Mesa lavapipe as the fallback), one queue that does graphics + compute + transfer, and the
// validation layer when asked for. No window code anywhere (headless: docs/internals/OVERVIEW.md).

#include <vulkan/vulkan.h>

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace vkr::vk {

struct DeviceCreateInfo {
  // Index into ListDevices(); -1 picks VKRECON_DEVICE if set, else the best device
  // (discrete GPU > integrated > virtual > CPU).
  int device_index = -1;
  // Enables VK_LAYER_KHRONOS_validation and records its messages. Also switched on by
  // VKRECON_VALIDATION=1 in the environment (the tests set it).
  bool validation = false;
};

struct PhysicalDeviceInfo {
  int index = 0;
  std::string name;
  std::string type;  // "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
  std::string api_version;
  std::string driver;
  uint64_t device_local_bytes = 0;
  bool usable = false;  // supports Vulkan 1.3 and the features vkrecon needs
  std::string why_not;  // when !usable
};

// Enumerates devices with a throw-away instance (for `vkrecon devices`).
std::vector<PhysicalDeviceInfo> ListDevices();

// How a resource's memory is used; raw memory-property flags never leave engine/vk.
enum class MemoryUse {
  Device,    // GPU only
  Upload,    // host writes, GPU reads (mapped, coherent)
  Readback,  // GPU writes, host reads (mapped, coherent, cached when possible)
};

class Device {
 public:
  explicit Device(const DeviceCreateInfo& info = {});
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkDevice handle() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  std::string name() const { return properties_.deviceName; }
  bool is_cpu() const { return properties_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  // The default subgroup size (lanes that run in lockstep: 8 on lavapipe, 32 on NVIDIA).
  uint32_t subgroup_size() const { return subgroup_size_; }
  // Whether a compute pipeline may require that size (else the device has only one size).
  bool compute_subgroup_size_can_be_required() const { return compute_subgroup_size_can_be_required_; }
  // Nanoseconds per timestamp tick.
  double timestamp_period_ns() const { return properties_.limits.timestampPeriod; }

  uint32_t FindMemoryType(uint32_t type_bits, MemoryUse use) const;
  // The largest device-local heap, and the most one allocation may take
  // (maxMemoryAllocationSize): what a likelihood's memory plan is checked against before
  // anything is allocated (pipelines/likelihood/MemoryPlan.h).
  uint64_t device_local_heap_bytes() const;
  uint64_t max_allocation_bytes() const { return max_allocation_bytes_; }
  // Bytes currently allocated through Buffer/GpuImage (for bench's memory report).
  uint64_t allocated_bytes() const { return allocated_bytes_; }
  void CountAllocation(int64_t delta) { allocated_bytes_ += delta; }

  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Warnings and errors reported by the validation layer so far.
  std::vector<std::string> validation_messages() const;

  void WaitIdle() const;

 private:
  void Release();
  static VKAPI_ATTR VkBool32 VKAPI_CALL OnValidationMessage(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  uint32_t subgroup_size_ = 1;
  bool compute_subgroup_size_can_be_required_ = false;
  uint64_t max_allocation_bytes_ = 0;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  uint64_t allocated_bytes_ = 0;

  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

}  // namespace vkr::vk
