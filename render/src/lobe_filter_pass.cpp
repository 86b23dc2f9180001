// The lobe-aware filter (passes.h, LobeFilterPass) on both hosts: the
// kernels of shaders/common/lobe_filter.glsl, step by step.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cfloat>
#include <chrono>
#include <stdexcept>

#include "filter_address.comp.spv.h"
#include "filter_single.comp.spv.h"
#include "filter_switch.comp.spv.h"
#include "shading_cache.h"
#include "svo/render/octree_access.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"

namespace svo::math {

struct NativeLobeFilter : render::NativeOctreeReader, render::NativeShadingReader {
#include "common/lobe_filter.glsl"
  SvoFilterParams filter_params{};
  const glm::vec4* gbuffer = nullptr;
  const glm::vec4* background = nullptr;
  const glm::vec4* lobes = nullptr;
  const glm::vec4* in_diffuse = nullptr;
  const glm::vec4* in_specular = nullptr;
  SvoGBuffer svo_filter_gbuffer(uint32_t t) { return render::gbuffer_at(gbuffer + kGBufferVec4s * t); }
  SvoPixelLobe svo_filter_lobe(uint32_t t) {
    const glm::vec4* l = lobes + SVO_LOBE_VEC4S * t;
    return svo_lobe_unpack(l[0], l[1], l[2], l[3], l[4], l[5]);
  }
  glm::vec4 svo_filter_background(uint32_t t) const { return background[t]; }
  glm::vec4 svo_filter_diffuse(uint32_t t) const { return in_diffuse[t]; }
  glm::vec4 svo_filter_specular(uint32_t t) const { return in_specular[t]; }
  static constexpr uint32_t kGBufferVec4s = render::kGBufferVec4s;
};

}  // namespace svo::math

namespace svo::render {

using Kernel = svo::math::NativeLobeFilter;

const char* filter_weight_name(FilterWeight weight) {
  switch (weight) {
    case FilterWeight::None:
      return "none";
    case FilterWeight::Normal:
      return "normal";
    case FilterWeight::Lobe:
      return "lobe";
    case FilterWeight::Mixture:
      return "mixture";
    case FilterWeight::Asg:
      return "asg";
  }
  return "?";
}

FilterWeight parse_filter_weight(const std::string& name) {
  for (auto w :
       {FilterWeight::None, FilterWeight::Normal, FilterWeight::Lobe, FilterWeight::Mixture, FilterWeight::Asg})
    if (name == filter_weight_name(w)) return w;
  throw std::invalid_argument("unknown filter weight '" + name +
                              "' (none, normal: Eq. 4, lobe: Eq. 12, mixture: Eq. 11, asg: Eq. 13)");
}

namespace {

ImageDesc rows_diffuse_image() { return {"filter_rows_diffuse", TexelFormat::Rgba32f}; }
ImageDesc rows_specular_image() { return {"filter_rows_specular", TexelFormat::Rgba32f}; }

svo::math::SvoFilterParams filter_params(const FilterOptions& o, uint32_t scale, uint32_t step) {
  svo::math::SvoFilterParams p{};
  const float kappa = o.kappa >= 0 ? o.kappa : scale == 1 ? FLT_MAX : 100.0f;
  p.mode = glm::uvec4(uint32_t(o.weight), o.radius, scale, step);
  p.weights = glm::vec4(o.beta, o.sigma_n2, o.sigma_z, kappa);
  p.adapt = glm::vec4(o.recompute, std::max(0.5f * float(o.radius), 0.5f), o.voxel_slopes ? 0.0f : 1.0f,
                      svo::math::svo_filter_diffuse_variance(o.beta, kappa));
  p.screen = glm::vec4(svo::math::svo_filter_screen_sum(int(o.radius), p.adapt.y), 0, 0, 0);
  return p;
}

}  // namespace

struct LobeFilterPass::State {
  ShadingCache shading;
  std::vector<glm::vec4> lobes;  // native host: SVO_LOBE_VEC4S per texel
  std::unique_ptr<vk::Buffer> lobe_buffer, params[4];
  std::unique_ptr<vk::ComputeKernel> kernels[4];  // per step
};

LobeFilterPass::LobeFilterPass(uint32_t scale) : scale_(scale), state_(std::make_unique<State>()) {
  if (scale != 1 && scale != 2 && scale != 4) {
    throw std::invalid_argument("the lobe-aware filter upsamples from 1/2 or 1/4, not 1/" + std::to_string(scale));
  }
}
LobeFilterPass::~LobeFilterPass() = default;

std::vector<ImageDesc> LobeFilterPass::reads() const {
  return {gbuffer_image(), background_image(), diffuse_image(scale_), specular_image(scale_)};
}

std::vector<ImageDesc> LobeFilterPass::writes() const {
  if (scale_ == 1) return {rows_diffuse_image(), rows_specular_image(), colour_image(), weight_image()};
  return {colour_image(), weight_image()};
}

double LobeFilterPass::run(PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  State& s = *state_;
  ShadingTables& t = s.shading.update(ctx);
  ImageMemory& gbuffer = ctx.images.read(gbuffer_image());
  ImageMemory& background = ctx.images.read(background_image());
  ImageMemory& diffuse = ctx.images.read(diffuse_image(scale_));
  ImageMemory& specular = ctx.images.read(specular_image(scale_));
  ImageMemory* rows_d = scale_ == 1 ? &ctx.images.write(rows_diffuse_image()) : nullptr;
  ImageMemory* rows_s = scale_ == 1 ? &ctx.images.write(rows_specular_image()) : nullptr;
  ImageMemory& colour = ctx.images.write(colour_image());
  ImageMemory& weight = ctx.images.write(weight_image());
  const uint32_t count = ctx.images.width() * ctx.images.height();
  // The steps: lobes, then rows and columns (filtering) or upsample.
  std::vector<uint32_t> steps{svo::math::SVO_FILTER_STEP_LOBES};
  if (scale_ == 1) {
    steps.push_back(svo::math::SVO_FILTER_STEP_ROWS);
    steps.push_back(svo::math::SVO_FILTER_STEP_COLUMNS);
  } else {
    steps.push_back(svo::math::SVO_FILTER_STEP_UPSAMPLE);
  }
  if (ctx.host == Host::Vulkan) {
    vk::Context& vc = *ctx.vulkan;
    const std::size_t lobe_bytes = std::size_t(count) * svo::math::SVO_LOBE_VEC4S * sizeof(glm::vec4);
    if (!s.lobe_buffer || s.lobe_buffer->size() < lobe_bytes)
      s.lobe_buffer = std::make_unique<vk::Buffer>(vc, lobe_bytes);
    double ms = 0;
    for (uint32_t step : steps) {
      if (!s.kernels[step]) {
        const auto spirv =
            octree.pick_kernel(svo_spv_filter_single_comp, svo_spv_filter_address_comp, svo_spv_filter_switch_comp);
        const uint32_t spec[3] = {svo::math::SVO_SPEC_ANY, svo::math::SVO_SPEC_ANY, step};
        s.kernels[step] = std::make_unique<vk::ComputeKernel>(vc, spirv, 10 + octree.binding_count(), 0, spec);
        s.params[step] = std::make_unique<vk::Buffer>(vc, sizeof(svo::math::SvoFilterParams));
      }
      const svo::math::SvoFilterParams fp = filter_params(ctx.settings.filter, scale_, step);
      std::memcpy(s.params[step]->data(), &fp, sizeof fp);
      const bool columns = step == svo::math::SVO_FILTER_STEP_COLUMNS;
      const bool rows = step == svo::math::SVO_FILTER_STEP_ROWS;
      std::vector<const vk::Buffer*> bound{gbuffer.buffer(),
                                           background.buffer(),
                                           columns ? rows_d->buffer() : diffuse.buffer(),
                                           columns ? rows_s->buffer() : specular.buffer(),
                                           s.lobe_buffer.get(),
                                           rows ? rows_d->buffer() : colour.buffer(),
                                           rows ? rows_s->buffer() : weight.buffer(),
                                           s.shading.params_buffer(vc),
                                           s.shading.tables_buffer(vc),
                                           s.params[step].get()};
      octree.bind(params, bound);
      const double t_ms = s.kernels[step]->dispatch(bound, nullptr, (count + 63) / 64);
      ms = t_ms < 0 || ms < 0 ? -1 : ms + t_ms;
    }
    return ms;
  }
  auto start = std::chrono::steady_clock::now();
  Kernel kernel{octree.native(params), {t.params, t.floats.data()}};
  s.lobes.resize(std::size_t(count) * svo::math::SVO_LOBE_VEC4S);
  kernel.gbuffer = static_cast<const glm::vec4*>(gbuffer.data());
  kernel.background = static_cast<const glm::vec4*>(background.data());
  kernel.lobes = s.lobes.data();
  kernel.in_diffuse = static_cast<const glm::vec4*>(diffuse.data());
  kernel.in_specular = static_cast<const glm::vec4*>(specular.data());
  auto* out_a = static_cast<glm::vec4*>(colour.data());
  auto* out_b = static_cast<glm::vec4*>(weight.data());
  for (uint32_t step : steps) {
    kernel.filter_params = filter_params(ctx.settings.filter, scale_, step);
    if (step == svo::math::SVO_FILTER_STEP_COLUMNS) {
      kernel.in_diffuse = static_cast<const glm::vec4*>(rows_d->data());
      kernel.in_specular = static_cast<const glm::vec4*>(rows_s->data());
    }
    glm::vec4* a = step == svo::math::SVO_FILTER_STEP_ROWS ? static_cast<glm::vec4*>(rows_d->data()) : out_a;
    glm::vec4* b = step == svo::math::SVO_FILTER_STEP_ROWS ? static_cast<glm::vec4*>(rows_s->data()) : out_b;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 256), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t i = r.begin(); i != r.end(); ++i) {
        if (step == svo::math::SVO_FILTER_STEP_LOBES) {
          const svo::math::SvoPixelLobe l = kernel.svo_pixel_lobe(kernel.svo_filter_gbuffer(i));
          for (uint32_t k = 0; k < svo::math::SVO_LOBE_VEC4S; ++k)
            s.lobes[std::size_t(i) * svo::math::SVO_LOBE_VEC4S + k] = svo::math::svo_lobe_pack(l, k);
          continue;
        }
        const Kernel::SvoFilterOut o = step == svo::math::SVO_FILTER_STEP_ROWS ? kernel.svo_filter_rows_texel(i)
                                       : step == svo::math::SVO_FILTER_STEP_COLUMNS
                                           ? kernel.svo_filter_columns_texel(i)
                                           : kernel.svo_filter_upsample_texel(i);
        a[i] = o.diffuse;
        b[i] = o.specular;
      }
    });
  }
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace svo::render
