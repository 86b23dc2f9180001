#include "svo/render/octree_access.h"

#include <algorithm>
#include <string>

#include "trace_setup.h"

namespace svo::render {

namespace {

constexpr uint32_t kPoolSlots = 8;  // SVO_POOL_SLOTS in octree_bindings.glsl

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

}  // namespace

const char* pool_access_name(PoolAccess access) {
  switch (access) {
    case PoolAccess::Single:
      return "single";
    case PoolAccess::Address:
      return "address";
    case PoolAccess::Switch:
      return "switch";
  }
  return "unknown";
}

OctreeAccess::OctreeAccess(const octree::Octree& tree) : tree_(tree), packed_(pack_octree(tree)) {}

OctreeAccess::OctreeAccess(const octree::Octree& tree, vk::Context& context, uint64_t max_buffer_bytes,
                           bool device_address)
    : OctreeAccess(tree) {
  params_ = std::make_unique<vk::Buffer>(context, sizeof(TraceParams));
  // The tree is written once and read by every cone: in the GPU's own memory where it is host-visible.
  nodes_ = std::make_unique<vk::Buffer>(context, std::max<size_t>(8, packed_.nodes.size() * sizeof(glm::uvec2)), false,
                                        vk::Residence::Device);
  masks_ =
      std::make_unique<vk::Buffer>(context, tracer_mask_buffer().size() * sizeof(Mask), false, vk::Residence::Device);
  addresses_ = std::make_unique<vk::Buffer>(context, kPoolSlots * sizeof(uint64_t));
  std::memcpy(nodes_->data(), packed_.nodes.data(), packed_.nodes.size() * sizeof(glm::uvec2));
  std::memcpy(masks_->data(), tracer_mask_buffer().data(), masks_->size());
  const vk::DeviceInfo& info = context.info();
  const uint64_t all = packed_.brick_count * packed_.brick_bytes + 4;
  auto limited = [&](uint64_t limit) { return max_buffer_bytes > 0 ? std::min(limit, max_buffer_bytes) : limit; };
  // One storage buffer when the bricks fit; else buffers read through
  // device addresses (bounded by the allocation size, not the descriptor
  // range); else separate storage buffers and a switch.
  uint64_t range = limited(info.max_storage_buffer_range);
  access_ = PoolAccess::Single;
  if (all > range) {
    access_ = PoolAccess::Switch;
    if (device_address && info.buffer_device_address) {
      access_ = PoolAccess::Address;
      range = limited(std::min<uint64_t>(info.max_allocation_bytes, 0xFFFFFFFCull));
    }
  }
  if (range < uint64_t(packed_.brick_bytes) + 4) {
    throw vk::Error("a brick of " + std::to_string(packed_.brick_bytes) + " bytes exceeds the buffer limit " +
                    std::to_string(range) + " of device '" + info.name + "'");
  }
  // Whole bricks per buffer, plus one word so that no buffer is empty.
  bricks_per_slot_ = uint32_t(std::min<uint64_t>((range - 4) / packed_.brick_bytes, 0xFFFFFFFFull));
  const uint64_t slots = std::max<uint64_t>(1, (packed_.brick_count + bricks_per_slot_ - 1) / bricks_per_slot_);
  if (slots > kPoolSlots) {
    throw vk::Error("the octree's bricks (" + mib(all) + ") need " + std::to_string(slots) + " buffers of at most " +
                    mib(range) + " on device '" + info.name + "' and the tracer binds " + std::to_string(kPoolSlots));
  }
  const bool address = access_ == PoolAccess::Address;
  auto slot_addresses = addresses_->as<uint64_t>();
  for (uint64_t s = 0; s < slots; ++s) {
    const uint64_t first = s * bricks_per_slot_;
    const uint64_t count =
        std::min<uint64_t>(bricks_per_slot_, packed_.brick_count - std::min(first, packed_.brick_count));
    const size_t bytes = size_t(count * packed_.brick_bytes + 4);
    pools_.emplace_back(context, bytes, address, vk::Residence::Device);
    std::memcpy(pools_.back().data(), packed_.bricks.data() + first * packed_.brick_bytes, bytes);
    slot_addresses[s] = pools_.back().device_address();
    pool_bytes_ += bytes;
  }
  pool_bytes_ += nodes_->size() + masks_->size();
}

OctreeAccess::~OctreeAccess() = default;

TraceParams OctreeAccess::params(const RenderSettings& settings) const {
  TraceParams p = make_trace_params(tree_, packed_, settings);
  p.pool.y = bricks_per_slot_;
  return p;
}

NativeOctreeReader OctreeAccess::native(const TraceParams& params) const {
  return {params, packed_.nodes.data(), packed_.bricks.data(), tracer_mask_buffer().data()};
}

uint32_t OctreeAccess::binding_count() const { return access_ == PoolAccess::Switch ? 3 + kPoolSlots : 4; }

void OctreeAccess::bind(const TraceParams& params, std::vector<const vk::Buffer*>& bound) const {
  if (!params_) throw std::logic_error("OctreeAccess::bind on an octree without Vulkan pools");
  std::memcpy(params_->data(), &params, sizeof params);
  bound.insert(bound.end(), {params_.get(), nodes_.get(), masks_.get()});
  if (access_ == PoolAccess::Address) {
    bound.push_back(addresses_.get());
  } else {
    const size_t slots = access_ == PoolAccess::Single ? 1 : kPoolSlots;
    for (size_t s = 0; s < slots; ++s) bound.push_back(&pools_[std::min(s, pools_.size() - 1)]);
  }
}

}  // namespace svo::render
