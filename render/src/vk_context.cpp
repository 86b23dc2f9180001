#include "svo/render/vk_context.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

namespace svo::vk {

const char* result_name(VkResult result) {
  switch (result) {
#define SVO_CASE(x) \
  case x:           \
    return #x;
    SVO_CASE(VK_SUCCESS)
    SVO_CASE(VK_NOT_READY)
    SVO_CASE(VK_TIMEOUT)
    SVO_CASE(VK_INCOMPLETE)
    SVO_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    SVO_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    SVO_CASE(VK_ERROR_INITIALIZATION_FAILED)
    SVO_CASE(VK_ERROR_DEVICE_LOST)
    SVO_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    SVO_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    SVO_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    SVO_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    SVO_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    SVO_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    SVO_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    SVO_CASE(VK_ERROR_FRAGMENTED_POOL)
    SVO_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    SVO_CASE(VK_ERROR_UNKNOWN)
    SVO_CASE(VK_SUBOPTIMAL_KHR)
    SVO_CASE(VK_ERROR_OUT_OF_DATE_KHR)
    SVO_CASE(VK_ERROR_SURFACE_LOST_KHR)
    SVO_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
#undef SVO_CASE
    default:
      return "VK_ERROR_(unlisted)";
  }
}

void check(VkResult result, const char* what, const char* file, int line) {
  if (result == VK_SUCCESS) return;
  std::ostringstream out;
  out << "Vulkan: " << what << " failed with " << result_name(result) << " (" << int(result) << ") at " << file << ":"
      << line;
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY) out << ": the device is out of memory";
  if (result == VK_ERROR_DEVICE_LOST) out << ": the device was lost (driver reset or crash)";
  throw Error(out.str());
}

namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

std::string type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "cpu";
    default:
      return "other";
  }
}

int type_rank(const std::string& type) {
  if (type == "discrete") return 4;
  if (type == "integrated") return 3;
  if (type == "virtual") return 2;
  if (type == "cpu") return 1;
  return 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool has_layer(const char* name) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
  std::vector<VkLayerProperties> layers(count);
  SVO_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool has_instance_extension(const std::string& name) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  SVO_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data()));
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return name == e.extensionName; });
}

// `wanted`: instance extensions asked for by the caller (for presenting).
VkInstance create_instance(bool validation, const std::vector<std::string>& wanted = {}) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "svo";
  app.applicationVersion = VK_MAKE_VERSION(0, 1, 0);
  app.pEngineName = "svo";
  app.apiVersion = VK_API_VERSION_1_1;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) {
    if (!has_layer(kValidationLayer)) {
      throw Error(std::string("Vulkan: validation requested but ") + kValidationLayer +
                  " is not installed (Debian package vulkan-validationlayers)");
    }
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  for (const std::string& name : wanted) {
    if (!has_instance_extension(name)) {
      throw Error("Vulkan: instance extension " + name +
                  " is not available (the driver cannot present to this display)");
    }
    if (std::none_of(extensions.begin(), extensions.end(), [&](const char* e) { return name == e; })) {
      extensions.push_back(name.c_str());
    }
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    throw Error("Vulkan: no driver found (install mesa-vulkan-drivers for the lavapipe CPU device)");
  }
  SVO_VK_CHECK(r);
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  SVO_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  if (devices.empty()) {
    throw Error("Vulkan: no device found (install mesa-vulkan-drivers for the lavapipe CPU device)");
  }
  return devices;
}

// Index of the first queue family with compute support, or -1.
int compute_family(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  // Prefer a family that also does graphics: it is the "main" queue on most drivers.
  for (uint32_t i = 0; i < count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) {
      return int(i);
    }
  }
  for (uint32_t i = 0; i < count; ++i) {
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return int(i);
  }
  return -1;
}

// Index of the queue family that does compute and presents to `surface`
// (preferring one that also does graphics), or -1 with the reason in `why`.
int present_family(VkPhysicalDevice device, VkSurfaceKHR surface, std::string& why) {
  uint32_t count = 0;
  SVO_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr));
  std::vector<VkExtensionProperties> extensions(count);
  SVO_VK_CHECK(vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()));
  if (std::none_of(extensions.begin(), extensions.end(), [](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, VK_KHR_SWAPCHAIN_EXTENSION_NAME) == 0;
      })) {
    why = "it has no " VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    return -1;
  }
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  int found = -1;
  for (uint32_t i = 0; i < count; ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    VkBool32 supported = VK_FALSE;
    SVO_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(device, i, surface, &supported));
    if (!supported) continue;
    if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) return int(i);
    if (found < 0) found = int(i);
  }
  if (found < 0) why = "no queue family does both compute and present to this window";
  return found;
}

DeviceInfo describe(VkPhysicalDevice device, uint32_t index) {
  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  subgroup.pNext = &maintenance3;
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(device, &props2);
  const VkPhysicalDeviceProperties& p = props2.properties;
  DeviceInfo info;
  info.index = index;
  info.name = p.deviceName;
  info.type = type_name(p.deviceType);
  info.api_version = std::to_string(VK_API_VERSION_MAJOR(p.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_MINOR(p.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_PATCH(p.apiVersion));
  info.max_storage_buffer_range = p.limits.maxStorageBufferRange;
  info.max_allocation_bytes = maintenance3.maxMemoryAllocationSize;
  info.max_image_dimension_3d = p.limits.maxImageDimension3D;
  info.max_compute_workgroup_invocations = p.limits.maxComputeWorkGroupInvocations;
  info.subgroup_size = subgroup.subgroupSize;
  info.timestamp_period_ns = p.limits.timestampPeriod;
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device, &memory);
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i) {
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) {
      info.device_local_bytes = std::max<uint64_t>(info.device_local_bytes, memory.memoryHeaps[i].size);
    }
  }
  const VkMemoryPropertyFlags mapped_local =
      VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    const VkMemoryType& type = memory.memoryTypes[i];
    if ((type.propertyFlags & mapped_local) == mapped_local) {
      info.mapped_device_local_bytes =
          std::max<uint64_t>(info.mapped_device_local_bytes, memory.memoryHeaps[type.heapIndex].size);
    }
    if (type.propertyFlags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT) info.host_cached = true;
  }
  int family = compute_family(device);
  if (family >= 0) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
    info.timestamps = families[size_t(family)].timestampValidBits > 0 && p.limits.timestampPeriod > 0;
  }
  return info;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  VkInstance instance = create_instance(false);
  std::vector<DeviceInfo> infos;
  try {
    auto devices = physical_devices(instance);
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return infos;
}

uint32_t select_device(const std::vector<DeviceInfo>& devices, const std::string& selector) {
  if (devices.empty()) throw Error("Vulkan: no device found");
  auto names = [&] {
    std::string all;
    for (const auto& d : devices) all += (all.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
    return all;
  };
  if (selector.empty()) {
    uint32_t best = 0;
    for (uint32_t i = 1; i < devices.size(); ++i) {
      if (type_rank(devices[i].type) > type_rank(devices[best].type)) best = i;
    }
    return best;
  }
  bool numeric = std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); });
  if (numeric) {
    unsigned long index = std::stoul(selector);
    if (index >= devices.size()) {
      throw Error("Vulkan: --device " + selector + " is out of range; devices are " + names());
    }
    return uint32_t(index);
  }
  std::vector<uint32_t> matches;
  for (uint32_t i = 0; i < devices.size(); ++i) {
    if (lower(devices[i].name).find(lower(selector)) != std::string::npos) matches.push_back(i);
  }
  if (matches.size() != 1) {
    throw Error("Vulkan: --device '" + selector + "' matches " + std::to_string(matches.size()) +
                " devices; devices are " + names());
  }
  return matches[0];
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  const char* level = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)     ? "error"
                      : (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) ? "warning"
                                                                                     : "info";
  std::lock_guard<std::mutex> lock(self->messages_mutex_);
  self->messages_.push_back(std::string(level) + ": " + (data && data->pMessage ? data->pMessage : "(no text)"));
  return VK_FALSE;
}

Context::Context(const ContextOptions& options) {
  instance_ = create_instance(options.validation, options.instance_extensions);
  try {
    if (options.validation) {
      VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      info.messageSeverity =
          VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      info.pfnUserCallback = &Context::on_message;
      info.pUserData = this;
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw Error("Vulkan: vkCreateDebugUtilsMessengerEXT is missing although validation is on");
      SVO_VK_CHECK(create(instance_, &info, nullptr, &messenger_));
    }
    if (options.create_surface) {
      surface_ = options.create_surface(instance_);
      if (!surface_) throw Error("Vulkan: no surface to present to");
    }
    auto devices = physical_devices(instance_);
    std::vector<DeviceInfo> infos;
    for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], i));
    uint32_t chosen = 0;
    int family = -1;
    if (!surface_) {
      chosen = select_device(infos, options.device);
      family = compute_family(devices[chosen]);
      if (family < 0) throw Error("Vulkan: device '" + infos[chosen].name + "' has no compute queue");
    } else {
      // Only devices that can present are candidates.
      std::vector<int> families(devices.size());
      std::vector<std::string> why(devices.size());
      std::vector<DeviceInfo> able;
      for (uint32_t i = 0; i < devices.size(); ++i) {
        families[i] = present_family(devices[i], surface_, why[i]);
        if (families[i] >= 0) able.push_back(infos[i]);
      }
      if (options.device.empty()) {
        if (able.empty()) {
          std::string all;
          for (uint32_t i = 0; i < devices.size(); ++i) all += (i ? "; " : "") + infos[i].name + ": " + why[i];
          throw Error("Vulkan: no device can present to the window (" + all + ")");
        }
        chosen = able[select_device(able, "")].index;
      } else {
        chosen = select_device(infos, options.device);
        if (families[chosen] < 0) {
          throw Error("Vulkan: device '" + infos[chosen].name + "' cannot present to the window: " + why[chosen]);
        }
      }
      family = families[chosen];
    }
    physical_ = devices[chosen];
    info_ = infos[chosen];
    queue_family_ = uint32_t(family);
    {
      uint32_t count = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, nullptr);
      std::vector<VkQueueFamilyProperties> queue_families(count);
      vkGetPhysicalDeviceQueueFamilyProperties(physical_, &count, queue_families.data());
      info_.timestamps = queue_families[queue_family_].timestampValidBits > 0 && info_.timestamp_period_ns > 0;
    }

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue.queueFamilyIndex = queue_family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkDeviceCreateInfo device{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    device.queueCreateInfoCount = 1;
    device.pQueueCreateInfos = &queue;
    std::vector<const char*> extensions;
    if (surface_) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    // Buffer device addresses: the tracer's brick pools beyond
    // maxStorageBufferRange (lavapipe: 128 MiB) without a branch per read.
    VkPhysicalDeviceBufferDeviceAddressFeatures address{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    {
      uint32_t count = 0;
      vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, nullptr);
      std::vector<VkExtensionProperties> available(count);
      vkEnumerateDeviceExtensionProperties(physical_, nullptr, &count, available.data());
      bool has = false;
      for (const auto& e : available) has = has || std::string(e.extensionName) == VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME;
      if (has) {
        features.pNext = &address;
        vkGetPhysicalDeviceFeatures2(physical_, &features);
        if (address.bufferDeviceAddress && features.features.shaderInt64) {
          address = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES};
          address.bufferDeviceAddress = VK_TRUE;
          features = {VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
          features.features.shaderInt64 = VK_TRUE;
          features.pNext = &address;
          device.pNext = &features;
          extensions.push_back(VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME);
          info_.buffer_device_address = true;
        }
      }
    }
    device.enabledExtensionCount = uint32_t(extensions.size());
    device.ppEnabledExtensionNames = extensions.data();
    SVO_VK_CHECK(vkCreateDevice(physical_, &device, nullptr, &device_));
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = queue_family_;
    SVO_VK_CHECK(vkCreateCommandPool(device_, &pool, nullptr, &pool_));
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    SVO_VK_CHECK(vkCreateFence(device_, &fence, nullptr, &fence_));
  } catch (...) {
    release();
    throw;
  }
}

Context::~Context() { release(); }

void Context::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (fence_) vkDestroyFence(device_, fence_, nullptr);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  fence_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  device_ = VK_NULL_HANDLE;
  surface_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags properties) const {
  return memory_types(type_bits, properties, 0).front().first;
}

std::vector<std::pair<uint32_t, VkMemoryPropertyFlags>> Context::memory_types(uint32_t type_bits,
                                                                              VkMemoryPropertyFlags properties,
                                                                              VkMemoryPropertyFlags preferred) const {
  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory);
  std::vector<std::pair<uint32_t, VkMemoryPropertyFlags>> first, then;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags flags = memory.memoryTypes[i].propertyFlags;
    if (!(type_bits & (1u << i)) || (flags & properties) != properties) continue;
    ((flags & preferred) == preferred ? first : then).emplace_back(i, flags);
  }
  first.insert(first.end(), then.begin(), then.end());
  if (first.empty()) {
    throw Error("Vulkan: device '" + info_.name + "' has no memory type with the required properties");
  }
  return first;
}

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = pool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  SVO_VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &cmd));
  struct Release {
    VkDevice device;
    VkCommandPool pool;
    VkCommandBuffer cmd;
    ~Release() { vkFreeCommandBuffers(device, pool, 1, &cmd); }
  } release{device_, pool_, cmd};

  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  SVO_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
  record(cmd);
  SVO_VK_CHECK(vkEndCommandBuffer(cmd));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  SVO_VK_CHECK(vkResetFences(device_, 1, &fence_));
  SVO_VK_CHECK(vkQueueSubmit(queue_, 1, &submit, fence_));
  SVO_VK_CHECK(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX));
}

std::vector<std::string> Context::validation_messages() const {
  std::lock_guard<std::mutex> lock(messages_mutex_);
  return messages_;
}

}  // namespace svo::vk
