#include "svo/render/vk_compute.h"

#include <utility>
#include <vector>

namespace svo::vk {

Buffer::Buffer(Context& context, std::size_t bytes, bool device_address, Residence residence)
    : context_(&context), bytes_(bytes) {
  const DeviceInfo& info = context.info();
  if (bytes == 0) throw Error("Vulkan: a storage buffer of 0 bytes was requested");
  if (device_address && !info.buffer_device_address) {
    throw Error("Vulkan: device '" + info.name + "' has no buffer device addresses (VK_KHR_buffer_device_address)");
  }
  if (device_address && bytes > info.max_allocation_bytes) {
    throw Error("Vulkan: a buffer of " + std::to_string(bytes) + " bytes exceeds maxMemoryAllocationSize = " +
                std::to_string(info.max_allocation_bytes) + " bytes of device '" + info.name + "'");
  }
  if (!device_address && bytes > info.max_storage_buffer_range) {
    throw Error("Vulkan: a storage buffer of " + std::to_string(bytes) + " bytes exceeds maxStorageBufferRange = " +
                std::to_string(info.max_storage_buffer_range) + " bytes of device '" + info.name + "'");
  }
  VkDevice device = context.device();
  VkBufferCreateInfo create{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  create.size = bytes;
  create.usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  if (device_address) create.usage |= VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  create.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  SVO_VK_CHECK(vkCreateBuffer(device, &create, nullptr, &buffer_));
  try {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, buffer_, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    if (device_address) alloc.pNext = &flags;
    const VkMemoryPropertyFlags preferred = residence == Residence::Device     ? VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT
                                            : residence == Residence::Readback ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT
                                                                               : 0;
    const auto candidates = context.memory_types(
        req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, preferred);
    VkResult result = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    // A preferred heap may be small (a 256 MiB window onto a GPU's memory):
    // out of memory there, the next type is tried.
    for (const auto& candidate : candidates) {
      alloc.memoryTypeIndex = candidate.first;
      result = vkAllocateMemory(device, &alloc, nullptr, &memory_);
      if (result == VK_SUCCESS) break;
      if (result != VK_ERROR_OUT_OF_DEVICE_MEMORY && result != VK_ERROR_OUT_OF_HOST_MEMORY) break;
      memory_ = VK_NULL_HANDLE;
    }
    SVO_VK_CHECK(result);
    SVO_VK_CHECK(vkBindBufferMemory(device, buffer_, memory_, 0));
    SVO_VK_CHECK(vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_));
    if (device_address) {
      VkBufferDeviceAddressInfo where{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
      where.buffer = buffer_;
      auto get = reinterpret_cast<PFN_vkGetBufferDeviceAddressKHR>(
          vkGetDeviceProcAddr(device, "vkGetBufferDeviceAddressKHR"));
      if (!get) throw Error("Vulkan: vkGetBufferDeviceAddressKHR is missing");
      address_ = get(device, &where);
    }
  } catch (...) {
    if (memory_) vkFreeMemory(device, memory_, nullptr);
    vkDestroyBuffer(device, buffer_, nullptr);
    throw;
  }
}

Buffer::Buffer(Buffer&& other) noexcept
    : context_(other.context_),
      bytes_(other.bytes_),
      buffer_(std::exchange(other.buffer_, VK_NULL_HANDLE)),
      memory_(std::exchange(other.memory_, VK_NULL_HANDLE)),
      mapped_(std::exchange(other.mapped_, nullptr)),
      address_(std::exchange(other.address_, 0)) {}

Buffer::~Buffer() {
  VkDevice device = context_->device();
  if (memory_) {
    vkUnmapMemory(device, memory_);
    vkFreeMemory(device, memory_, nullptr);
  }
  if (buffer_) vkDestroyBuffer(device, buffer_, nullptr);
}

ComputeKernel::ComputeKernel(Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffers,
                             uint32_t push_constant_bytes, std::span<const uint32_t> specialization)
    : ComputeKernel(context, spirv, std::vector<uint32_t>(storage_buffers, 1u), push_constant_bytes, specialization) {}

ComputeKernel::ComputeKernel(Context& context, std::span<const uint32_t> spirv, std::vector<uint32_t> binding_counts,
                             uint32_t push_constant_bytes, std::span<const uint32_t> specialization)
    : context_(context), binding_counts_(std::move(binding_counts)), push_bytes_(push_constant_bytes) {
  storage_buffers_ = 0;
  for (uint32_t c : binding_counts_) storage_buffers_ += c;
  if (spirv.empty() || spirv[0] != 0x07230203u) {
    throw Error("Vulkan: compute kernel given " + std::to_string(spirv.size()) +
                " words that are not a SPIR-V module (no magic number)");
  }
  VkDevice device = context.device();
  struct Cleanup {
    ComputeKernel* self;
    bool armed = true;
    ~Cleanup() {
      if (armed) self->release();
    }
  } cleanup{this};

  VkShaderModuleCreateInfo module{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  module.codeSize = spirv.size_bytes();
  module.pCode = spirv.data();
  SVO_VK_CHECK(vkCreateShaderModule(device, &module, nullptr, &module_));

  std::vector<VkDescriptorSetLayoutBinding> bindings(binding_counts_.size());
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = binding_counts_[i];
    bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo set_layout{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_layout.bindingCount = uint32_t(bindings.size());
  set_layout.pBindings = bindings.data();
  SVO_VK_CHECK(vkCreateDescriptorSetLayout(device, &set_layout, nullptr, &set_layout_));

  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo layout{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout.setLayoutCount = 1;
  layout.pSetLayouts = &set_layout_;
  layout.pushConstantRangeCount = push_constant_bytes > 0 ? 1 : 0;
  layout.pPushConstantRanges = &push;
  SVO_VK_CHECK(vkCreatePipelineLayout(device, &layout, nullptr, &layout_));

  VkComputePipelineCreateInfo pipeline{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipeline.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  pipeline.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline.stage.module = module_;
  pipeline.stage.pName = "main";
  // Specialization constants: constant_id i takes specialization[i].
  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < specialization.size(); ++i) entries.push_back({i, i * 4u, 4u});
  VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), specialization.size_bytes(),
                            specialization.data()};
  if (!specialization.empty()) pipeline.stage.pSpecializationInfo = &spec;
  pipeline.layout = layout_;
  pipeline.flags = VK_PIPELINE_CREATE_DISPATCH_BASE_BIT;  // dispatch_base()
  SVO_VK_CHECK(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline, nullptr, &pipeline_));

  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, storage_buffers_ > 0 ? storage_buffers_ : 1};
  VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool.maxSets = 1;
  pool.poolSizeCount = 1;
  pool.pPoolSizes = &size;
  SVO_VK_CHECK(vkCreateDescriptorPool(device, &pool, nullptr, &pool_));
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool_;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &set_layout_;
  SVO_VK_CHECK(vkAllocateDescriptorSets(device, &alloc, &set_));

  if (context.info().timestamps) {
    VkQueryPoolCreateInfo queries{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queries.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queries.queryCount = 2;
    SVO_VK_CHECK(vkCreateQueryPool(device, &queries, nullptr, &queries_));
  }
  cleanup.armed = false;
}

ComputeKernel::~ComputeKernel() { release(); }

void ComputeKernel::release() {
  VkDevice device = context_.device();
  if (queries_) vkDestroyQueryPool(device, queries_, nullptr);
  if (pool_) vkDestroyDescriptorPool(device, pool_, nullptr);
  if (pipeline_) vkDestroyPipeline(device, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
  if (module_) vkDestroyShaderModule(device, module_, nullptr);
  queries_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
  module_ = VK_NULL_HANDLE;
}

double ComputeKernel::dispatch(std::span<const Buffer* const> buffers, const void* push, uint32_t groups_x,
                               uint32_t groups_y, uint32_t groups_z) {
  return dispatch_at(buffers, push, {0, 0}, {groups_x, groups_y, groups_z});
}

double ComputeKernel::dispatch_base(std::span<const Buffer* const> buffers, const void* push, uint32_t base_x,
                                    uint32_t base_y, uint32_t groups_x, uint32_t groups_y) {
  return dispatch_at(buffers, push, {base_x, base_y}, {groups_x, groups_y, 1});
}

double ComputeKernel::dispatch_at(std::span<const Buffer* const> buffers, const void* push, glm::uvec2 base,
                                  glm::uvec3 groups) {
  if (buffers.size() != storage_buffers_) {
    throw Error("Vulkan: kernel expects " + std::to_string(storage_buffers_) + " buffers, got " +
                std::to_string(buffers.size()));
  }
  if ((push == nullptr) != (push_bytes_ == 0)) {
    throw Error("Vulkan: push constants given to a kernel without them, or missing");
  }
  VkDevice device = context_.device();
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  for (size_t i = 0; i < buffers.size(); ++i) infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
  std::vector<VkWriteDescriptorSet> writes(binding_counts_.size());
  for (size_t b = 0, first = 0; b < binding_counts_.size(); first += binding_counts_[b], ++b) {
    writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[b].dstSet = set_;
    writes[b].dstBinding = uint32_t(b);
    writes[b].descriptorCount = binding_counts_[b];
    writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[b].pBufferInfo = &infos[first];
  }
  vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);

  context_.submit_and_wait([&](VkCommandBuffer cmd) {
    if (queries_) {
      vkCmdResetQueryPool(cmd, queries_, 0, 2);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
    if (push_bytes_ > 0) vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_, push);
    if (base == glm::uvec2(0)) {
      vkCmdDispatch(cmd, groups.x, groups.y, groups.z);
    } else {
      vkCmdDispatchBase(cmd, base.x, base.y, 0, groups.x, groups.y, groups.z);
    }
    if (queries_) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
  });
  if (!queries_) return -1.0;
  uint64_t ticks[2] = {0, 0};
  SVO_VK_CHECK(vkGetQueryPoolResults(device, queries_, 0, 2, sizeof(ticks), ticks, sizeof(uint64_t),
                                     VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  return double(ticks[1] - ticks[0]) * context_.info().timestamp_period_ns * 1e-6;
}

}  // namespace svo::vk
