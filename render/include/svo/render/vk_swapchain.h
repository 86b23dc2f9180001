// Shows host images in a window: a Vulkan swapchain on the surface of a
// presenting Context (ContextOptions::create_surface). Each present uploads
// 8-bit sRGB pixels to a transfer image and blits them, scaled to the window,
// into the acquired swapchain image. Knows nothing of the windowing library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "svo/render/vk_context.h"

namespace svo::vk {

class Swapchain {
 public:
  // `context` must have a surface, and must outlive the swapchain.
  // `width` x `height`: the window's framebuffer in pixels, used when the
  // surface leaves the extent to the application; 0 x 0 (a minimised window)
  // creates no swapchain until resize().
  // @throw Error when the surface cannot take transfer writes, when no surface
  //        format can be a blit destination, or on any Vulkan failure.
  Swapchain(Context& context, uint32_t width, uint32_t height);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Recreates the swapchain for the window's new framebuffer size.
  void resize(uint32_t width, uint32_t height);

  // Presents `rgba` (width x height pixels, row-major, top row first, bytes
  // R, G, B, A, sRGB-encoded), stretched over the whole window with a linear
  // filter. Returns when the GPU copy is done (the span may then be reused).
  // Returns false when the swapchain no longer matches the window (out of
  // date, suboptimal, or no swapchain because the window is minimised): call
  // resize() with the window's size and present again.
  // @throw std::invalid_argument when rgba.size() != width * height * 4 or a side is 0;
  //        Error on Vulkan failures.
  bool present(std::span<const uint8_t> rgba, uint32_t width, uint32_t height);

  VkExtent2D extent() const { return extent_; }  // 0 x 0 without a swapchain
  VkFormat format() const { return format_; }

 private:
  void release();  // destroys every handle created so far
  void create(uint32_t width, uint32_t height);
  void destroy_swapchain();
  void ensure_source(uint32_t width, uint32_t height);  // staging buffer and transfer image of this size
  void destroy_source();

  Context& context_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<VkSemaphore> blitted_;  // per swapchain image: the blit is done, present may read

  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkSemaphore acquired_ = VK_NULL_HANDLE;

  // The uploaded picture: host-visible staging buffer, then a transfer image.
  uint32_t source_width_ = 0, source_height_ = 0;
  VkFormat source_format_ = VK_FORMAT_UNDEFINED;  // R8G8B8A8, UNORM or SRGB like the swapchain's
  VkBuffer staging_ = VK_NULL_HANDLE;
  VkDeviceMemory staging_memory_ = VK_NULL_HANDLE;
  void* staging_mapped_ = nullptr;
  VkImage source_ = VK_NULL_HANDLE;
  VkDeviceMemory source_memory_ = VK_NULL_HANDLE;
};

}  // namespace svo::vk
