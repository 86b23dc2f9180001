// Device selection, limits and the validation plumbing of the Vulkan harness.
#include "svo/render/vk_context.h"

#include <gtest/gtest.h>

#include <cstring>

#include "svo/render/vk_compute.h"

namespace {
using svo::vk::DeviceInfo;

std::vector<DeviceInfo> fake_devices() {
  std::vector<DeviceInfo> d(3);
  d[0].index = 0, d[0].name = "llvmpipe (LLVM 15.0.6, 256 bits)", d[0].type = "cpu";
  d[1].index = 1, d[1].name = "Intel(R) UHD Graphics 630", d[1].type = "integrated";
  d[2].index = 2, d[2].name = "NVIDIA GeForce RTX 4090", d[2].type = "discrete";
  return d;
}

TEST(DeviceSelection, DefaultPrefersDiscreteThenIntegratedThenCpu) {
  auto d = fake_devices();
  EXPECT_EQ(svo::vk::select_device(d, ""), 2u);
  d.pop_back();
  EXPECT_EQ(svo::vk::select_device(d, ""), 1u);
  d.pop_back();
  EXPECT_EQ(svo::vk::select_device(d, ""), 0u);
}

TEST(DeviceSelection, ByIndexOrUniqueNameSubstring) {
  auto d = fake_devices();
  EXPECT_EQ(svo::vk::select_device(d, "0"), 0u);
  EXPECT_EQ(svo::vk::select_device(d, "llvmpipe"), 0u);
  EXPECT_EQ(svo::vk::select_device(d, "rtx"), 2u);
  EXPECT_THROW(svo::vk::select_device(d, "7"), svo::vk::Error);
  EXPECT_THROW(svo::vk::select_device(d, "radeon"), svo::vk::Error);
  try {
    svo::vk::select_device(d, "i");  // matches all three
    FAIL() << "ambiguous selector accepted";
  } catch (const svo::vk::Error& e) {
    EXPECT_NE(std::string(e.what()).find("matches 3 devices"), std::string::npos) << e.what();
  }
}

TEST(VulkanContext, FindsADeviceWithCompute) {
  auto devices = svo::vk::list_devices();
  ASSERT_FALSE(devices.empty());
  svo::vk::Context context({"", true});
  EXPECT_FALSE(context.info().name.empty());
  EXPECT_GT(context.info().max_storage_buffer_range, 0u);
  EXPECT_TRUE(context.validation_messages().empty());
}

TEST(VulkanContext, OversizedBufferIsRefusedNamingTheLimit) {
  svo::vk::Context context({"", true});
  size_t too_big = size_t(context.info().max_storage_buffer_range) + 16;
  try {
    svo::vk::Buffer buffer(context, too_big);
    FAIL() << "a buffer beyond maxStorageBufferRange was created";
  } catch (const svo::vk::Error& e) {
    EXPECT_NE(std::string(e.what()).find("maxStorageBufferRange"), std::string::npos) << e.what();
  }
  EXPECT_THROW(svo::vk::Buffer(context, 0), svo::vk::Error);
  EXPECT_TRUE(context.validation_messages().empty());
}

// The "validation on and silent" checks mean something only if a misuse is
// reported: create a buffer with size 0 behind our wrapper's back.
TEST(VulkanContext, ValidationReportsMisuse) {
  svo::vk::Context context({"", true});
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = 0;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkResult r = vkCreateBuffer(context.device(), &info, nullptr, &buffer);
  if (r == VK_SUCCESS && buffer) vkDestroyBuffer(context.device(), buffer, nullptr);
  auto messages = context.validation_messages();
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages[0].find("size"), std::string::npos) << messages[0];
}

TEST(VulkanCompute, KernelRefusesWhatIsNotSpirv) {
  svo::vk::Context context({"", true});
  // Handed to the driver, these crash lavapipe; the wrapper refuses them first.
  static const uint32_t kWords[] = {0x07230203u, 0xdeadbeefu};
  EXPECT_THROW(svo::vk::ComputeKernel(context, std::span<const uint32_t>(kWords, 0), 1, 0), svo::vk::Error);
  EXPECT_THROW(svo::vk::ComputeKernel(context, std::span<const uint32_t>(kWords + 1, 1), 1, 0), svo::vk::Error);
  EXPECT_TRUE(context.validation_messages().empty());
}

}  // namespace
