// The luminaire pass (passes.h) on both hosts: the kernel of
// shaders/common/luminaire.glsl over the G-buffer.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

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
  float svo_lum_table(uint32_t i) const { return lum_tables[i]; }
#include "common/luminaire.glsl"
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

LuminairePass::LuminairePass(bool over_colour) : over_(over_colour), cache_(std::make_unique<Cache>()) {}
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
  if (ctx.host == Host::Vulkan) {
    if (!c.kernel) {
      const auto spirv = octree.pick_kernel(svo_spv_luminaire_single_comp, svo_spv_luminaire_address_comp,
                                            svo_spv_luminaire_switch_comp);
      c.kernel =
          std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 6 + octree.binding_count(), 4 * sizeof(uint32_t));
    }
    if (!c.tables_buffer) {
      c.tables_buffer = std::make_unique<vk::Buffer>(*ctx.vulkan, lum.size() * sizeof(float));
      std::memcpy(c.tables_buffer->data(), lum.data(), lum.size() * sizeof(float));
    }
    std::vector<const vk::Buffer*> bound{gbuffer.buffer(),
                                         over_ ? gbuffer.buffer() : base.buffer(),
                                         out.buffer(),
                                         c.shading.params_buffer(*ctx.vulkan),
                                         c.shading.tables_buffer(*ctx.vulkan),
                                         c.tables_buffer.get()};
    octree.bind(params, bound);
    // A few samples per dispatch: llvmpipe stops an invocation's loops
    // past 65535 iterations together (forward.glsl), and every sample
    // searches two CDFs and may march a cone.
    const uint32_t chunk = ctx.settings.luminaire.visibility == LuminaireVisibility::None ? 64 : 16;
    double ms = 0;
    for (uint32_t first = 0; first < samples; first += chunk) {
      const uint32_t push[4] = {first, std::min(chunk, samples - first), over_ ? 1u : 0u, 0u};
      const double t_ms = c.kernel->dispatch(bound, push, (count + 63) / 64);
      ms = t_ms < 0 || ms < 0 ? -1 : ms + t_ms;
    }
    return ms;
  }
  auto start = std::chrono::steady_clock::now();
  svo::math::NativeLuminaire kernel{octree.native(params), {t.params, t.floats.data()}, lum.data()};
  const auto* g = static_cast<const glm::vec4*>(gbuffer.data());
  const auto* in = static_cast<const glm::vec4*>(base.data());
  auto* colour = static_cast<glm::vec4*>(out.data());
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 64), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) {
      const svo::math::SvoGBuffer texel = gbuffer_at(g + kGBufferVec4s * i);
      if (quadrature == 0) {
        colour[i] = kernel.svo_luminaire_texel(texel, in[i], i, over_, 0, samples);
        continue;
      }
      // The texel as the estimator's (no samples), plus the quadrature.
      glm::vec4 sum = kernel.svo_luminaire_texel(texel, in[i], i, over_, 0, 0);
      for (uint32_t l = 0; l < ctx.settings.luminaire.luminaires.size(); ++l) {
        sum += glm::vec4(kernel.svo_luminaire_quadrature(texel, l, quadrature), 0.0f);
      }
      colour[i] = sum;
    }
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace svo::render
