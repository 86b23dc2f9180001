// The octree as every pass can trace it (DESIGN section 10.1): packed once
// for the tracer's reads, and on a Vulkan host uploaded once as pools that
// any pass's kernel binds (shaders/render/octree_bindings.glsl). A pass that
// traces cones from G-buffer points (render::VisibilityPass) reads the
// octree through here: natively by deriving its kernel from
// NativeOctreeReader and including the GLSL, on Vulkan by bind().
#pragma once

#include <cstdint>
#include <cstring>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <span>
#include <vector>

#include "common/shared_math.h"
#include "svo/octree/octree.h"
#include "svo/render/vk_compute.h"

namespace svo::render {

struct RenderSettings;
using TraceParams = svo::math::SvoTraceParams;

// The octree as the tracer reads it: nodes as (children, brick) pairs, and
// every brick's channels one after the other in one record of `brick_bytes`,
// so that one index finds all of a voxel. Channel sections start on a word;
// 3-byte samples are padded to 4 bytes, so that no sample straddles a word.
struct PackedOctree {
  std::vector<glm::uvec2> nodes;
  uint32_t brick_bytes = 0;
  uint64_t brick_count = 0;
  std::vector<uint8_t> bricks;  // brick_count * brick_bytes, then 4 bytes of padding
  glm::uvec4 offsets_a{0}, offsets_b{0}, offsets_c{0}, encodings{0};
};

// Each pool brick holds the (B + 1)^3 lattice points of its node, x fastest
// (the tracer interpolates inside a node from its brick alone): the B^3 that
// the file stores plus the upper faces, copied from the neighbouring bricks or
// reconstructed where those are absent (octree::BrickFaces). Expects a valid
// octree (validate_octree); throws std::invalid_argument when it lacks the
// distance channel.
PackedOctree pack_octree(const octree::Octree& tree);

// The host contract of shaders/common/tracer.glsl on the native host. A
// kernel derives from it and includes the GLSL it needs in its body.
struct NativeOctreeReader {
  TraceParams params;
  const glm::uvec2* nodes;
  const uint8_t* bricks;
  const glm::uvec4* masks;

  glm::uvec2 svo_node(uint32_t index) const { return nodes[index]; }
  uint32_t svo_brick_bytes(uint32_t brick, uint32_t offset) const {
    const std::size_t at = std::size_t(brick) * params.pool.x + offset;
    uint32_t v;
    std::memcpy(&v, bricks + (at & ~std::size_t(3)), 4);
    return v >> ((at & 3u) * 8u);
  }
  glm::uvec4 svo_mask(uint32_t cell) const { return masks[cell]; }
  // Every mode and flag open (tracer_params.glsl, "Specialisation").
  static constexpr uint32_t SVO_SPEC_MODE = svo::math::SVO_SPEC_ANY;
  static constexpr uint32_t SVO_SPEC_FLAGS = svo::math::SVO_SPEC_ANY;
};

// How a Vulkan kernel reads the brick pools (octree_bindings.glsl).
enum class PoolAccess { Single, Address, Switch };
const char* pool_access_name(PoolAccess access);  // "single", "address", "switch"

class OctreeAccess {
 public:
  // The native host's: the packed octree.
  explicit OctreeAccess(const octree::Octree& tree);
  // The Vulkan host's: the pools uploaded to `context`, split across
  // buffers of at most `max_buffer_bytes` (0: the device's limit), read
  // through device addresses when `device_address` and the device has them.
  // Throws vk::Error naming the limit when the octree cannot fit.
  OctreeAccess(const octree::Octree& tree, vk::Context& context, uint64_t max_buffer_bytes, bool device_address);
  ~OctreeAccess();
  OctreeAccess(const OctreeAccess&) = delete;
  OctreeAccess& operator=(const OctreeAccess&) = delete;

  const octree::Octree& tree() const { return tree_; }
  const PackedOctree& packed() const { return packed_; }

  // The parameters of a trace with `settings`. Throws std::invalid_argument
  // naming what is wrong with them.
  TraceParams params(const RenderSettings& settings) const;
  // The native reader of those parameters.
  NativeOctreeReader native(const TraceParams& params) const;

  // Vulkan: uploads `params` and appends the buffers of
  // octree_bindings.glsl in binding order (params, nodes, masks, pools).
  void bind(const TraceParams& params, std::vector<const vk::Buffer*>& bound) const;
  PoolAccess pool_access() const { return access_; }
  // Of a kernel compiled three ways (octree_bindings.glsl), the one that
  // reads the pools as this octree holds them.
  std::span<const uint32_t> pick_kernel(std::span<const uint32_t> single, std::span<const uint32_t> address,
                                        std::span<const uint32_t> switched) const {
    return access_ == PoolAccess::Single ? single : access_ == PoolAccess::Address ? address : switched;
  }
  uint32_t binding_count() const;  // the buffers bind() appends
  std::size_t pool_bytes() const { return pool_bytes_; }
  uint32_t pool_buffers() const { return uint32_t(pools_.size()); }

 private:
  const octree::Octree& tree_;
  PackedOctree packed_;
  PoolAccess access_ = PoolAccess::Single;
  uint32_t bricks_per_slot_ = 0xFFFFFFFFu;
  std::unique_ptr<vk::Buffer> params_, nodes_, masks_, addresses_;
  std::vector<vk::Buffer> pools_;
  std::size_t pool_bytes_ = 0;
};

}  // namespace svo::render
