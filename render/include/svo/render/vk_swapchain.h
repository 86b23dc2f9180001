// Shows host images in a window: a Vulkan swapchain on the surface of a
// presenting Context (ContextOptions::create_surface). Each present scales
// 8-bit sRGB pixels to the window on the host (bilinear), writes them to a
// staging buffer in the swapchain's byte order and copies them into the
// acquired swapchain image (vkCmdCopyBufferToImage: no shader runs, so the
// path works on any device whose surface takes transfer writes). Knows
// nothing of the windowing library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "svo/render/vk_context.h"

namespace svo::vk {

// `src` (w x h pixels, bytes R, G, B, A) stretched over `dst` (W x H pixels,
// 4 bytes each: B, G, R, 255 when `bgra`, else R, G, B, 255) with a bilinear
// filter on pixel centres, edges clamped; a plain copy when the sizes match.
// @throw std::invalid_argument when a span does not hold its pixels or a side is 0.
void stretch_rgba8(std::span<const uint8_t> src, uint32_t w, uint32_t h, std::span<uint8_t> dst, uint32_t W, uint32_t H,
                   bool bgra);

class Swapchain {
 public:
  // `context` must have a surface, and must outlive the swapchain.
  // `width` x `height`: the window's framebuffer in pixels, used when the
  // surface leaves the extent to the application; 0 x 0 (a minimised window)
  // creates no swapchain until resize().
  // @throw Error when the surface cannot take transfer writes, when it offers
  //        no 8-bit RGBA or BGRA format in the sRGB colour space, or on any
  //        Vulkan failure.
  Swapchain(Context& context, uint32_t width, uint32_t height);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Recreates the swapchain for the window's new framebuffer size.
  void resize(uint32_t width, uint32_t height);

  // Presents `rgba` (width x height pixels, row-major, top row first, bytes
  // R, G, B, A, sRGB-encoded; A is ignored: the window is opaque), stretched
  // over the whole window with a bilinear filter. Returns when the GPU copy is done.
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
  void ensure_staging(VkDeviceSize bytes);
  void destroy_staging();

  Context& context_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  bool bgra_ = false;  // the swapchain's bytes are B, G, R, A
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<VkSemaphore> copied_;  // per swapchain image: the copy is done, present may read

  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkSemaphore acquired_ = VK_NULL_HANDLE;

  // The picture at the swapchain's size, host-visible and mapped.
  VkDeviceSize staging_bytes_ = 0;
  VkBuffer staging_ = VK_NULL_HANDLE;
  VkDeviceMemory staging_memory_ = VK_NULL_HANDLE;
  uint8_t* staging_mapped_ = nullptr;
};

}  // namespace svo::vk
