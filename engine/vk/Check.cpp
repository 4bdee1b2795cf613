#include "engine/vk/Check.h"

namespace vkr::vk {

const char* ResultName(VkResult result) {
  switch (result) {
#define VKR_CASE(x) \
  case x:           \
    return #x;
    VKR_CASE(VK_SUCCESS)
    VKR_CASE(VK_NOT_READY)
    VKR_CASE(VK_TIMEOUT)
    VKR_CASE(VK_EVENT_SET)
    VKR_CASE(VK_EVENT_RESET)
    VKR_CASE(VK_INCOMPLETE)
    VKR_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    VKR_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    VKR_CASE(VK_ERROR_INITIALIZATION_FAILED)
    VKR_CASE(VK_ERROR_DEVICE_LOST)
    VKR_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    VKR_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    VKR_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    VKR_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    VKR_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    VKR_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    VKR_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    VKR_CASE(VK_ERROR_FRAGMENTED_POOL)
    VKR_CASE(VK_ERROR_UNKNOWN)
    VKR_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    VKR_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    VKR_CASE(VK_ERROR_FRAGMENTATION)
    VKR_CASE(VK_PIPELINE_COMPILE_REQUIRED)
#undef VKR_CASE
    default:
      return "VK_RESULT_UNKNOWN";
  }
}

VulkanError::VulkanError(VkResult result, const std::string& call)
    : std::runtime_error(call + " failed: " + ResultName(result) + " (" +
                         std::to_string(int(result)) + ")"),
      result_(result) {}

}  // namespace vkr::vk
