#include <gtest/gtest.h>

#include <cstring>
#include <numeric>
#include <random>

#include "engine/vk/Check.h"
#include "engine/vk/Commands.h"
#include "tests/common/GpuTest.h"

namespace vkr::vk {
namespace {

using test::GpuTest;

TEST(VkCheck, ThrowsWithCallAndResultName) {
  auto allocate_too_much = [] { return VK_ERROR_OUT_OF_DEVICE_MEMORY; };
  try {
    VK_CHECK(allocate_too_much());
    FAIL() << "VK_CHECK did not throw";
  } catch (const VulkanError& e) {
    EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
    EXPECT_NE(std::string(e.what()).find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("allocate_too_much()"), std::string::npos) << e.what();
  }
}

TEST(Devices, ListsAtLeastOneUsableDevice) {
  const auto devices = ListDevices();
  ASSERT_FALSE(devices.empty());
  EXPECT_TRUE(std::any_of(devices.begin(), devices.end(), [](const auto& d) { return d.usable; }));
}

TEST(Devices, RejectsAnIndexThatDoesNotExist) {
  DeviceCreateInfo info;
  info.device_index = 999;
  EXPECT_THROW(Device{info}, std::runtime_error);
}

TEST_F(GpuTest, ValidationLayerIsOnAndCatchesMisuse) {
  ASSERT_TRUE(device().validation_enabled());
  // A separate device, so the deliberate error does not fail the other tests.
  DeviceCreateInfo info;
  info.validation = true;
  Device d(info);
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = 0;  // invalid: VUID-VkBufferCreateInfo-size-00912
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  vkCreateBuffer(d.handle(), &bi, nullptr, &buffer);
  if (buffer) vkDestroyBuffer(d.handle(), buffer, nullptr);
  EXPECT_FALSE(d.validation_messages().empty());
}

TEST_F(GpuTest, BufferRoundTripThroughDeviceMemory) {
  Transfer transfer(device());
  std::vector<uint32_t> data(100000);
  std::iota(data.begin(), data.end(), 7u);
  Buffer buffer(device(), data.size() * 4,
                VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                MemoryUse::Device);
  transfer.UploadBuffer(buffer, data.data(), data.size() * 4);
  std::vector<uint32_t> back(data.size());
  transfer.ReadBuffer(buffer, 0, back.size() * 4, back.data());
  EXPECT_EQ(back, data);
}

TEST_F(GpuTest, ImageRoundTripIsExact) {
  Transfer transfer(device());
  GpuImage image(device(), {37, 21, 1, VK_FORMAT_R32G32B32A32_SFLOAT,
                            VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                                VK_IMAGE_USAGE_TRANSFER_SRC_BIT});
  std::vector<float> texels(37 * 21 * 4);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (float& t : texels) t = u(rng);
  transfer.UploadImage(image, 0, texels.data(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  std::vector<float> back(texels.size());
  transfer.ReadImage(image, 0, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, back.data());
  EXPECT_EQ(0, std::memcmp(back.data(), texels.data(), texels.size() * 4));
}

TEST_F(GpuTest, TimestampsAdvanceAcrossWork) {
  CommandContext context(device());
  TimestampQueries queries(device(), 2);
  Buffer a(device(), 64 << 20, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
           MemoryUse::Device);
  Buffer b(device(), 64 << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Device);
  VkCommandBuffer cmd = context.Begin();
  queries.Reset(cmd);
  queries.Write(cmd, 0);
  // The barrier keeps the first timestamp from floating past the copy (LAVAPIPE.md).
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  vkCmdFillBuffer(cmd, a.handle(), 0, VK_WHOLE_SIZE, 0x12345678u);
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT);
  VkBufferCopy region{0, 0, 64 << 20};
  vkCmdCopyBuffer(cmd, a.handle(), b.handle(), 1, &region);
  MemoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
  queries.Write(cmd, 1);
  context.SubmitAndWait();
  const auto ms = queries.ReadMs(2);
  EXPECT_EQ(ms[0], 0.0);
  EXPECT_GT(ms[1], 0.0);
  EXPECT_LT(ms[1], 10000.0);
}

TEST_F(GpuTest, AllocationsAreCountedAndReleased) {
  const uint64_t before = device().allocated_bytes();
  {
    Buffer b(device(), 1 << 20, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUse::Upload);
    EXPECT_GE(device().allocated_bytes(), before + (1 << 20));
    ASSERT_NE(b.mapped(), nullptr);
    Buffer moved = std::move(b);
    EXPECT_EQ(b.handle(), VK_NULL_HANDLE);
  }
  EXPECT_EQ(device().allocated_bytes(), before);
}

}  // namespace
}  // namespace vkr::vk
