// Vulkan failures end with a message naming the cause (issue 7). Out of
// device memory and a lost device cannot be provoked on lavapipe on demand:
// here the mapping of their result codes to messages; the missing driver and
// the render size beyond the device's limits are command-line tests
// (CMakeLists.txt).
#include <gtest/gtest.h>

#include "svo/render/vk_context.h"

namespace {

std::string message_of(VkResult result) {
  try {
    svo::vk::check(result, "vkAllocateMemory(...)", "file.cpp", 12);
  } catch (const svo::vk::Error& e) {
    return e.what();
  }
  return "";
}

TEST(VulkanErrors, OutOfDeviceMemoryAndDeviceLostNameTheCause) {
  EXPECT_EQ(message_of(VK_SUCCESS), "");
  std::string oom = message_of(VK_ERROR_OUT_OF_DEVICE_MEMORY);
  EXPECT_NE(oom.find("vkAllocateMemory(...) failed with VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos) << oom;
  EXPECT_NE(oom.find("the device is out of memory"), std::string::npos) << oom;
  std::string lost = message_of(VK_ERROR_DEVICE_LOST);
  EXPECT_NE(lost.find("VK_ERROR_DEVICE_LOST"), std::string::npos) << lost;
  EXPECT_NE(lost.find("the device was lost"), std::string::npos) << lost;
  std::string host = message_of(VK_ERROR_OUT_OF_HOST_MEMORY);
  EXPECT_NE(host.find("VK_ERROR_OUT_OF_HOST_MEMORY"), std::string::npos) << host;
  for (const std::string& m : {oom, lost, host}) EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

}  // namespace
