#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

// The Vulkan host: the octree's pools on the device and the trace pass as a
// compute kernel (shaders/render/trace_main.glsl).
#include "svo/render/renderer.h"
#include "svo/render/vk_compute.h"
#include "common/shared_math.h"
#include "trace_address.comp.spv.h"
#include "trace_single.comp.spv.h"
#include "trace_switch.comp.spv.h"
#include "trace_setup.h"

namespace svo::render {

namespace {

constexpr uint32_t kPoolSlots = 8;  // SVO_POOL_SLOTS in trace_main.glsl
constexpr uint32_t kGroup = 8;  // local_size_x = local_size_y
constexpr uint32_t kRaysPerDispatch = 16;  // raymarch: rays per pixel in one dispatch, at most

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// The cone tracer as the first pass: writes "colour", "background",
// "gbuffer" (when the settings ask for it) and "steps".
class TracePass : public Pass {
 public:
  TracePass(vk::Context& context, const octree::Octree& tree, const GpuRenderer::Options& options)
      : context_(context),
        tree_(tree),
        packed_(pack_octree(tree)),
        params_(context, sizeof(TraceParams)),
        nodes_(context, std::max<size_t>(8, packed_.nodes.size() * sizeof(glm::uvec2))),
        masks_(context, tracer_mask_buffer().size() * sizeof(Mask)),
        addresses_(context, kPoolSlots * sizeof(uint64_t)),
        no_gbuffer_(context, 16) {
    std::memcpy(nodes_.data(), packed_.nodes.data(), packed_.nodes.size() * sizeof(glm::uvec2));
    std::memcpy(masks_.data(), tracer_mask_buffer().data(), masks_.size());
    const vk::DeviceInfo& info = context.info();
    const uint64_t all = packed_.brick_count * packed_.brick_bytes + 4;
    auto limited = [&](uint64_t limit) { return options.max_buffer_bytes > 0 ? std::min(limit, options.max_buffer_bytes) : limit; };
    // One storage buffer when the bricks fit; else buffers read through
    // device addresses (bounded by the allocation size, not the descriptor
    // range); else separate storage buffers and a switch.
    uint64_t range = limited(info.max_storage_buffer_range);
    access_ = "single";
    if (all > range) {
      access_ = "switch";
      if (options.device_address && info.buffer_device_address) {
        access_ = "address";
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
    const bool address = access_ == std::string("address");
    auto slot_addresses = addresses_.as<uint64_t>();
    for (uint64_t s = 0; s < slots; ++s) {
      const uint64_t first = s * bricks_per_slot_;
      const uint64_t count = std::min<uint64_t>(bricks_per_slot_, packed_.brick_count - std::min(first, packed_.brick_count));
      const size_t bytes = size_t(count * packed_.brick_bytes + 4);
      pools_.emplace_back(context, bytes, address);
      std::memcpy(pools_.back().data(), packed_.bricks.data() + first * packed_.brick_bytes, bytes);
      slot_addresses[s] = pools_.back().device_address();
      pool_bytes_ += bytes;
    }
    pool_bytes_ += nodes_.size() + masks_.size();
    if (access_ == std::string("single")) {
      spirv_ = svo_spv_trace_single_comp;
    } else if (address) {
      spirv_ = svo_spv_trace_address_comp;
    } else {
      spirv_ = svo_spv_trace_switch_comp;
      bindings_ = 7 + kPoolSlots;
    }
  }

  std::string name() const override { return "trace"; }
  std::vector<ImageDesc> reads() const override { return {}; }
  std::vector<ImageDesc> writes() const override {
    return {colour_image(), background_image(), gbuffer_image(), steps_image()};
  }

  double run(PassContext& ctx) override {
    const RenderSettings& settings = ctx.settings;
    FrameImages& images = ctx.images;
    TraceParams p = make_trace_params(tree_, packed_, settings);
    p.pool.y = bricks_per_slot_;
    const uint64_t limit = context_.info().max_storage_buffer_range;
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    // The largest image the kernel binds must fit one storage buffer.
    const uint64_t largest = pixels * texel_bytes(settings.gbuffer ? TexelFormat::GBuffer : TexelFormat::Rgba32f);
    if (largest > limit) {
      throw std::invalid_argument("a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                  (settings.gbuffer ? " G-buffer" : " colour image") +
                                  " exceeds the device's maxStorageBufferRange of " + mib(limit));
    }
    std::memcpy(params_.data(), &p, sizeof p);
    auto buffer = [&](const ImageDesc& desc) -> vk::Buffer* { return images.write(desc).buffer(); };
    std::vector<const vk::Buffer*> bound{&params_, &nodes_, &masks_, buffer(colour_image()),
                                         settings.gbuffer ? buffer(gbuffer_image()) : &no_gbuffer_,
                                         buffer(steps_image()), buffer(background_image())};
    if (access_ == std::string("address")) {
      bound.push_back(&addresses_);
    } else {
      const size_t slots = access_ == std::string("single") ? 1 : kPoolSlots;
      for (size_t s = 0; s < slots; ++s) bound.push_back(&pools_[std::min(s, pools_.size() - 1)]);
    }
    const uint32_t gx = (settings.width + kGroup - 1) / kGroup, gy = (settings.height + kGroup - 1) / kGroup;
    // Many rays per pixel (raymarch): a few rows of the ray grid per
    // dispatch, averaged here. Lavapipe ends all loops of an invocation
    // after 65,535 iterations in total, which 64 rays of a march reach (the
    // picture then breaks in 8 x 8 blocks). Unrolling the trilinear loop
    // instead costs 1.8x per frame on lavapipe.
    const uint32_t n = uint32_t(p.lens.w);
    const uint32_t rows = settings.mode == Mode::RayMarch ? std::max(1u, kRaysPerDispatch / n) : n;
    vk::ComputeKernel& kernel = kernel_for(settings);
    if (rows >= n) return kernel.dispatch(bound, nullptr, gx, gy);
    // Sums over the dispatches: colour and background weighted by the
    // share of rays, the G-buffer by coverage too (gbuffer.glsl).
    using svo::math::SvoGBuffer;
    constexpr size_t n4 = svo::math::SVO_GBUFFER_VEC4S;
    std::vector<glm::vec4> colour(pixels, glm::vec4(0)), background(pixels, glm::vec4(0));
    std::vector<SvoGBuffer> g(settings.gbuffer ? pixels : 0, svo::math::svo_gbuffer_empty());
    std::vector<float> covered(g.size(), 0.0f);
    std::vector<uint32_t> steps(pixels, 0);
    auto c = images.texels<glm::vec4>(images.read(colour_image()));
    auto bg = images.texels<glm::vec4>(images.read(background_image()));
    auto st = images.texels<uint32_t>(images.read(steps_image()));
    auto gb = settings.gbuffer ? images.texels<glm::vec4>(images.read(gbuffer_image())) : std::span<glm::vec4>();
    double ms = 0;
    for (uint32_t first = 0; first < n; first += rows) {
      p.lens.z = float(first);
      p.lens.w = float(std::min(rows, n - first));
      std::memcpy(params_.data(), &p, sizeof p);
      double part = kernel.dispatch(bound, nullptr, gx, gy);
      ms = part < 0 || ms < 0 ? -1 : ms + part;
      const float w = p.lens.w / float(n);
      for (size_t i = 0; i < pixels; ++i) {
        colour[i] += w * c[i];
        background[i] += w * bg[i];
        steps[i] += st[i];
        if (settings.gbuffer) {
          const glm::vec4* t = &gb[n4 * i];
          SvoGBuffer part_g = svo::math::svo_gbuffer_unpack(t[0], t[1], t[2], t[3], t[4], t[5]);
          g[i] = svo::math::svo_gbuffer_madd(g[i], part_g, w * part_g.coverage);
          covered[i] += w * part_g.coverage;
        }
      }
    }
    for (size_t i = 0; i < pixels; ++i) {
      c[i] = colour[i];
      bg[i] = background[i];
      st[i] = steps[i];
      if (settings.gbuffer) {
        g[i].coverage = covered[i];
        SvoGBuffer done = svo::math::svo_gbuffer_finish(g[i], covered[i]);
        for (uint32_t k = 0; k < n4; ++k) gb[n4 * i + k] = svo::math::svo_gbuffer_pack(done, k);
      }
    }
    return ms;
  }

  // The pipeline specialised for the settings' mode, shadows and detail
  // (tracer_params.glsl, "Specialisation"), made at its first use.
  vk::ComputeKernel& kernel_for(const RenderSettings& settings) {
    using namespace svo::math;
    uint32_t flags = SVO_SPEC_ANY;
    if (!settings.shadows) flags &= ~SVO_FLAG_SHADOWS;
    if (tree_.detail.octaves == 0) flags &= ~SVO_FLAG_DETAIL;
    const std::pair<uint32_t, uint32_t> key{uint32_t(settings.mode), flags};
    auto& kernel = kernels_[key];
    if (!kernel) {
      const uint32_t spec[] = {key.first, key.second};
      kernel = std::make_unique<vk::ComputeKernel>(context_, spirv_, bindings_, 0, spec);
    }
    return *kernel;
  }

  size_t pool_bytes() const { return pool_bytes_; }
  uint32_t pool_buffers() const { return uint32_t(pools_.size()); }
  const char* pool_access() const { return access_; }

 private:
  vk::Context& context_;
  const octree::Octree& tree_;
  PackedOctree packed_;
  uint32_t bricks_per_slot_ = 1;
  vk::Buffer params_, nodes_, masks_;
  vk::Buffer addresses_;  // device address of each pool buffer (the "address" kernel)
  vk::Buffer no_gbuffer_;  // bound in the G-buffer's place when the settings do not ask for it
  const char* access_ = "single";
  std::vector<vk::Buffer> pools_;
  std::span<const uint32_t> spirv_;  // the kernel of the pools' access
  uint32_t bindings_ = 8;
  std::map<std::pair<uint32_t, uint32_t>, std::unique_ptr<vk::ComputeKernel>> kernels_;  // by specialisation
  size_t pool_bytes_ = 0;
};

}  // namespace

GpuRenderer::GpuRenderer(vk::Context& context, const octree::Octree& tree, const Options& options)
    : GpuRenderer(nullptr, &context, tree, options) {}

GpuRenderer::GpuRenderer(std::unique_ptr<vk::Context> context, const octree::Octree& tree, const Options& options)
    : GpuRenderer(std::move(context), nullptr, tree, options) {}

GpuRenderer::GpuRenderer(std::unique_ptr<vk::Context> owned, vk::Context* context, const octree::Octree& tree,
                         const Options& options)
    : Renderer(Host::Vulkan, context, std::move(owned)) {
  vk::Context& c = *vulkan();
  set_trace(std::make_unique<TracePass>(c, tree, options));
  // Drivers may compile a pipeline at its first dispatch (lavapipe takes
  // about a second): do it here, so that frame times are frame times.
  RenderSettings warm_up;
  warm_up.width = warm_up.height = 1;
  warm_up.camera.eye = tree.origin - glm::vec3(tree.size);
  warm_up.camera.target = tree.origin + 0.5f * glm::vec3(tree.size);
  warm_up.display = true;
  render(warm_up);
}

namespace {
const TracePass& trace_of(const Pass& pass) { return static_cast<const TracePass&>(pass); }
}  // namespace

std::size_t GpuRenderer::pool_bytes() const { return trace_of(first_pass()).pool_bytes(); }

uint32_t GpuRenderer::pool_buffers() const { return trace_of(first_pass()).pool_buffers(); }

const char* GpuRenderer::pool_access() const { return trace_of(first_pass()).pool_access(); }

}  // namespace svo::render
