#include "svo/render/vk_swapchain.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace svo::vk {

namespace {

bool is_srgb(VkFormat format) {
  switch (format) {
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_A8B8G8R8_SRGB_PACK32:
      return true;
    default:
      return false;
  }
}

bool can_blit_to(VkPhysicalDevice physical, VkFormat format) {
  VkFormatProperties props;
  vkGetPhysicalDeviceFormatProperties(physical, format, &props);
  return props.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT;
}

// Our bytes are already sRGB-encoded, so a UNORM format in the sRGB colour
// space shows them unchanged; an SRGB format works too (the blit decodes and
// re-encodes). Anything else in that colour space that takes blits comes last.
VkSurfaceFormatKHR choose_format(VkPhysicalDevice physical, VkSurfaceKHR surface) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, nullptr));
  std::vector<VkSurfaceFormatKHR> formats(count);
  SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface, &count, formats.data()));
  const VkFormat preferred[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB,
                                VK_FORMAT_R8G8B8A8_SRGB};
  for (VkFormat want : preferred) {
    for (const auto& f : formats) {
      if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR && can_blit_to(physical, f.format)) {
        return f;
      }
    }
  }
  for (const auto& f : formats) {
    if (f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR && can_blit_to(physical, f.format)) return f;
  }
  throw Error("Vulkan: none of the window's " + std::to_string(count) +
              " surface formats can be a blit destination in the sRGB colour space");
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

}  // namespace

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
  destroy_source();
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
  extent_ = extent;
  uint32_t count = 0;
  SVO_VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, nullptr));
  images_.resize(count);
  SVO_VK_CHECK(vkGetSwapchainImagesKHR(device, swapchain_, &count, images_.data()));
  blitted_.assign(count, VK_NULL_HANDLE);
  VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  for (VkSemaphore& s : blitted_) SVO_VK_CHECK(vkCreateSemaphore(device, &semaphore, nullptr, &s));
}

void Swapchain::destroy_swapchain() {
  VkDevice device = context_.device();
  for (VkSemaphore s : blitted_) {
    if (s) vkDestroySemaphore(device, s, nullptr);
  }
  blitted_.clear();
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

void Swapchain::ensure_source(uint32_t width, uint32_t height) {
  VkFormat format = is_srgb(format_) ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
  if (source_ && width == source_width_ && height == source_height_ && format == source_format_) return;
  destroy_source();
  VkDevice device = context_.device();
  VkDeviceSize bytes = VkDeviceSize(width) * height * 4;

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
  SVO_VK_CHECK(vkMapMemory(device, staging_memory_, 0, VK_WHOLE_SIZE, 0, &staging_mapped_));

  VkImageCreateInfo image{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  image.imageType = VK_IMAGE_TYPE_2D;
  image.format = format;
  image.extent = {width, height, 1};
  image.mipLevels = 1;
  image.arrayLayers = 1;
  image.samples = VK_SAMPLE_COUNT_1_BIT;
  image.tiling = VK_IMAGE_TILING_OPTIMAL;
  image.usage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  image.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  image.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  SVO_VK_CHECK(vkCreateImage(device, &image, nullptr, &source_));
  vkGetImageMemoryRequirements(device, source_, &req);
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = context_.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  SVO_VK_CHECK(vkAllocateMemory(device, &alloc, nullptr, &source_memory_));
  SVO_VK_CHECK(vkBindImageMemory(device, source_, source_memory_, 0));
  source_width_ = width;
  source_height_ = height;
  source_format_ = format;
}

void Swapchain::destroy_source() {
  VkDevice device = context_.device();
  if (source_) vkDestroyImage(device, source_, nullptr);
  if (source_memory_) vkFreeMemory(device, source_memory_, nullptr);
  if (staging_) vkDestroyBuffer(device, staging_, nullptr);
  if (staging_memory_) vkFreeMemory(device, staging_memory_, nullptr);  // unmaps
  source_ = VK_NULL_HANDLE;
  source_memory_ = VK_NULL_HANDLE;
  staging_ = VK_NULL_HANDLE;
  staging_memory_ = VK_NULL_HANDLE;
  staging_mapped_ = nullptr;
  source_width_ = source_height_ = 0;
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

  ensure_source(width, height);
  std::memcpy(staging_mapped_, rgba.data(), rgba.size());

  SVO_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  SVO_VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
  const VkPipelineStageFlags transfer = VK_PIPELINE_STAGE_TRANSFER_BIT;
  // staging buffer -> source image (host writes are visible at submission)
  barrier(cmd_, source_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
          VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, transfer);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {width, height, 1};
  vkCmdCopyBufferToImage(cmd_, staging_, source_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  barrier(cmd_, source_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
          VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, transfer, transfer);
  // source image -> swapchain image, scaled; the acquire semaphore is waited on at the transfer stage
  VkImage target = images_[index];
  barrier(cmd_, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
          VK_ACCESS_TRANSFER_WRITE_BIT, transfer, transfer);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int32_t(width), int32_t(height), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[1] = {int32_t(extent_.width), int32_t(extent_.height), 1};
  bool same_size = width == extent_.width && height == extent_.height;
  vkCmdBlitImage(cmd_, source_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                 &blit, same_size ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
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
  submit.pSignalSemaphores = &blitted_[index];
  SVO_VK_CHECK(vkResetFences(device, 1, &fence_));
  SVO_VK_CHECK(vkQueueSubmit(context_.queue(), 1, &submit, fence_));
  SVO_VK_CHECK(vkWaitForFences(device, 1, &fence_, VK_TRUE, UINT64_MAX));

  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &blitted_[index];
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &index;
  VkResult shown = vkQueuePresentKHR(context_.queue(), &present);
  if (shown == VK_ERROR_OUT_OF_DATE_KHR || shown == VK_SUBOPTIMAL_KHR) return false;
  SVO_VK_CHECK(shown);
  return acquired == VK_SUCCESS;
}

}  // namespace svo::vk
