// The forward-shading pass (passes.h) on both hosts: the kernel of
// shaders/common/forward.glsl over the G-buffer.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "forward_address.comp.spv.h"
#include "forward_single.comp.spv.h"
#include "forward_switch.comp.spv.h"
#include "svo/render/octree_access.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"

namespace svo::math {

struct NativeForward : render::NativeOctreeReader, render::NativeShadingReader {
#include "common/forward.glsl"
};

}  // namespace svo::math

namespace svo::render {

struct ForwardPass::Cache {
  // What the tables were built from.
  const Environment* environment = nullptr;
  const Material* material = nullptr;
  Material default_material;
  const octree::Octree* scene = nullptr;  // whose materials scene_materials holds
  std::vector<std::shared_ptr<const Material>> scene_materials;
  bool valid = false;
  ShadingTables tables;
  std::unique_ptr<vk::ComputeKernel> kernel;
  std::unique_ptr<vk::Buffer> shade, floats;
};

ForwardPass::ForwardPass() : cache_(std::make_unique<Cache>()) {}
ForwardPass::~ForwardPass() = default;

double ForwardPass::run(PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  ShadingOptions options = ctx.settings.shading;
  Cache& c = *cache_;
  // Without --material: the octree's own materials, parsed once per octree.
  if (c.scene != &octree.tree()) {
    c.scene_materials = parse_scene_materials(octree.tree().materials, "the octree");
    c.scene = &octree.tree();
    c.valid = false;
  }
  if (options.scene_materials.empty()) options.scene_materials = c.scene_materials;
  // Nothing at all: the built-in one, the Beckmann lobe of --specular
  // with the file's (or --roughness's) micro-BRDF slope variance.
  const Material fallback = builtin_material(ctx.settings.specular, params.material.x);
  const bool same = c.valid && c.environment == options.environment.get() && c.material == options.material.get() &&
                    (options.material || !c.scene_materials.empty() ||
                     (c.default_material.f0 == fallback.f0 && c.default_material.roughness == fallback.roughness));
  if (!same) {
    c.tables = build_shading_tables(options, fallback, ctx.settings.shadows);
    c.environment = options.environment.get();
    c.material = options.material.get();
    c.default_material = fallback;
    c.valid = true;
    c.floats.reset();
  }
  // The parameters that change without new tables.
  ShadingTables& t = c.tables;
  t.params.env_xform = glm::vec4(glm::radians(options.env_rotate_deg), options.env_scale, 0, 0);
  t.params.sampling = glm::uvec4(std::max(options.spp, 1u), options.seed,
                                 (options.env_shadows ? svo::math::SVO_SHADE_ENV_SHADOWS : 0u) |
                                     (ctx.settings.shadows ? svo::math::SVO_SHADE_LIGHT_SHADOWS : 0u),
                                 t.params.sampling.w);
  ImageMemory& gbuffer = ctx.images.read(gbuffer_image());
  ImageMemory& background = ctx.images.read(background_image());
  ImageMemory& out = ctx.images.write(colour_image());
  const uint32_t count = ctx.images.width() * ctx.images.height();
  if (ctx.host == Host::Vulkan) {
    if (!c.kernel) {
      const auto spirv =
          octree.pick_kernel(svo_spv_forward_single_comp, svo_spv_forward_address_comp, svo_spv_forward_switch_comp);
      c.kernel =
          std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 5 + octree.binding_count(), 2 * sizeof(uint32_t));
      c.shade = std::make_unique<vk::Buffer>(*ctx.vulkan, sizeof(svo::math::SvoShadeParams));
    }
    if (!c.floats) {
      c.floats = std::make_unique<vk::Buffer>(*ctx.vulkan, t.floats.size() * sizeof(float));
      std::memcpy(c.floats->data(), t.floats.data(), t.floats.size() * sizeof(float));
    }
    std::memcpy(c.shade->data(), &t.params, sizeof(t.params));
    std::vector<const vk::Buffer*> bound{gbuffer.buffer(), background.buffer(), out.buffer(), c.shade.get(),
                                         c.floats.get()};
    octree.bind(params, bound);
    // Dispatches of a few samples each, so that no invocation's loops pass
    // llvmpipe's limit of 65535 iterations together (forward.glsl); visibility
    // cones march hundreds of steps per sample.
    const uint32_t spp = t.params.sampling.x;
    const uint32_t chunk = options.env_shadows || ctx.settings.shadows ? 8 : 64;
    double ms = 0;
    for (uint32_t first = 0; first < spp; first += chunk) {
      const uint32_t push[2] = {first, std::min(chunk, spp - first)};
      const double t_ms = c.kernel->dispatch(bound, push, (count + 63) / 64);
      ms = t_ms < 0 || ms < 0 ? -1 : ms + t_ms;
    }
    return ms;
  }
  auto start = std::chrono::steady_clock::now();
  svo::math::NativeForward kernel{octree.native(params), {t.params, t.floats.data()}};
  const auto* g = static_cast<const glm::vec4*>(gbuffer.data());
  const auto* back = static_cast<const glm::vec4*>(background.data());
  auto* colour = static_cast<glm::vec4*>(out.data());
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 64), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i)
      colour[i] =
          kernel.svo_forward_texel(gbuffer_at(g + kGBufferVec4s * i), back[i], i, 0, t.params.sampling.x, glm::vec4(0));
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace svo::render
