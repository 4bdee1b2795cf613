#include "engine/vk/Device.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <optional>

#include "engine/vk/Check.h"

namespace vkr::vk {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool EnvFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

bool HasLayer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

VkInstance CreateInstance(bool validation, const VkDebugUtilsMessengerCreateInfoEXT* messenger) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "vkrecon";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  const char* layers[] = {kValidationLayer};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  if (validation) {
    if (!HasLayer(kValidationLayer))
      throw std::runtime_error(
          "validation requested but VK_LAYER_KHRONOS_validation is not installed "
          "(Debian package vulkan-validationlayers)");
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = layers;
    ci.enabledExtensionCount = 1;
    ci.ppEnabledExtensionNames = extensions;
    ci.pNext = messenger;  // also report problems of instance creation itself
  }
  VkInstance instance = VK_NULL_HANDLE;
  VK_CHECK(vkCreateInstance(&ci, nullptr, &instance));
  return instance;
}

std::vector<VkPhysicalDevice> PhysicalDevices(VkInstance instance) {
  uint32_t n = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &n, nullptr));
  std::vector<VkPhysicalDevice> devices(n);
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &n, devices.data()));
  return devices;
}

const char* TypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

int TypeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 4;
    default: return 3;
  }
}

std::optional<uint32_t> UniversalQueueFamily(VkPhysicalDevice pd) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  for (uint32_t i = 0; i < n; ++i) {
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0) return i;
  }
  return std::nullopt;
}

// The Vulkan 1.1–1.3 features vkrecon relies on; the chain is filled by a query or used to
// enable exactly these.
struct FeatureChain {
  VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan11Features v11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES};
  VkPhysicalDeviceFeatures2 core{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  FeatureChain() {
    core.pNext = &v11;
    v11.pNext = &v13;
  }
  FeatureChain(const FeatureChain&) = delete;
};

// Why a device cannot run vkrecon, or empty.
std::string Unusable(VkPhysicalDevice pd) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  if (p.apiVersion < VK_API_VERSION_1_3) return "needs Vulkan 1.3";
  if (!UniversalQueueFamily(pd)) return "no graphics+compute queue with timestamps";
  FeatureChain f;
  vkGetPhysicalDeviceFeatures2(pd, &f.core);
  if (!f.v13.dynamicRendering) return "no dynamicRendering";
  if (!f.v13.synchronization2) return "no synchronization2";
  if (!f.v13.maintenance4) return "no maintenance4";
  if (!f.v11.multiview) return "no multiview";
  if (!f.v13.subgroupSizeControl || !f.v13.computeFullSubgroups) return "no subgroup size control";
  VkPhysicalDeviceVulkan13Properties p13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
  VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES, &p13};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p11};
  vkGetPhysicalDeviceProperties2(pd, &p2);
  // The composite pass sums within one subgroup of the default size (CompositePass.cpp).
  if (!(p11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
      !(p11.subgroupSupportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT))
    return "no subgroup arithmetic in compute shaders";
  if (!(p13.requiredSubgroupSizeStages & VK_SHADER_STAGE_COMPUTE_BIT) && p13.minSubgroupSize != p13.maxSubgroupSize)
    return "cannot fix the subgroup size of compute shaders";
  return {};
}

std::string VersionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
         "." + std::to_string(VK_API_VERSION_PATCH(v));
}

PhysicalDeviceInfo Describe(int index, VkPhysicalDevice pd) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
  vkGetPhysicalDeviceProperties2(pd, &props);
  VkPhysicalDeviceMemoryProperties mem;
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);
  PhysicalDeviceInfo info;
  info.index = index;
  info.name = props.properties.deviceName;
  info.type = TypeName(props.properties.deviceType);
  info.api_version = VersionString(props.properties.apiVersion);
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  for (uint32_t h = 0; h < mem.memoryHeapCount; ++h)
    if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.device_local_bytes += mem.memoryHeaps[h].size;
  info.why_not = Unusable(pd);
  info.usable = info.why_not.empty();
  return info;
}

int ChooseDevice(const std::vector<VkPhysicalDevice>& devices, int requested) {
  if (devices.empty()) throw std::runtime_error("no Vulkan device found (is mesa-vulkan-drivers installed?)");
  if (requested < 0) {
    if (const char* env = std::getenv("VKRECON_DEVICE"); env && *env) {
      char* end = nullptr;
      const long v = std::strtol(env, &end, 10);
      if (*end != '\0' || v < 0)
        throw std::runtime_error(std::string("VKRECON_DEVICE must be a device index, got '") + env + "'");
      requested = int(v);
    }
  }
  if (requested >= 0) {
    if (requested >= int(devices.size()))
      throw std::runtime_error("device " + std::to_string(requested) + " does not exist (" +
                               std::to_string(devices.size()) + " found; see `vkrecon devices`)");
    if (const std::string why = Unusable(devices[requested]); !why.empty())
      throw std::runtime_error("device " + std::to_string(requested) + " cannot run vkrecon: " + why);
    return requested;
  }
  int best = -1, best_rank = 1 << 30;
  for (int i = 0; i < int(devices.size()); ++i) {
    if (!Unusable(devices[i]).empty()) continue;
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    if (TypeRank(p.deviceType) < best_rank) best = i, best_rank = TypeRank(p.deviceType);
  }
  if (best < 0) throw std::runtime_error("no Vulkan 1.3 device with the features vkrecon needs (see `vkrecon devices`)");
  return best;
}

}  // namespace

std::vector<PhysicalDeviceInfo> ListDevices() {
  VkInstance instance = CreateInstance(false, nullptr);
  std::vector<PhysicalDeviceInfo> out;
  try {
    const auto devices = PhysicalDevices(instance);
    for (int i = 0; i < int(devices.size()); ++i) out.push_back(Describe(i, devices[i]));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return out;
}

Device::Device(const DeviceCreateInfo& info) {
  const bool validation = info.validation || EnvFlag("VKRECON_VALIDATION");
  VkDebugUtilsMessengerCreateInfoEXT mci{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  mci.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                        VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  mci.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  mci.pfnUserCallback = &Device::OnValidationMessage;
  mci.pUserData = this;
  instance_ = CreateInstance(validation, &mci);
  try {
    if (validation) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw std::runtime_error("vkCreateDebugUtilsMessengerEXT not available");
      VK_CHECK(create(instance_, &mci, nullptr, &messenger_));
    }
    const auto devices = PhysicalDevices(instance_);
    physical_ = devices[ChooseDevice(devices, info.device_index)];
    vkGetPhysicalDeviceProperties(physical_, &properties_);
    VkPhysicalDeviceVulkan13Properties p13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_PROPERTIES};
    VkPhysicalDeviceVulkan11Properties p11{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES, &p13};
    VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &p11};
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    subgroup_size_ = p11.subgroupSize;
    max_allocation_bytes_ = p11.maxMemoryAllocationSize;
    compute_subgroup_size_can_be_required_ = (p13.requiredSubgroupSizeStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    queue_family_ = *UniversalQueueFamily(physical_);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queue_family_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;

    FeatureChain enable;
    enable.v13.dynamicRendering = VK_TRUE;
    enable.v13.synchronization2 = VK_TRUE;
    // SPIR-V 1.6 (Vulkan 1.3 target) needs maintenance4 or validation complains.
    enable.v13.maintenance4 = VK_TRUE;
    enable.v11.multiview = VK_TRUE;
    enable.v13.subgroupSizeControl = VK_TRUE;
    enable.v13.computeFullSubgroups = VK_TRUE;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.pNext = &enable.core;
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    VK_CHECK(vkCreateDevice(physical_, &dci, nullptr, &device_));
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  } catch (...) {
    Release();
    throw;
  }
}

Device::~Device() { Release(); }

void Device::Release() {
  if (device_) vkDestroyDevice(device_, nullptr);
  device_ = VK_NULL_HANDLE;
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  instance_ = VK_NULL_HANDLE;
}

uint64_t Device::device_local_heap_bytes() const {
  uint64_t largest = 0;
  for (uint32_t h = 0; h < memory_.memoryHeapCount; ++h)
    if (memory_.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      largest = std::max<uint64_t>(largest, memory_.memoryHeaps[h].size);
  return largest;
}

uint32_t Device::FindMemoryType(uint32_t type_bits, MemoryUse use) const {
  VkMemoryPropertyFlags required = 0, preferred = 0;
  switch (use) {
    case MemoryUse::Device:
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
    case MemoryUse::Upload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
    case MemoryUse::Readback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
  }
  int fallback = -1;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags flags = memory_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (fallback < 0) fallback = int(i);
  }
  if (fallback < 0) throw std::runtime_error("no Vulkan memory type fits the request");
  return uint32_t(fallback);
}

std::vector<std::string> Device::validation_messages() const {
  std::lock_guard<std::mutex> lock(messages_mutex_);
  return messages_;
}

void Device::WaitIdle() const { VK_CHECK(vkDeviceWaitIdle(device_)); }

VKAPI_ATTR VkBool32 VKAPI_CALL Device::OnValidationMessage(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Device*>(user);
  const std::string text =
      std::string(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning") +
      ": " + (data && data->pMessage ? data->pMessage : "(no message)");
  std::cerr << "vulkan validation " << text << "\n";
  std::lock_guard<std::mutex> lock(self->messages_mutex_);
  self->messages_.push_back(text);
  return VK_FALSE;
}

}  // namespace vkr::vk
