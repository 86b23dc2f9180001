// The Vulkan host: the octree's pools on the device and the trace pass as a
// compute kernel (shaders/render/trace_main.glsl).
#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

#include "common/shared_math.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_compute.h"
#include "trace_address.comp.spv.h"
#include "trace_setup.h"
#include "trace_single.comp.spv.h"
#include "trace_switch.comp.spv.h"

namespace svo::render {

namespace {

constexpr uint32_t kGroup = 8;             // local_size_x = local_size_y
constexpr uint32_t kRaysPerDispatch = 16;  // raymarch: rays per pixel in one dispatch, at most
constexpr uint32_t kConesPerDispatch = 16;  // a lens in parts: cones per pixel in one dispatch, at most

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// Writes the pixels of the trace's images outside `rect` as the kernel
// would (svo_background_pixel: the background, no coverage, no steps, an
// empty G-buffer texel), where it is not run. Returns the milliseconds taken.
double fill_background(FrameImages& images, const RenderSettings& settings, const TraceParams& p, PixelRect rect) {
  const uint32_t width = settings.width, height = settings.height;
  if (rect.x0 == 0 && rect.y0 == 0 && rect.x1 == width && rect.y1 == height) return 0;
  const auto start = std::chrono::steady_clock::now();
  auto colour = images.texels<glm::vec4>(images.read(colour_image()));
  auto background = images.texels<glm::vec4>(images.read(background_image()));
  auto steps = images.texels<uint32_t>(images.read(steps_image()));
  auto gbuffer = settings.gbuffer ? images.texels<glm::vec4>(images.read(gbuffer_image())) : std::span<glm::vec4>();
  constexpr uint32_t n4 = svo::math::SVO_GBUFFER_VEC4S;
  glm::vec4 empty[n4];
  for (uint32_t k = 0; k < n4; ++k) empty[k] = svo::math::svo_gbuffer_pack(svo::math::svo_gbuffer_empty(), k);
  const glm::vec3 bg(p.background);
  for (uint32_t y = 0; y < height; ++y) {
    const bool row_inside = y >= rect.y0 && y < rect.y1;
    for (uint32_t x = 0; x < width; ++x) {
      if (row_inside && x == rect.x0) {
        x = rect.x1 - 1;
        continue;
      }
      const size_t i = size_t(y) * width + x;
      colour[i] = glm::vec4(bg, 0.0f);
      background[i] = glm::vec4(bg, 1.0f);
      steps[i] = 0;
      if (!gbuffer.empty()) std::copy(empty, empty + n4, &gbuffer[n4 * i]);
    }
  }
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The cone tracer as the first pass: writes "colour", "background",
// "gbuffer" (when the settings ask for it) and "steps".
class TracePass : public Pass {
 public:
  TracePass(vk::Context& context, const OctreeAccess& octree)
      : context_(context),
        octree_(octree),
        no_gbuffer_(context, 16),
        spirv_(octree.pick_kernel(svo_spv_trace_single_comp, svo_spv_trace_address_comp, svo_spv_trace_switch_comp)) {}

  std::string name() const override { return "trace"; }
  std::vector<ImageDesc> reads() const override { return {}; }
  std::vector<ImageDesc> writes() const override { return trace_images(); }

  double run(PassContext& ctx) override {
    const RenderSettings& settings = ctx.settings;
    FrameImages& images = ctx.images;
    TraceParams p = octree_.params(settings);
    const uint64_t limit = context_.info().max_storage_buffer_range;
    const uint64_t pixels = uint64_t(settings.width) * settings.height;
    // The largest image the kernel binds must fit one storage buffer.
    const uint64_t largest = pixels * texel_bytes(settings.gbuffer ? TexelFormat::GBuffer : TexelFormat::Rgba32f);
    if (largest > limit) {
      throw std::invalid_argument("a " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                                  (settings.gbuffer ? " G-buffer" : " colour image") +
                                  " exceeds the device's maxStorageBufferRange of " + mib(limit));
    }
    auto buffer = [&](const ImageDesc& desc) -> vk::Buffer* { return images.write(desc).buffer(); };
    std::vector<const vk::Buffer*> bound{buffer(colour_image()),
                                         settings.gbuffer ? buffer(gbuffer_image()) : &no_gbuffer_,
                                         buffer(steps_image()), buffer(background_image())};
    octree_.bind(p, bound);
    // Only the work groups over the pixels whose cones may meet the domain:
    // lavapipe runs a kernel's code for every lane of a SIMD group, even
    // lanes that returned, so a pixel that misses costs it far more than
    // writing the background here (an all-miss 512^2 frame: 52 ms).
    const PixelRect rect = domain_pixel_rect(p);
    const double fill_ms = fill_background(images, settings, p, rect);
    const uint32_t bx = rect.x0 / kGroup, by = rect.y0 / kGroup;
    const uint32_t gx = rect.empty() ? 0 : (rect.x1 + kGroup - 1) / kGroup - bx;
    const uint32_t gy = rect.empty() ? 0 : (rect.y1 + kGroup - 1) / kGroup - by;
    if (gx == 0 || gy == 0) return fill_ms;
    // Many rays (raymarch) or lens parts (a cone each) per pixel: a few
    // rows of their grid per dispatch, averaged here. Lavapipe ends all
    // loops of an invocation after 65,535 iterations in total, which 64
    // rays of a march reach (the picture then breaks in 8 x 8 blocks), and
    // 64 cones of a lens in 8 x 8 parts too (the elephant's strong blur:
    // 34.7 dB against the native host). Unrolling the trilinear loop
    // instead costs 1.8x per frame on lavapipe.
    const uint32_t n = uint32_t(p.lens.w);
    const uint32_t rows = std::max(1u, (settings.mode == Mode::RayMarch ? kRaysPerDispatch : kConesPerDispatch) / n);
    vk::ComputeKernel& kernel = kernel_for(settings, p);
    auto dispatch = [&] {
      const double ms = kernel.dispatch_base(bound, nullptr, bx, by, gx, gy);
      return ms < 0 ? ms : ms + fill_ms;
    };
    if (rows >= n) return dispatch();
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
    double ms = fill_ms;
    for (uint32_t first = 0; first < n; first += rows) {
      p.lens.z = float(first);
      p.lens.w = float(std::min(rows, n - first));
      bound.resize(4);
      octree_.bind(p, bound);
      double part = kernel.dispatch_base(bound, nullptr, bx, by, gx, gy);
      ms = part < 0 || ms < 0 ? -1 : ms + part;
      const float w = p.lens.w / float(n);
      for (size_t i = 0; i < pixels; ++i) {
        colour[i] += w * c[i];
        background[i] += w * bg[i];
        steps[i] += st[i];
        if (settings.gbuffer) {
          const SvoGBuffer part_g = gbuffer_at(&gb[n4 * i]);
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

  // The pipeline specialised for the settings' mode, shadows, G-buffer,
  // detail, level blending and shading normals (tracer_params.glsl, "Specialisation"),
  // made at its first use.
  vk::ComputeKernel& kernel_for(const RenderSettings& settings, const TraceParams& p) {
    using namespace svo::math;
    uint32_t flags = SVO_SPEC_ANY;
    if (!settings.shadows) flags &= ~SVO_FLAG_SHADOWS;
    if (!settings.gbuffer) flags &= ~SVO_FLAG_GBUFFER;
    if (octree_.tree().detail.octaves == 0) flags &= ~SVO_FLAG_DETAIL;
    if (!cones_may_blend(p)) flags &= ~SVO_FLAG_LEVEL_BLEND;
    if (p.offsets_c.x == SVO_ABSENT) flags &= ~SVO_FLAG_SHADING_NORMAL;
    const std::pair<uint32_t, uint32_t> key{uint32_t(settings.mode), flags};
    auto& kernel = kernels_[key];
    if (!kernel) {
      const uint32_t spec[] = {key.first, key.second};
      kernel = std::make_unique<vk::ComputeKernel>(context_, spirv_, 4 + octree_.binding_count(), 0, spec);
    }
    return *kernel;
  }

 private:
  vk::Context& context_;
  const OctreeAccess& octree_;
  vk::Buffer no_gbuffer_;            // bound in the G-buffer's place when the settings do not ask for it
  std::span<const uint32_t> spirv_;  // the kernel of the pools' access
  std::map<std::pair<uint32_t, uint32_t>, std::unique_ptr<vk::ComputeKernel>> kernels_;  // by specialisation
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
  set_octree(std::make_unique<OctreeAccess>(tree, c, options.max_buffer_bytes, options.device_address));
  set_trace(std::make_unique<TracePass>(c, octree()));
  // Drivers may compile a pipeline at its first dispatch (lavapipe takes
  // about a second): do it here, so that frame times are frame times.
  RenderSettings warm_up;
  warm_up.width = warm_up.height = 1;
  warm_up.camera.eye = tree.origin - glm::vec3(tree.size);
  warm_up.camera.target = tree.origin + 0.5f * glm::vec3(tree.size);
  warm_up.display = true;
  render(warm_up);
}

std::size_t GpuRenderer::pool_bytes() const { return octree().pool_bytes(); }

uint32_t GpuRenderer::pool_buffers() const { return octree().pool_buffers(); }

const char* GpuRenderer::pool_access() const { return pool_access_name(octree().pool_access()); }

}  // namespace svo::render
