// The bandwidth-adaptive pass (passes.h; Bagher et al. 2013): the kernels
// of shaders/common/bandwidth.glsl over the G-buffer, level by level.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstring>
#include <span>
#include <stdexcept>

#include "adaptive_address.comp.spv.h"
#include "adaptive_single.comp.spv.h"
#include "adaptive_switch.comp.spv.h"
#include "shading_cache.h"
#include "svo/render/bandwidth.h"
#include "svo/render/octree_access.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"

namespace svo::math {

struct NativeAdaptive : render::NativeOctreeReader, render::NativeShadingReader {
  SvoAdaptiveParams adapt{};
  const float* bw_tables = nullptr;
  const glm::vec4* gbuf = nullptr;
  const glm::vec4* bw_pyramid = nullptr;
  const glm::vec4* pyramid = nullptr;
  std::array<std::size_t, SVO_ADAPTIVE_LEVELS> offset{};
  std::array<uint32_t, SVO_ADAPTIVE_LEVELS> width{};

  float svo_bw_table(uint32_t i) const { return bw_tables[i]; }
  SvoGBuffer svo_adaptive_gbuffer(uint32_t pixel) const {
    return render::gbuffer_at(gbuf + render::kGBufferVec4s * pixel);
  }
  vec4 svo_adaptive_bandwidth(uint32_t level, uvec2 q) const {
    return bw_pyramid[offset[level] + std::size_t(q.y) * width[level] + q.x];
  }
  vec4 svo_adaptive_pyramid(uint32_t level, uvec2 q) const {
    return pyramid[offset[level] + std::size_t(q.y) * width[level] + q.x];
  }
#include "common/bandwidth.glsl"
};

}  // namespace svo::math

namespace svo::render {

using svo::math::SVO_ADAPTIVE_LEVELS;

ImageDesc AdaptivePass::bandwidth_image() { return {"bandwidth", TexelFormat::Rgba32f, 1, SVO_ADAPTIVE_LEVELS}; }
ImageDesc AdaptivePass::pyramid_image() { return {"adaptive", TexelFormat::Rgba32f, 1, SVO_ADAPTIVE_LEVELS}; }

struct AdaptivePass::Cache {
  ShadingCache shading;
  uint64_t generation = ~uint64_t(0);  // of the shading tables the bandwidth tables were built from
  std::vector<float> tables;
  glm::uvec4 table_offsets{0};
  glm::uvec4 area_offsets{0};
  uint32_t brdf_count = 0;
  // The Vulkan host's kernel and buffers.
  std::unique_ptr<vk::ComputeKernel> kernel;
  std::unique_ptr<vk::Buffer> adapt, tables_buffer;
};

AdaptivePass::AdaptivePass() : cache_(std::make_unique<Cache>()) {}
AdaptivePass::~AdaptivePass() = default;

namespace {

// The bandwidth tables of the frame's environment and materials
// (bandwidth.glsl's svo_bw_table): the environment's angular bandwidth map,
// then 16^3 floats per material in the shading tables' order, then the
// area light's spatial bandwidth grid (`area`: offset, width, height).
void build_bandwidth_tables(const ShadingOptions& options, const std::vector<const Material*>& materials,
                            std::vector<float>& tables, glm::uvec4& offsets, uint32_t& brdf_count, glm::uvec4& area) {
  tables.assign(1, 0.0f);  // offset 0 stays unused
  offsets = glm::uvec4(0);
  area = glm::uvec4(0);
  if (options.environment) {
    const Environment& env = *options.environment;
    const uint32_t out = std::bit_floor(std::min(env.width, 256u));
    const EnvironmentBandwidth bw = environment_bandwidth(env, out);
    offsets = glm::uvec4(uint32_t(tables.size()), bw.width, bw.height, 0);
    tables.insert(tables.end(), bw.cycles_per_radian.begin(), bw.cycles_per_radian.end());
  }
  offsets.w = uint32_t(tables.size());
  for (const Material* m : materials) {
    const std::vector<float> b = brdf_bandwidth(*m);
    tables.insert(tables.end(), b.begin(), b.end());
  }
  brdf_count = uint32_t(materials.size());
  if (options.area_light) {
    const AreaLightBandwidth bw = area_light_bandwidth(*options.area_light);
    area = glm::uvec4(uint32_t(tables.size()), bw.width, bw.height, 0);
    tables.insert(tables.end(), bw.cycles_per_unit.begin(), bw.cycles_per_unit.end());
  }
}

template <class F>
void for_texels(uint32_t w, uint32_t h, F f) {
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, h), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t y = r.begin(); y != r.end(); ++y)
      for (uint32_t x = 0; x < w; ++x) f(x, y);
  });
}

// The texels shaded over all levels, their samples, and the covered pixels.
void count_stats(const glm::vec4* pyramid, const glm::vec4* bandwidth, const glm::vec4* gbuffer,
                 std::span<const std::size_t> offset, std::span<const uint32_t> width, std::span<const uint32_t> height,
                 uint32_t coarsest, std::size_t pixels, AdaptivePass::Stats& stats) {
  for (uint32_t l = 0; l <= coarsest; ++l) {
    const std::size_t n = std::size_t(width[l]) * height[l];
    for (std::size_t i = 0; i < n; ++i) {
      if (pyramid[offset[l] + i].w != svo::math::SVO_ADAPTIVE_SHADED) continue;
      ++stats.shaded;
      ++stats.shaded_at_level[l];
      stats.samples += uint64_t(bandwidth[offset[l] + i].y + 0.5f);
    }
  }
  for (std::size_t i = 0; i < pixels; ++i) {
    if (!(gbuffer[kGBufferVec4s * i + 1].w > 0)) continue;
    ++stats.covered;
    ++stats.pixels_at_level[std::min(uint32_t(bandwidth[i].x), 7u)];
  }
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

double AdaptivePass::run(PassContext& ctx) {
  const auto start = std::chrono::steady_clock::now();
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  Cache& c = *cache_;
  ShadingTables& t = c.shading.update(ctx);
  const bool vulkan = ctx.host == Host::Vulkan;
  if (vulkan && (ctx.settings.shading.env_shadows || ctx.settings.shadows)) {
    // Visibility cones in every sample pass lavapipe's loop limit (forward_pass.cpp).
    throw std::runtime_error("the adaptive pass traces no shadows on a Vulkan device yet (use --cpu)");
  }
  double tables_ms = 0;
  if (c.shading.generation() != c.generation) {
    const auto tables_start = std::chrono::steady_clock::now();
    build_bandwidth_tables(ctx.settings.shading, c.shading.materials(), c.tables, c.table_offsets, c.brdf_count,
                           c.area_offsets);
    c.generation = c.shading.generation();
    c.tables_buffer.reset();
    tables_ms = ms_since(tables_start);
  }
  const AdaptiveOptions& o = ctx.settings.adaptive;
  const uint32_t W = ctx.images.width(), H = ctx.images.height();
  const uint32_t coarsest =
      std::min({o.coarsest, SVO_ADAPTIVE_LEVELS - 1u, uint32_t(std::bit_width(std::min(W, H))) - 1u});

  svo::math::NativeAdaptive k{octree.native(params), {t.params, t.floats.data()}};
  k.adapt.config = glm::uvec4(std::max(o.directions, 1u), std::max(o.max_spp, 1u),
                              (o.slope_limit ? svo::math::SVO_ADAPTIVE_SLOPE_LIMIT : 0u) |
                                  (o.finest ? svo::math::SVO_ADAPTIVE_FINEST : 0u) |
                                  (o.measured_variance ? svo::math::SVO_ADAPTIVE_MEASURED : 0u),
                              coarsest);
  k.adapt.quality = glm::vec4(o.tau, o.sigma_z, float(std::max(o.min_spp, 1u)), 0.0f);
  k.adapt.tables = c.table_offsets;
  const uint32_t side = o.bandwidth_block == 2 ? 2u : 1u;
  k.adapt.frame = glm::uvec4(0, c.brdf_count, side, 0);
  k.adapt.area = c.area_offsets;
  k.bw_tables = c.tables.data();
  const ImageDesc bw_desc = bandwidth_image();
  std::array<uint32_t, SVO_ADAPTIVE_LEVELS> height{};
  std::size_t at = 0;
  for (uint32_t l = 0; l < SVO_ADAPTIVE_LEVELS; ++l) {
    k.offset[l] = at;
    k.width[l] = bw_desc.width(W, l);
    height[l] = bw_desc.height(H, l);
    at += std::size_t(k.width[l]) * height[l];
  }

  ImageMemory& gbuffer = ctx.images.read(gbuffer_image());
  ImageMemory& background = ctx.images.read(background_image());
  ImageMemory& colour_memory = ctx.images.write(colour_image());
  ImageMemory& bw_memory = ctx.images.write(bw_desc);
  ImageMemory& pyr_memory = ctx.images.write(pyramid_image());
  ImageMemory& mask_memory = ctx.images.write(mask_image());
  auto* colour = static_cast<glm::vec4*>(colour_memory.data());
  auto* bw = static_cast<glm::vec4*>(bw_memory.data());
  auto* pyr = static_cast<glm::vec4*>(pyr_memory.data());
  auto* mask = static_cast<glm::vec4*>(mask_memory.data());
  const auto* g = static_cast<const glm::vec4*>(gbuffer.data());
  const auto* back = static_cast<const glm::vec4*>(background.data());
  k.gbuf = g;
  k.bw_pyramid = bw;
  k.pyramid = pyr;
  // Levels coarser than the coarsest stay pending (the mask reads them).
  std::fill(pyr, pyr + at, glm::vec4(0));
  stats_ = {};
  stats_.tables_ms = tables_ms;
  const auto bandwidth_start = std::chrono::steady_clock::now();

  if (vulkan) {
    if (!c.kernel) {
      const auto spirv =
          octree.pick_kernel(svo_spv_adaptive_single_comp, svo_spv_adaptive_address_comp, svo_spv_adaptive_switch_comp);
      c.kernel =
          std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 10 + octree.binding_count(), 2 * sizeof(uint32_t));
    }
    if (!c.adapt) c.adapt = std::make_unique<vk::Buffer>(*ctx.vulkan, sizeof(svo::math::SvoAdaptiveParams));
    std::memcpy(c.adapt->data(), &k.adapt, sizeof(k.adapt));
    if (!c.tables_buffer) {
      c.tables_buffer = std::make_unique<vk::Buffer>(*ctx.vulkan, c.tables.size() * sizeof(float));
      std::memcpy(c.tables_buffer->data(), c.tables.data(), c.tables.size() * sizeof(float));
    }
    std::vector<const vk::Buffer*> bound{gbuffer.buffer(),
                                         background.buffer(),
                                         colour_memory.buffer(),
                                         c.shading.params_buffer(*ctx.vulkan),
                                         c.shading.tables_buffer(*ctx.vulkan),
                                         bw_memory.buffer(),
                                         pyr_memory.buffer(),
                                         mask_memory.buffer(),
                                         c.adapt.get(),
                                         c.tables_buffer.get()};
    octree.bind(params, bound);
    double device_ms = 0;
    auto dispatch = [&](uint32_t stage, uint32_t level, double& into) {
      const uint32_t push[2] = {stage, level};
      const uint32_t texels = stage == 0   ? ((W + side - 1) / side) * ((H + side - 1) / side)
                              : stage == 4 ? k.width[level] * height[level] * svo::math::SVO_ADAPTIVE_SLOTS
                                           : k.width[level] * height[level];
      const double ms = c.kernel->dispatch(bound, push, (texels + 63) / 64);
      into = ms < 0 || into < 0 ? -1 : into + ms;
      device_ms = ms < 0 || device_ms < 0 ? -1 : device_ms + ms;
    };
    dispatch(0, 0, stats_.bandwidth_ms);
    for (uint32_t l = 1; l < SVO_ADAPTIVE_LEVELS; ++l) dispatch(1, l, stats_.bandwidth_ms);
    // Each level: mark or upsample its texels, then take the marked ones'
    // samples, SVO_ADAPTIVE_SLOTS threads per texel.
    for (uint32_t l = coarsest + 1; l-- > 0;) {
      dispatch(2, l, stats_.shading_ms);
      dispatch(4, l, stats_.shading_ms);
    }
    dispatch(3, 0, stats_.shading_ms);
    count_stats(pyr, bw, g, k.offset, k.width, height, coarsest, std::size_t(W) * H, stats_);
    return device_ms;
  }

  // 1. The bandwidth buffer and its mips.
  const svo::math::SvoGBuffer none = svo::math::svo_gbuffer_empty();
  auto texel = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= int(W) || y >= int(H)) return none;
    return gbuffer_at(g + kGBufferVec4s * (std::size_t(y) * W + x));
  };
  for_texels((W + side - 1) / side, (H + side - 1) / side, [&](uint32_t bx, uint32_t by) {
    const glm::uvec2 rep = k.svo_bandwidth_representative(glm::uvec2(bx, by), side);
    const int ix = int(rep.x), iy = int(rep.y);
    const glm::vec4 estimate = k.svo_bandwidth_texel(texel(ix, iy), texel(ix - 1, iy), texel(ix + 1, iy),
                                                     texel(ix, iy - 1), texel(ix, iy + 1), rep.y * W + rep.x);
    for (uint32_t y = by * side; y < std::min((by + 1) * side, H); ++y)
      for (uint32_t x = bx * side; x < std::min((bx + 1) * side, W); ++x) {
        const std::size_t i = std::size_t(y) * W + x;
        bw[i] = k.svo_bandwidth_pixel(estimate, g[kGBufferVec4s * i + 1].w);
      }
  });
  for (uint32_t l = 1; l < SVO_ADAPTIVE_LEVELS; ++l) {
    const uint32_t fw = k.width[l - 1], fh = height[l - 1];
    const glm::vec4* fine = bw + k.offset[l - 1];
    glm::vec4* coarse = bw + k.offset[l];
    for_texels(k.width[l], height[l], [&](uint32_t x, uint32_t y) {
      auto child = [&](uint32_t dx, uint32_t dy) {
        const uint32_t cx = std::min(2 * x + dx, fw - 1), cy = std::min(2 * y + dy, fh - 1);
        return fine[std::size_t(cy) * fw + cx];
      };
      coarse[std::size_t(y) * k.width[l] + x] =
          k.svo_bandwidth_reduce(child(0, 0), child(1, 0), child(0, 1), child(1, 1));
    });
  }
  stats_.bandwidth_ms = ms_since(bandwidth_start);

  // 2. Coarse to fine, then the frame.
  const auto shading_start = std::chrono::steady_clock::now();
  for (uint32_t l = coarsest + 1; l-- > 0;) {
    glm::vec4* level = pyr + k.offset[l];
    for_texels(k.width[l], height[l], [&](uint32_t x, uint32_t y) {
      level[std::size_t(y) * k.width[l] + x] = k.svo_adaptive_level_texel(glm::uvec2(x, y), l, true);
    });
  }
  for_texels(W, H, [&](uint32_t x, uint32_t y) {
    const std::size_t i = std::size_t(y) * W + x;
    colour[i] = k.svo_adaptive_compose(gbuffer_at(g + kGBufferVec4s * i), back[i], uint32_t(i), glm::vec3(pyr[i]));
    mask[i] = k.svo_adaptive_mask(glm::uvec2(x, y));
  });
  stats_.shading_ms = ms_since(shading_start);
  count_stats(pyr, bw, g, k.offset, k.width, height, coarsest, std::size_t(W) * H, stats_);
  return ms_since(start);
}

}  // namespace svo::render
