#include "svo/render/vk_swapchain.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace svo::vk {

namespace {

// Copies do not convert, so the swapchain must hold 8-bit RGBA or BGRA. Our
// bytes are sRGB-encoded: a UNORM format in the sRGB colour space and an SRGB
// format both show them as they are.
VkSurfaceFormatKHR choose_format(VkPhysicalDevice physical, VkSurfaceKHR surface) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data()));
  const VkFormat preferred[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                VK_FORMAT_R8G8B8A8_SRGB};
  for (VkFormat want : preferred) {
    for (const auto& f : formats) {
      if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    }
  }
  std::string offered;
  for (const auto& f : formats) offered += (offered.empty() ? "" : ", ") + std::to_string(int(f.format));
  throw Error("Vulkan: the window's surface offers no 8-bit RGBA or BGRA format in the sRGB colour space (VkFormat " +
              offered + ")");
}

void barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags src_access,
             VkAccessFlags dst_access, VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

// Where output pixel i of n falls among the m source pixels (pixel centres
// aligned, clamped at the borders): the lower source index and the weight of the next.
struct Tap {
  uint32_t i0, i1;
  float w1;
};
std::vector<Tap> taps(uint32_t n, uint32_t m) {
  std::vector<Tap> t(n);
  for (uint32_t i = 0; i < n; ++i) {
    float x = std::clamp((float(i) + 0.5f) * float(m) / float(n) - 0.5f, 0.0f, float(m - 1));
    uint32_t i0 = std::min(uint32_t(x), m - 1);
    t[i] = {i0, std::min(i0 + 1, m - 1), x - float(i0)};
  }
  return t;
}

}  // namespace

void stretch_rgba8(std::span<const uint8_t> src, uint32_t w, uint32_t h, std::span<uint8_t> out, uint32_t W, uint32_t H,
                   bool bgra) {
  if (w == 0 || h == 0 || W == 0 || H == 0 || src.size() != size_t(w) * h * 4 || out.size() != size_t(W) * H * 4) {
    throw std::invalid_argument("stretch_rgba8: " + std::to_string(src.size()) + " bytes for " + std::to_string(w) +
                                " x " + std::to_string(h) + " pixels to " + std::to_string(out.size()) + " bytes for " +
                                std::to_string(W) + " x " + std::to_string(H));
  }
  uint8_t* dst = out.data();
  const int order[3] = {bgra ? 2 : 0, 1, bgra ? 0 : 2};  // destination byte c takes source channel order[c]
  if (w == W && h == H) {
    for (size_t p = 0; p < size_t(w) * h; ++p) {
      for (int c = 0; c < 3; ++c) dst[4 * p + size_t(c)] = src[4 * p + size_t(order[c])];
      dst[4 * p + 3] = 255;
    }
    return;
  }
  std::vector<Tap> xs = taps(W, w), ys = taps(H, h);
  for (uint32_t y = 0; y < H; ++y) {
    const uint8_t* row0 = src.data() + size_t(ys[y].i0) * w * 4;
    const uint8_t* row1 = src.data() + size_t(ys[y].i1) * w * 4;
    float wy = ys[y].w1;
    uint8_t* row = dst + size_t(y) * W * 4;
    for (uint32_t x = 0; x < W; ++x) {
      const Tap& t = xs[x];
      row[4 * x + 3] = 255;
      for (int c = 0; c < 3; ++c) {
        size_t k = size_t(order[c]);
        float top = float(row0[4 * t.i0 + k]) + t.w1 * (float(row0[4 * t.i1 + k]) - float(row0[4 * t.i0 + k]));
        float bottom = float(row1[4 * t.i0 + k]) + t.w1 * (float(row1[4 * t.i1 + k]) - float(row1[4 * t.i0 + k]));
        row[4 * x + uint32_t(c)] = uint8_t(top + wy * (bottom - top) + 0.5f);
      }
    }
  }
}

Swapchain::Swapchain(Context& context, uint32_t width, uint32_t height) : context_(context) {
  if (!context.surface()) throw Error("Vulkan: a swapchain needs a Context made with a surface");
  VkDevice device = context_.device();
  try {
    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = context_.queue_family();
    SVO_VK_CHECK(vkCreateCommandPool(device, &pool, nullptr, &pool_));
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    SVO_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &cmd_));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    SVO_VK_CHECK(vkCreateFence(device, &fence, nullptr, &fence_));
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    SVO_VK_CHECK(vkCreateSemaphore(device, &semaphore, nullptr, &acquired_));
    create(width, height);
  } catch (...) {
    release();
    throw;
  }
}

Swapchain::~Swapchain() { release(); }

void Swapchain::release() {
  VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  destroy_staging();
  destroy_swapchain();
  if (acquired_) vkDestroySemaphore(device, acquired_, nullptr);
  if (fence_) vkDestroyFence(device, fence_, nullptr);
  if (pool_) vkDestroyCommandPool(device, pool_, nullptr);  // frees cmd_
  acquired_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

void Swapchain::create(uint32_t width, uint32_t height) {
  VkPhysicalDevice physical = context_.physical_device();
  VkSurfaceKHR surface = context_.surface();
  VkSurfaceCapabilitiesKHR caps;
  SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface, &caps));
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
    throw Error("Vulkan: the window's surface on '" + context_.info().name + "' does not accept transfer writes");
  }
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX) {  // the surface takes the swapchain's size
    extent.width = std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  VkSwapchainKHR old = swapchain_;
  if (extent.width == 0 || extent.height == 0 || width == 0 || height == 0) {  // minimised
    destroy_swapchain();
    return;
  }
  VkSurfaceFormatKHR format = choose_format(physical, surface);
  uint32_t images = caps.minImageCount + 1;
  if (caps.maxImageCount > 0) images = std::min(images, caps.maxImageCount);
  VkCompositeAlphaFlagBitsKHR alpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(caps.supportedCompositeAlpha & alpha)) {
    for (uint32_t bit = 1; bit <= VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR; bit <<= 1) {
      if (caps.supportedCompositeAlpha & bit) {
        alpha = VkCompositeAlphaFlagBitsKHR(bit);
        break;
      }
    }
  }

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = images;
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = alpha;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // the one mode every driver has
  info.clipped = VK_TRUE;
  info.oldSwapchain = old;
  VkDevice device = context_.device();
  VkSwapchainKHR fresh = VK_NULL_HANDLE;
  SVO_VK_CHECK(vkCreateSwapchainKHR(device, &info, nullptr, &fresh));
  destroy_swapchain();  // the old one, retired by the new one's creation
  swapchain_ = fresh;
  format_ = format.format;
  bgra_ = format.format == VK_FORMAT_B8G8R8A8_UNORM || format.format == VK_FORMAT_B8G8R8A8_SRGB;
  extent_ = extent;
  uint32_t count = 0;
  SVO_VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, nullptr));
  images_.resize(count);
  SVO_VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, images_.data()));
  copied_.assign(count, VK_NULL_HANDLE);
  VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  for (VkSemaphore& s : copied_) SVO_VK_CHECK(vkCreateSemaphore(device, &semaphore, nullptr, &s));
}

void Swapchain::destroy_swapchain() {
  VkDevice device = context_.device();
  for (VkSemaphore s : copied_) {
    if (s) vkDestroySemaphore(device, s, nullptr);
  }
  copied_.clear();
  images_.clear();
  if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
  swapchain_ = VK_NULL_HANDLE;
  extent_ = {0, 0};
}

void Swapchain::resize(uint32_t width, uint32_t height) {
  // Presents still queued may wait on the semaphores that create() replaces.
  SVO_VK_CHECK(vkDeviceWaitIdle(context_.device()));
  create(width, height);
}

void Swapchain::ensure_staging(VkDeviceSize bytes) {
  if (staging_ && staging_bytes_ == bytes) return;
  destroy_staging();
  VkDevice device = context_.device();
  VkBufferCreateInfo buffer{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  buffer.size = bytes;
  buffer.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  buffer.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  SVO_VK_CHECK(vkCreateBuffer(device, &buffer, nullptr, &staging_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device, staging_, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = context_.memory_type(
      req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  SVO_VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &staging_memory_));
  SVO_VK_CHECK(vkBindBufferMemory(device, staging_, staging_memory_, 0));
  void* mapped = nullptr;
  SVO_VK_CHECK(vkMapMemory(device, staging_memory_, 0, VK_WHOLE_SIZE, 0, &mapped));
  staging_mapped_ = static_cast<uint8_t*>(mapped);
  staging_bytes_ = bytes;
}

void Swapchain::destroy_staging() {
  VkDevice device = context_.device();
  if (staging_) vkDestroyBuffer(device, staging_, nullptr);
  if (staging_memory_) vkFreeMemory(device, staging_memory_, nullptr);  // unmaps
  staging_ = VK_NULL_HANDLE;
  staging_memory_ = VK_NULL_HANDLE;
  staging_mapped_ = nullptr;
  staging_bytes_ = 0;
}

bool Swapchain::present(std::span<const uint8_t> rgba, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0 || rgba.size() != size_t(width) * height * 4) {
    throw std::invalid_argument("Swapchain::present: " + std::to_string(rgba.size()) + " bytes for " +
                                std::to_string(width) + " x " + std::to_string(height) + " RGBA8 pixels");
  }
  if (!swapchain_) return false;
  VkDevice device = context_.device();
  uint32_t index = 0;
  VkResult acquired = vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
  if (acquired == VK_ERROR_OUT_OF_DATE_KHR) return false;
  // Suboptimal still hands out an image and signals the semaphore: present it, then report.
  if (acquired != VK_SUBOPTIMAL_KHR) SVO_VK_CHECK(acquired);

  ensure_staging(VkDeviceSize(extent_.width) * extent_.height * 4);
  stretch_rgba8(rgba, width, height, {staging_mapped_, size_t(staging_bytes_)}, extent_.width, extent_.height, bgra_);

  SVO_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  SVO_VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
  // The acquire semaphore is waited on at the transfer stage; host writes to
  // the staging buffer are visible to the copy because the submission follows them.
  const VkPipelineStageFlags transfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkImage target = images_[index];
  barrier(cmd_, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
          VK_ACCESS_TRANSFER_WRITE_BIT, transfer, transfer);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {extent_.width, extent_.height, 1};
  vkCmdCopyBufferToImage(cmd_, staging_, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  barrier(cmd_, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
          VK_ACCESS_TRANSFER_WRITE_BIT, 0, transfer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  SVO_VK_CHECK(vkEndCommandBuffer(cmd_));

  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &acquired_;
  submit.pWaitDstStageMask = &transfer;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd_;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &copied_[index];
  SVO_VK_CHECK(vkResetFences(device, 1, &fence_));
  SVO_VK_CHECK(vkQueueSubmit(context_.queue(), 1, &submit, fence_));
  SVO_VK_CHECK(vkWaitForFences(device, 1, &fence_, VK_TRUE, UINT64_MAX));

  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &copied_[index];
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &index;
  VkResult shown = vkQueuePresentKHR(context_.queue(), &present);
  if (shown == VK_ERROR_OUT_OF_DATE_KHR || shown == VK_SUBOPTIMAL_KHR) return false;
  SVO_VK_CHECK(shown);
  return acquired == VK_SUCCESS;
}

}  // namespace svo::vk
