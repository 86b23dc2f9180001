// Presenting: a Context with a surface and the Swapchain, on a headless
// surface (VK_EXT_headless_surface: lavapipe has it) so that no display is
// needed, validation on; and the host-side stretch into the swapchain's bytes.
#include <gtest/gtest.h>

#include <cstring>
#include <numeric>

#include "svo/render/vk_swapchain.h"

namespace {

bool has_instance_extension(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> all(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, all.data());
  for (const auto& e : all) {
    if (std::strcmp(e.extensionName, name) == 0) return true;
  }
  return false;
}

svo::vk::ContextOptions headless_presenting() {
  svo::vk::ContextOptions options{"", true};
  options.instance_extensions = {VK_KHR_SURFACE_EXTENSION_NAME, VK_EXT_HEADLESS_SURFACE_EXTENSION_NAME};
  options.create_surface = [](VkInstance instance) {
    auto create =
        reinterpret_cast<PFN_vkCreateHeadlessSurfaceEXT>(vkGetInstanceProcAddr(instance, "vkCreateHeadlessSurfaceEXT"));
    if (!create) throw svo::vk::Error("vkCreateHeadlessSurfaceEXT is missing");
    VkHeadlessSurfaceCreateInfoEXT info{VK_STRUCTURE_TYPE_HEADLESS_SURFACE_CREATE_INFO_EXT};
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    SVO_VK_CHECK(create(instance, &info, nullptr, &surface));
    return surface;
  };
  return options;
}

std::vector<uint8_t> gradient(uint32_t w, uint32_t h) {
  std::vector<uint8_t> rgba(size_t(w) * h * 4);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      uint8_t* p = &rgba[(size_t(y) * w + x) * 4];
      p[0] = uint8_t(255 * x / (w - 1)), p[1] = uint8_t(255 * y / (h - 1)), p[2] = 77, p[3] = 0;
    }
  }
  return rgba;
}

TEST(Swapchain, PresentsAndResizesOnAHeadlessSurfaceWithoutValidationMessages) {
  if (!has_instance_extension(VK_EXT_HEADLESS_SURFACE_EXTENSION_NAME)) {
    GTEST_SKIP() << "the Vulkan driver has no " VK_EXT_HEADLESS_SURFACE_EXTENSION_NAME;
  }
  svo::vk::Context context(headless_presenting());
  ASSERT_NE(context.surface(), VK_NULL_HANDLE);
  svo::vk::Swapchain swapchain(context, 64, 48);
  EXPECT_EQ(swapchain.extent().width, 64u);
  EXPECT_EQ(swapchain.extent().height, 48u);
  auto small = gradient(32, 24), same = gradient(64, 48);
  // More presents than the swapchain has images, so that images and semaphores are reused.
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(swapchain.present(i % 2 ? small : same, i % 2 ? 32 : 64, i % 2 ? 24 : 48)) << "present " << i;
  }
  swapchain.resize(40, 30);
  EXPECT_EQ(swapchain.extent().width, 40u);
  EXPECT_TRUE(swapchain.present(small, 32, 24));
  swapchain.resize(0, 0);  // minimised: no swapchain, present says so
  EXPECT_FALSE(swapchain.present(small, 32, 24));
  swapchain.resize(16, 16);
  EXPECT_TRUE(swapchain.present(small, 32, 24));
  EXPECT_THROW(swapchain.present(small, 31, 24), std::invalid_argument);
  auto messages = context.validation_messages();
  EXPECT_TRUE(messages.empty()) << messages.front();
}

TEST(Swapchain, NeedsAContextWithASurface) {
  svo::vk::Context context({"", true});
  EXPECT_EQ(context.surface(), VK_NULL_HANDLE);
  EXPECT_THROW(svo::vk::Swapchain(context, 64, 48), svo::vk::Error);
}

TEST(Swapchain, ContextNamesAMissingInstanceExtension) {
  svo::vk::ContextOptions options;
  options.instance_extensions = {"VK_KHR_no_such_surface"};
  try {
    svo::vk::Context context(options);
    FAIL() << "a missing instance extension was accepted";
  } catch (const svo::vk::Error& e) {
    EXPECT_NE(std::string(e.what()).find("VK_KHR_no_such_surface is not available"), std::string::npos) << e.what();
  }
}

TEST(StretchRgba8, SameSizeSwapsToBgraAndMakesAlphaOpaque) {
  std::vector<uint8_t> src{10, 20, 30, 0, 40, 50, 60, 128};
  std::vector<uint8_t> dst(8);
  svo::vk::stretch_rgba8(src, 2, 1, dst, 2, 1, true);
  EXPECT_EQ(dst, (std::vector<uint8_t>{30, 20, 10, 255, 60, 50, 40, 255}));
  svo::vk::stretch_rgba8(src, 2, 1, dst, 2, 1, false);
  EXPECT_EQ(dst, (std::vector<uint8_t>{10, 20, 30, 255, 40, 50, 60, 255}));
}

TEST(StretchRgba8, DoublingInterpolatesBetweenPixelCentresAndClampsAtEdges) {
  // Two pixels, red 0 and 200: the centres of 4 output pixels fall at source
  // x = -0.25 (clamped to 0), 0.25, 0.75, 1.25 (clamped to 1).
  std::vector<uint8_t> src{0, 0, 0, 255, 200, 0, 0, 255};
  std::vector<uint8_t> dst(4 * 4 * 2);
  svo::vk::stretch_rgba8(src, 2, 1, dst, 4, 2, false);
  const uint8_t expected[4] = {0, 50, 150, 200};
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) EXPECT_EQ(dst[size_t(4 * (y * 4 + x))], expected[x]) << x << "," << y;
  }
}

TEST(StretchRgba8, RefusesSpansThatDoNotHoldThePixels) {
  std::vector<uint8_t> src(16), dst(16);
  EXPECT_THROW(svo::vk::stretch_rgba8(src, 3, 1, dst, 2, 2, false), std::invalid_argument);
  EXPECT_THROW(svo::vk::stretch_rgba8(src, 2, 2, dst, 0, 2, false), std::invalid_argument);
}

}  // namespace
