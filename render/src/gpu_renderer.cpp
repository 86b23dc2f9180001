#include <algorithm>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "svo/render/renderer.h"
#include "svo/render/vk_compute.h"
#include "trace.comp.spv.h"
#include "trace_setup.h"

namespace svo::render {

namespace {

constexpr uint32_t kPoolSlots = 8;  // SVO_POOL_SLOTS in trace.comp
constexpr uint32_t kBindings = 6 + kPoolSlots;
constexpr uint32_t kGroup = 8;  // local_size_x = local_size_y

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

}  // namespace

struct GpuRenderer::Impl {
  vk::Context& context;
  const octree::Octree& tree;
  PackedOctree packed;
  uint32_t bricks_per_slot = 1;
  std::optional<vk::ComputeKernel> kernel;  // created once the number of pool buffers is known
  vk::Buffer params;
  vk::Buffer nodes;
  vk::Buffer masks;
  std::vector<vk::Buffer> pools;
  std::optional<vk::Buffer> colour, gbuffer, steps;
  size_t pool_bytes = 0;

  Impl(vk::Context& c, const octree::Octree& t, uint64_t max_buffer_bytes)
      : context(c),
        tree(t),
        packed(pack_octree(t)),
        params(c, sizeof(TraceParams)),
        nodes(c, std::max<size_t>(8, packed.nodes.size() * sizeof(glm::uvec2))),
        masks(c, tracer_mask_table().masks.size() * sizeof(Mask)) {
    std::memcpy(nodes.data(), packed.nodes.data(), packed.nodes.size() * sizeof(glm::uvec2));
    std::memcpy(masks.data(), tracer_mask_table().masks.data(), masks.size());
    // Whole bricks per storage buffer, plus one word so that no buffer is
    // empty.
    uint64_t range = context.info().max_storage_buffer_range;
    if (max_buffer_bytes > 0) range = std::min(range, max_buffer_bytes);
    if (range < uint64_t(packed.brick_bytes) + 4) {
      throw vk::Error("a brick of " + std::to_string(packed.brick_bytes) + " bytes exceeds maxStorageBufferRange " +
                      std::to_string(range));
    }
    bricks_per_slot = uint32_t(std::min<uint64_t>((range - 4) / packed.brick_bytes, 0xFFFFFFFFull));
    const uint64_t slots = std::max<uint64_t>(1, (packed.brick_count + bricks_per_slot - 1) / bricks_per_slot);
    if (slots > kPoolSlots) {
      throw vk::Error("the octree's bricks (" + mib(packed.brick_count * packed.brick_bytes) + ") need " +
                      std::to_string(slots) + " storage buffers of at most " + mib(range) +
                      " (maxStorageBufferRange) and the tracer binds " + std::to_string(kPoolSlots));
    }
    for (uint64_t s = 0; s < slots; ++s) {
      const uint64_t first = s * bricks_per_slot;
      const uint64_t count = std::min<uint64_t>(bricks_per_slot, packed.brick_count - std::min(first, packed.brick_count));
      const size_t bytes = size_t(count * packed.brick_bytes + 4);
      pools.emplace_back(context, bytes);
      std::memcpy(pools.back().data(), packed.bricks.data() + first * packed.brick_bytes, bytes);
      pool_bytes += bytes;
    }
    pool_bytes += nodes.size() + masks.size();
    const uint32_t specialization[] = {uint32_t(pools.size())};
    kernel.emplace(context, svo_spv_trace_comp, kBindings, 0, specialization);
    // Drivers may compile the pipeline at its first dispatch (lavapipe takes
    // about a second): do it here, so that frame times are frame times.
    RenderSettings warm_up;
    warm_up.width = warm_up.height = 1;
    warm_up.camera.eye = t.origin - glm::vec3(t.size);
    warm_up.camera.target = t.origin + 0.5f * glm::vec3(t.size);
    render(warm_up);
  }

  vk::Buffer& ensure(std::optional<vk::Buffer>& buffer, size_t bytes) {
    if (!buffer || buffer->size() != bytes) {
      buffer.reset();
      buffer.emplace(context, bytes);
    }
    return *buffer;
  }

  Frame render(const RenderSettings& settings) {
    auto start = std::chrono::steady_clock::now();
    TraceParams p = make_trace_params(tree, packed, settings);
    p.pool.y = bricks_per_slot;
    const uint64_t limit = context.info().max_storage_buffer_range;
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    if (pixels * 3 * sizeof(glm::vec4) > limit) {
      throw std::invalid_argument("a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                  " G-buffer exceeds the device's maxStorageBufferRange of " + mib(limit));
    }
    std::memcpy(params.data(), &p, sizeof p);
    vk::Buffer& out = ensure(colour, pixels * sizeof(glm::vec4));
    vk::Buffer& g = ensure(gbuffer, settings.gbuffer ? pixels * 3 * sizeof(glm::vec4) : 16);
    vk::Buffer& st = ensure(steps, pixels * sizeof(uint32_t));
    std::vector<const vk::Buffer*> bound{&params, &nodes, &masks, &out, &g, &st};
    for (uint32_t s = 0; s < kPoolSlots; ++s) bound.push_back(&pools[std::min<size_t>(s, pools.size() - 1)]);
    Frame frame;
    frame.width = settings.width;
    frame.height = settings.height;
    frame.gpu_ms = kernel->dispatch(bound, nullptr, (settings.width + kGroup - 1) / kGroup,
                                   (settings.height + kGroup - 1) / kGroup);
    auto colours = out.as<glm::vec4>();
    frame.colour.assign(colours.begin(), colours.begin() + pixels);
    auto counts = st.as<uint32_t>();
    frame.steps.assign(counts.begin(), counts.begin() + pixels);
    if (settings.gbuffer) {
      auto texels = g.as<glm::vec4>();
      frame.gbuffer.resize(pixels);
      for (size_t i = 0; i < pixels; ++i) {
        glm::vec4 a = texels[3 * i], b = texels[3 * i + 1], c = texels[3 * i + 2];
        frame.gbuffer[i] = {a.x, glm::vec3(a.y, a.z, a.w), glm::vec3(b), b.w, glm::vec3(c), c.w};
      }
    }
    finish_frame_stats(frame);
    frame.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return frame;
  }
};

GpuRenderer::GpuRenderer(vk::Context& context, const octree::Octree& tree, uint64_t max_buffer_bytes)
    : impl_(std::make_unique<Impl>(context, tree, max_buffer_bytes)) {}

GpuRenderer::~GpuRenderer() = default;

Frame GpuRenderer::render(const RenderSettings& settings) { return impl_->render(settings); }

std::size_t GpuRenderer::pool_bytes() const { return impl_->pool_bytes; }

}  // namespace svo::render

namespace svo::render {
uint32_t GpuRenderer::pool_buffers() const { return uint32_t(impl_->pools.size()); }
}  // namespace svo::render
