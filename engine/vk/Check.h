#pragma once
// Every VkResult is checked; a failure throws VulkanError naming the call and the result.

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace vkr::vk {

const char* ResultName(VkResult result);

class VulkanError : public std::runtime_error {
 public:
  VulkanError(VkResult result, const std::string& call);
  VkResult result() const { return result_; }

 private:
  VkResult result_;
};

}  // namespace vkr::vk

#define VK_CHECK(call)                                                   \
  do {                                                                   \
    const VkResult vk_check_result_ = (call);                            \
    if (vk_check_result_ != VK_SUCCESS)                                  \
      throw ::vkr::vk::VulkanError(vk_check_result_, #call);             \
  } while (0)
