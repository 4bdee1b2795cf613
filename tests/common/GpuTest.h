#pragma once
// A test fixture sharing one Vulkan device per test binary, with the validation layer on;
// any message the layer reports during a test fails that test.

#include <gtest/gtest.h>

#include <memory>

#include "engine/vk/Device.h"

namespace vkr::test {

class GpuTest : public ::testing::Test {
 public:
  static vk::Device& device() {
    static std::unique_ptr<vk::Device> device = [] {
      vk::DeviceCreateInfo info;
      info.validation = true;
      return std::make_unique<vk::Device>(info);
    }();
    return *device;
  }

 protected:
  void SetUp() override { messages_before_ = device().validation_messages().size(); }
  void TearDown() override {
    const auto messages = device().validation_messages();
    for (size_t i = messages_before_; i < messages.size(); ++i)
      ADD_FAILURE() << "validation: " << messages[i];
  }

 private:
  size_t messages_before_ = 0;
};

}  // namespace vkr::test
