// Host-visible storage buffers and compute kernels with storage-buffer
// bindings and push constants: enough to run a shader over arrays and read
// the results back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "svo/render/vk_context.h"

namespace svo::vk {

// Where a buffer's memory should live, among the host-visible, host-coherent
// types (every buffer stays mapped). On lavapipe all are one; a discrete GPU
// lists system memory first (uncached for the CPU's reads, and read by the
// GPU across PCIe) and may list its own memory as host-visible too.
enum class Residence {
  Shared,    // the first host-visible type (the default)
  Device,    // written once by the CPU, read often by the GPU: a device-local type first
  Readback,  // written by the GPU, read by the CPU: a host-cached type first
};

// A storage buffer in host-visible, host-coherent memory, mapped for its lifetime.
class Buffer {
 public:
  // Throws Error if `bytes` is 0 or exceeds the device's maxStorageBufferRange
  // (the message names the limit), or if allocation fails. With
  // `device_address` the buffer is read through its device address instead
  // (see device_address()): the bound is then maxMemoryAllocationSize, and
  // the device must have DeviceInfo::buffer_device_address.
  // `residence` orders the candidate memory types; one whose heap cannot
  // hold the buffer is passed over for the next.
  Buffer(Context& context, std::size_t bytes, bool device_address = false, Residence residence = Residence::Shared);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&&) = delete;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  uint64_t device_address() const { return address_; }  // 0 unless created with device_address
  std::size_t size() const { return bytes_; }
  void* data() const { return mapped_; }

  template <class T>
  std::span<T> as() const {
    return {static_cast<T*>(mapped_), bytes_ / sizeof(T)};
  }

 private:
  Context* context_;
  std::size_t bytes_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  uint64_t address_ = 0;
};

// A compute pipeline whose set 0 holds `storage_buffers` storage buffers at
// bindings 0..n-1, with an optional push-constant block and 32-bit
// specialization constants (constant_id i = specialization[i]).
class ComputeKernel {
 public:
  ComputeKernel(Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffers,
                uint32_t push_constant_bytes, std::span<const uint32_t> specialization = {});
  // Binding i is an array of binding_counts[i] storage buffers; dispatch()
  // takes the buffers of all bindings in order, arrays flattened.
  ComputeKernel(Context& context, std::span<const uint32_t> spirv, std::vector<uint32_t> binding_counts,
                uint32_t push_constant_bytes, std::span<const uint32_t> specialization = {});
  ~ComputeKernel();
  ComputeKernel(const ComputeKernel&) = delete;
  ComputeKernel& operator=(const ComputeKernel&) = delete;

  // Binds `buffers` in order, pushes `push` (push_constant_bytes long, or
  // nullptr when there is none), dispatches and waits; shader writes are
  // visible to the host on return. Returns the GPU time of the dispatch in
  // milliseconds (timestamp queries), or a negative value when the queue has
  // no timestamps.
  double dispatch(std::span<const Buffer* const> buffers, const void* push, uint32_t groups_x, uint32_t groups_y = 1,
                  uint32_t groups_z = 1);
  // The same with the work groups' indices starting at (base_x, base_y)
  // (vkCmdDispatchBase: gl_WorkGroupID and gl_GlobalInvocationID count from
  // there).
  double dispatch_base(std::span<const Buffer* const> buffers, const void* push, uint32_t base_x, uint32_t base_y,
                       uint32_t groups_x, uint32_t groups_y);

 private:
  void release();  // destroys every handle created so far
  double dispatch_at(std::span<const Buffer* const> buffers, const void* push, glm::uvec2 base, glm::uvec3 groups);

  Context& context_;
  std::vector<uint32_t> binding_counts_;
  uint32_t storage_buffers_;  // sum of binding_counts_
  uint32_t push_bytes_;
  VkShaderModule module_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
};

}  // namespace svo::vk
