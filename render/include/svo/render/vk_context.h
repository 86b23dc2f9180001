// Vulkan instance, device selection and a compute queue: the ground every
// pass of the renderer stands on. Headless by default; lavapipe is the device
// of last resort so that it runs on any machine. With a surface (a window,
// ContextOptions::create_surface) the queue can also present.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace svo::vk {

// Every Vulkan failure: the message names the call, the VkResult and the
// source position, or the limit or missing piece that stopped us.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Name of a VkResult ("VK_ERROR_DEVICE_LOST").
const char* result_name(VkResult result);

// Throws Error("<what> failed with <result> at <file>:<line>") unless result is VK_SUCCESS.
void check(VkResult result, const char* what, const char* file, int line);

#define SVO_VK_CHECK(call) ::svo::vk::check((call), #call, __FILE__, __LINE__)

struct DeviceInfo {
  uint32_t index = 0;  // in vkEnumeratePhysicalDevices order
  std::string name;
  std::string type;  // "discrete", "integrated", "virtual", "cpu", "other"
  std::string api_version;
  uint64_t max_storage_buffer_range = 0;  // bytes
  uint32_t max_image_dimension_3d = 0;
  uint32_t max_compute_workgroup_invocations = 0;
  uint32_t subgroup_size = 0;
  uint64_t device_local_bytes = 0;
  uint64_t mapped_device_local_bytes = 0;  // largest device-local heap the CPU can map (a BAR window or all of it)
  bool host_cached = false;                // a host-visible type the CPU caches (fast read-back)
  bool timestamps = false;         // compute queue supports timestamp queries
  uint64_t max_allocation_bytes = 0;  // maxMemoryAllocationSize
  // Buffers read through 64-bit device addresses (VK_KHR_buffer_device_address
  // and shaderInt64), not bounded by maxStorageBufferRange; enabled when present.
  bool buffer_device_address = false;
  double timestamp_period_ns = 0;  // nanoseconds per timestamp tick
};

struct ContextOptions {
  // "" picks the default: the best of discrete > integrated > virtual > cpu
  // (lavapipe). Otherwise a device index, or a case-insensitive substring of
  // the device name that must match exactly one device.
  std::string device;
  // Enable VK_LAYER_KHRONOS_validation; every message it sends is recorded
  // (validation_messages()) so that callers can fail on any of them.
  bool validation = false;

  // Presenting to a window (leave both empty for headless work).
  // Instance extensions to enable besides our own, e.g. the ones
  // glfwGetRequiredInstanceExtensions names (VK_KHR_surface and a platform one).
  std::vector<std::string> instance_extensions;
  // Called once with the new instance, before the device is chosen; returns
  // the surface to present to (or throws). The Context owns the surface from
  // then on and destroys it before the instance. When set, only a device with
  // a queue family that does both compute and present to this surface, and
  // with VK_KHR_swapchain, is acceptable: the default choice skips the others,
  // an explicit `device` that cannot present is an Error. The device is then
  // created with VK_KHR_swapchain enabled.
  std::function<VkSurfaceKHR(VkInstance)> create_surface;
};

// Lists the Vulkan devices of this machine. Throws Error when Vulkan has no
// driver or no device.
std::vector<DeviceInfo> list_devices();

// Index into `devices` chosen by `selector` (see ContextOptions::device).
// Throws Error naming the selector and the devices when nothing or more than
// one device matches.
uint32_t select_device(const std::vector<DeviceInfo>& devices, const std::string& selector);

class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& info() const { return info_; }
  VkDevice device() const { return device_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkInstance instance() const { return instance_; }
  // The one queue (compute, and present when there is a surface) and its family.
  // Callers that submit to it themselves must do so from the thread that uses the Context.
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  // The surface made by ContextOptions::create_surface; VK_NULL_HANDLE when headless.
  VkSurfaceKHR surface() const { return surface_; }

  // Memory type index with the requested properties among `type_bits`; throws Error if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags properties) const;
  // Every type with `properties`, those that also have `preferred` first
  // (each group in the device's order), with their property flags.
  std::vector<std::pair<uint32_t, VkMemoryPropertyFlags>> memory_types(uint32_t type_bits,
                                                                       VkMemoryPropertyFlags properties,
                                                                       VkMemoryPropertyFlags preferred) const;

  // Records commands with `record` into a fresh command buffer, submits it to
  // the compute queue and waits for it to finish.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);

  // Validation messages received so far (empty without validation).
  std::vector<std::string> validation_messages() const;

 private:
  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
  void release();  // destroys every handle created so far

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  DeviceInfo info_;
  mutable std::mutex messages_mutex_;
  std::vector<std::string> messages_;
};

}  // namespace svo::vk
