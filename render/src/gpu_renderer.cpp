#include <algorithm>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "svo/render/renderer.h"
#include "svo/render/vk_compute.h"
#include "display.comp.spv.h"
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

// The cone tracer as the first pass: writes "colour", "gbuffer", "steps".
class TracePass : public Pass {
 public:
  TracePass(vk::Context& context, const octree::Octree& tree, const GpuRenderer::Options& options)
      : context_(context),
        tree_(tree),
        packed_(pack_octree(tree)),
        params_(context, sizeof(TraceParams)),
        nodes_(context, std::max<size_t>(8, packed_.nodes.size() * sizeof(glm::uvec2))),
        masks_(context, tracer_mask_buffer().size() * sizeof(Mask)),
        addresses_(context, kPoolSlots * sizeof(uint64_t)) {
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
      kernel_.emplace(context, svo_spv_trace_single_comp, 7, 0);
    } else if (address) {
      kernel_.emplace(context, svo_spv_trace_address_comp, 7, 0);
    } else {
      kernel_.emplace(context, svo_spv_trace_switch_comp, 6 + kPoolSlots, 0);
    }
  }

  std::string name() const override { return "trace"; }
  std::vector<std::string> reads() const override { return {}; }
  std::vector<std::string> writes() const override { return {"colour", "gbuffer", "steps"}; }

  double run(FrameImages& images, const RenderSettings& settings) override {
    TraceParams p = make_trace_params(tree_, packed_, settings);
    p.pool.y = bricks_per_slot_;
    const uint64_t limit = context_.info().max_storage_buffer_range;
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    if (pixels * 3 * sizeof(glm::vec4) > limit) {
      throw std::invalid_argument("a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                  " G-buffer exceeds the device's maxStorageBufferRange of " + mib(limit));
    }
    std::memcpy(params_.data(), &p, sizeof p);
    std::vector<const vk::Buffer*> bound{&params_, &nodes_, &masks_, &images.image("colour", sizeof(glm::vec4)),
                                         &images.image("gbuffer", 3 * sizeof(glm::vec4)),
                                         &images.image("steps", sizeof(uint32_t))};
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
    if (rows >= n) return kernel_->dispatch(bound, nullptr, gx, gy);
    std::vector<glm::vec4> colour(pixels, glm::vec4(0)), g(settings.gbuffer ? 3 * pixels : 0, glm::vec4(0));
    std::vector<uint32_t> steps(pixels, 0);
    double ms = 0;
    for (uint32_t first = 0; first < n; first += rows) {
      p.lens.z = float(first);
      p.lens.w = float(std::min(rows, n - first));
      std::memcpy(params_.data(), &p, sizeof p);
      double part = kernel_->dispatch(bound, nullptr, gx, gy);
      ms = part < 0 || ms < 0 ? -1 : ms + part;
      const float w = p.lens.w / float(n);
      auto c = images.existing("colour").as<glm::vec4>();
      auto st = images.existing("steps").as<uint32_t>();
      auto gb = images.existing("gbuffer").as<glm::vec4>();
      for (size_t i = 0; i < pixels; ++i) {
        colour[i] += w * c[i];
        steps[i] += st[i];
        if (settings.gbuffer) {
          // G-buffer fields are coverage-weighted averages.
          const float cw = w * c[i].a;
          g[3 * i] += cw * gb[3 * i];
          g[3 * i + 1] += cw * gb[3 * i + 1];
          g[3 * i + 2] += glm::vec4(cw * glm::vec3(gb[3 * i + 2]), 0.0f);
        }
      }
    }
    auto c = images.existing("colour").as<glm::vec4>();
    auto st = images.existing("steps").as<uint32_t>();
    auto gb = images.existing("gbuffer").as<glm::vec4>();
    for (size_t i = 0; i < pixels; ++i) {
      c[i] = colour[i];
      st[i] = steps[i];
      if (settings.gbuffer) {
        const float inv = colour[i].a > 0 ? 1.0f / colour[i].a : 0.0f;
        gb[3 * i] = inv * g[3 * i];
        gb[3 * i + 1] = inv * g[3 * i + 1];
        gb[3 * i + 2] = glm::vec4(inv * glm::vec3(g[3 * i + 2]), colour[i].a);
      }
    }
    return ms;
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
  const char* access_ = "single";
  std::vector<vk::Buffer> pools_;
  std::optional<vk::ComputeKernel> kernel_;  // created once the number of pool buffers is known
  size_t pool_bytes_ = 0;
};

}  // namespace

void FrameImages::resize(uint32_t width, uint32_t height) {
  if (width != width_ || height != height_) images_.clear();
  width_ = width;
  height_ = height;
}

vk::Buffer& FrameImages::image(const std::string& name, std::size_t texel_bytes) {
  const size_t bytes = std::max<size_t>(4, size_t(width_) * height_ * texel_bytes);
  auto it = images_.find(name);
  if (it != images_.end() && it->second.size() == bytes) return it->second;
  if (it != images_.end()) images_.erase(it);
  return images_.emplace(name, vk::Buffer(context_, bytes)).first->second;
}

vk::Buffer& FrameImages::existing(const std::string& name) {
  auto it = images_.find(name);
  if (it == images_.end()) throw std::invalid_argument("frame image '" + name + "' does not exist");
  return it->second;
}

DisplayPass::DisplayPass(vk::Context& context) : kernel_(context, svo_spv_display_comp, 2, sizeof(uint32_t)) {}

double DisplayPass::run(FrameImages& images, const RenderSettings&) {
  const uint32_t count = images.width() * images.height();
  const vk::Buffer* bound[] = {&images.existing("colour"), &images.image("display", sizeof(uint32_t))};
  return kernel_.dispatch(bound, &count, (count + 63) / 64);
}

struct GpuRenderer::Impl {
  vk::Context& context;
  TracePass* trace;  // passes.front()
  std::vector<std::unique_ptr<Pass>> passes;
  std::vector<std::string> written;  // images the chain writes so far
  DisplayPass display;
  FrameImages images;

  Impl(vk::Context& c, const octree::Octree& t, const Options& options) : context(c), display(c), images(c) {
    auto tp = std::make_unique<TracePass>(c, t, options);
    trace = tp.get();
    add(std::move(tp));
    // Drivers may compile a pipeline at its first dispatch (lavapipe takes
    // about a second): do it here, so that frame times are frame times.
    RenderSettings warm_up;
    warm_up.width = warm_up.height = 1;
    warm_up.camera.eye = t.origin - glm::vec3(t.size);
    warm_up.camera.target = t.origin + 0.5f * glm::vec3(t.size);
    warm_up.display = true;
    render(warm_up);
  }

  void add(std::unique_ptr<Pass> pass) {
    for (const auto& r : pass->reads()) {
      if (std::find(written.begin(), written.end(), r) == written.end()) {
        throw std::invalid_argument("pass '" + pass->name() + "' reads image '" + r + "' that no earlier pass writes");
      }
    }
    for (const auto& w : pass->writes()) written.push_back(w);
    passes.push_back(std::move(pass));
  }

  Frame render(const RenderSettings& settings) {
    auto start = std::chrono::steady_clock::now();
    images.resize(settings.width, settings.height);
    Frame frame;
    frame.width = settings.width;
    frame.height = settings.height;
    frame.gpu_ms = 0;
    auto time = [&](double ms) { frame.gpu_ms = ms < 0 || frame.gpu_ms < 0 ? -1 : frame.gpu_ms + ms; };
    for (auto& pass : passes) time(pass->run(images, settings));
    if (settings.display) time(display.run(images, settings));
    const size_t pixels = size_t(settings.width) * settings.height;
    auto colours = images.existing("colour").as<glm::vec4>();
    frame.colour.assign(colours.begin(), colours.begin() + pixels);
    auto counts = images.existing("steps").as<uint32_t>();
    frame.steps.assign(counts.begin(), counts.begin() + pixels);
    if (settings.gbuffer) {
      auto texels = images.existing("gbuffer").as<glm::vec4>();
      frame.gbuffer.resize(pixels);
      for (size_t i = 0; i < pixels; ++i) {
        glm::vec4 a = texels[3 * i], b = texels[3 * i + 1], c = texels[3 * i + 2];
        frame.gbuffer[i] = {a.x, glm::vec3(a.y, a.z, a.w), glm::vec3(b), b.w, glm::vec3(c), c.w};
      }
    }
    if (settings.display) {
      auto d = images.existing("display").as<uint32_t>();
      frame.display.assign(d.begin(), d.begin() + pixels);
    }
    finish_frame_stats(frame);
    frame.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return frame;
  }
};

GpuRenderer::GpuRenderer(vk::Context& context, const octree::Octree& tree, const Options& options)
    : impl_(std::make_unique<Impl>(context, tree, options)) {}

GpuRenderer::~GpuRenderer() = default;

Frame GpuRenderer::render(const RenderSettings& settings) { return impl_->render(settings); }

std::size_t GpuRenderer::pool_bytes() const { return impl_->trace->pool_bytes(); }

void GpuRenderer::add_pass(std::unique_ptr<Pass> pass) { impl_->add(std::move(pass)); }

FrameImages& GpuRenderer::images() { return impl_->images; }

}  // namespace svo::render

namespace svo::render {
uint32_t GpuRenderer::pool_buffers() const { return impl_->trace->pool_buffers(); }

const char* GpuRenderer::pool_access() const { return impl_->trace->pool_access(); }
}  // namespace svo::render
