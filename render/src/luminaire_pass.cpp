// The luminaire pass (passes.h) on both hosts: the kernel of
// shaders/common/luminaire.glsl over the G-buffer.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "luminaire_address.comp.spv.h"
#include "luminaire_single.comp.spv.h"
#include "luminaire_switch.comp.spv.h"
#include "shading_cache.h"
#include "svo/render/octree_access.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"

namespace svo::math {

struct NativeLuminaire : render::NativeOctreeReader, render::NativeShadingReader {
  const float* lum_tables = nullptr;
  // The state of pixels [state_begin, ...), state_stride entries each,
  // made on demand: an entry is made when first read (kUnmade until then),
  // so that the native host traces only the cells' cones that a sample
  // reads, as the Vulkan host, which makes every entry first, cannot.
  static constexpr uint32_t kUnmade = 0xFFFFFFFFu;
  float* state = nullptr;
  uint32_t state_begin = 0;
  uint32_t state_stride = 0;
  float svo_lum_table(uint32_t i) const { return lum_tables[i]; }
#include "common/luminaire.glsl"
  // (After the GLSL, whose SvoShadingPoint it takes.)
  float svo_lum_state(uint32_t pixel, uint32_t k, const SvoShadingPoint& p) {
    float& v = state[size_t(pixel - state_begin) * state_stride + k];
    if (floatBitsToUint(v) == kUnmade) v = svo_lum_state_entry(p, k, false);
    return v;
  }
};

}  // namespace svo::math

namespace svo::render {

struct LuminairePass::Cache {
  ShadingCache shading;
  // The luminaire tables of the options they were built from (held, so
  // that a freed light field's address cannot pass for it).
  std::vector<PlacedLuminaire> built_from;
  LuminaireOptions options_built;
  std::vector<float> tables;
  std::unique_ptr<vk::Buffer> tables_buffer;
  std::unique_ptr<vk::ComputeKernel> kernel;
  // The pixels' state (luminaire.glsl) of one band of pixels.
  std::vector<float> state;
  std::unique_ptr<vk::Buffer> state_buffer;

  const std::vector<float>& update(const LuminaireOptions& o) {
    auto same_placement = [](const LuminairePlacement& a, const LuminairePlacement& b) {
      return a.at == b.at && a.aim == b.aim && a.size == b.size;
    };
    bool same = !tables.empty() && o.luminaires.size() == built_from.size() && o.sampler == options_built.sampler &&
                o.search == options_built.search && o.visibility == options_built.visibility &&
                o.sequence == options_built.sequence && o.spp == options_built.spp && o.kmax == options_built.kmax &&
                o.search_depth == options_built.search_depth && o.seed == options_built.seed;
    for (size_t i = 0; same && i < o.luminaires.size(); ++i) {
      same = o.luminaires[i].field == built_from[i].field &&
             same_placement(o.luminaires[i].placement, built_from[i].placement);
    }
    if (!same) {
      tables = build_luminaire_tables(o);
      built_from = o.luminaires;
      options_built = o;
      options_built.luminaires.clear();
      tables_buffer.reset();
    }
    return tables;
  }
};

LuminairePass::LuminairePass(bool over_colour, uint64_t state_band_bytes)
    : over_(over_colour), band_bytes_(state_band_bytes), cache_(std::make_unique<Cache>()) {}
LuminairePass::~LuminairePass() = default;

std::vector<ImageDesc> LuminairePass::reads() const {
  if (over_) return {gbuffer_image(), colour_image()};
  return {gbuffer_image(), background_image()};
}

double LuminairePass::run(PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  Cache& c = *cache_;
  ShadingTables& t = c.shading.update(ctx);
  const std::vector<float>& lum = c.update(ctx.settings.luminaire);
  ImageMemory& gbuffer = ctx.images.read(gbuffer_image());
  ImageMemory& base = ctx.images.read(over_ ? colour_image() : background_image());
  ImageMemory& out = ctx.images.write(colour_image());
  const uint32_t count = ctx.images.width() * ctx.images.height();
  // Every image of every luminaire may draw up to K samples (at least one
  // each, and Eq. 12 rounds up): the calls cover them all.
  uint32_t most = 0;
  for (const auto& l : ctx.settings.luminaire.luminaires) most = std::max(most, l.field->image_count());
  const uint32_t samples = std::max(ctx.settings.luminaire.spp, 1u) + 2 * most;
  const uint32_t quadrature = ctx.settings.luminaire.quadrature;
  if (ctx.host == Host::Vulkan && quadrature > 0) {
    throw std::invalid_argument("the luminaire pass's quadrature runs on the native host only");
  }
  // The pixels' state is made band by band, a band at most band_bytes_.
  uint32_t stride = 0;
  std::memcpy(&stride, &lum[7], sizeof stride);
  stride = std::max(stride, 1u);
  const uint32_t band = uint32_t(std::min<uint64_t>(
      std::max<uint64_t>(64, band_bytes_ / (sizeof(float) * stride) / 64 * 64), (uint64_t(count) + 63) / 64 * 64));
  if (ctx.host == Host::Vulkan) {
    if (!c.kernel) {
      const auto spirv = octree.pick_kernel(svo_spv_luminaire_single_comp, svo_spv_luminaire_address_comp,
                                            svo_spv_luminaire_switch_comp);
      c.kernel =
          std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 7 + octree.binding_count(), 8 * sizeof(uint32_t));
    }
    if (!c.tables_buffer) {
      c.tables_buffer = std::make_unique<vk::Buffer>(*ctx.vulkan, lum.size() * sizeof(float));
      std::memcpy(c.tables_buffer->data(), lum.data(), lum.size() * sizeof(float));
    }
    const size_t state_bytes = size_t(band) * stride * sizeof(float);
    if (!c.state_buffer || c.state_buffer->size() < state_bytes) {
      c.state_buffer.reset();
      c.state_buffer = std::make_unique<vk::Buffer>(*ctx.vulkan, state_bytes);
    }
    std::vector<const vk::Buffer*> bound{gbuffer.buffer(),
                                         over_ ? gbuffer.buffer() : base.buffer(),
                                         out.buffer(),
                                         c.shading.params_buffer(*ctx.vulkan),
                                         c.shading.tables_buffer(*ctx.vulkan),
                                         c.tables_buffer.get(),
                                         c.state_buffer.get()};
    octree.bind(params, bound);
    // Some samples per dispatch: llvmpipe stops an invocation's loops
    // past 65535 iterations together (forward.glsl). A sample's loops take
    // at most about 90 (two CDF inversions of at most 24 secant steps and
    // a bisection, the n^2 cells' visibility), the walk over the images'
    // shares at most 10 per image; a cone per sample up to
    // SVO_SHADOW_STEPS more.
    const uint32_t chunk = ctx.settings.luminaire.visibility == LuminaireVisibility::Samples ? 16 : 256;
    double ms = 0;
    auto add = [&ms](double t_ms) { ms = t_ms < 0 || ms < 0 ? -1 : ms + t_ms; };
    for (uint32_t begin = 0; begin < count; begin += band) {
      const uint32_t end = std::min(count, begin + band);
      const uint32_t groups = (end - begin + 63) / 64;
      const uint32_t state_push[8] = {0, 0, 0, 1, begin, end, stride, 0};
      add(c.kernel->dispatch(bound, state_push, groups, stride));
      for (uint32_t first = 0; first < samples; first += chunk) {
        const uint32_t push[8] = {first, std::min(chunk, samples - first), over_ ? 1u : 0u, 0, begin, end, stride, 0};
        add(c.kernel->dispatch(bound, push, groups));
      }
    }
    return ms;
  }
  auto start = std::chrono::steady_clock::now();
  svo::math::NativeLuminaire kernel{octree.native(params), {t.params, t.floats.data()}, lum.data()};
  const auto* g = static_cast<const glm::vec4*>(gbuffer.data());
  const auto* in = static_cast<const glm::vec4*>(base.data());
  auto* colour = static_cast<glm::vec4*>(out.data());
  if (quadrature > 0) {
    // The texel as the estimator's (no samples, so no state), plus the
    // quadrature.
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 64), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t i = r.begin(); i != r.end(); ++i) {
        const svo::math::SvoGBuffer texel = gbuffer_at(g + kGBufferVec4s * i);
        glm::vec4 sum = kernel.svo_luminaire_texel(texel, in[i], i, over_, 0, 0);
        for (uint32_t l = 0; l < ctx.settings.luminaire.luminaires.size(); ++l) {
          sum += glm::vec4(kernel.svo_luminaire_quadrature(texel, l, quadrature), 0.0f);
        }
        colour[i] = sum;
      }
    });
  } else {
    c.state.resize(size_t(band) * stride);
    kernel.state = c.state.data();
    kernel.state_stride = stride;
    for (uint32_t begin = 0; begin < count; begin += band) {
      const uint32_t end = std::min(count, begin + band);
      kernel.state_begin = begin;
      std::fill(c.state.begin(), c.state.end(), glm::uintBitsToFloat(svo::math::NativeLuminaire::kUnmade));
      tbb::parallel_for(tbb::blocked_range<uint32_t>(begin, end, 64), [&](const tbb::blocked_range<uint32_t>& r) {
        for (uint32_t i = r.begin(); i != r.end(); ++i) {
          colour[i] = kernel.svo_luminaire_texel(gbuffer_at(g + kGBufferVec4s * i), in[i], i, over_, 0, samples);
        }
      });
    }
  }
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace svo::render
