// The forward-shading pass (passes.h) on both hosts: the kernel of
// shaders/common/forward.glsl over the G-buffer.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "forward_address.comp.spv.h"
#include "forward_single.comp.spv.h"
#include "forward_switch.comp.spv.h"
#include "shading_cache.h"
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
  ShadingCache shading;
  std::unique_ptr<vk::ComputeKernel> kernel;
};

ForwardPass::ForwardPass(ForwardOutput output) : output_(output), cache_(std::make_unique<Cache>()) {
  if (output_.scale != 1 && output_.scale != 2 && output_.scale != 4) {
    throw std::invalid_argument("the forward pass shades at 1/1, 1/2 or 1/4 of the frame's size, not 1/" +
                                std::to_string(output_.scale));
  }
  if (output_.scale != 1 && !output_.split) {
    throw std::invalid_argument("the forward pass shades at a reduced size only with diffuse and specular apart");
  }
}
ForwardPass::~ForwardPass() = default;

std::vector<ImageDesc> ForwardPass::reads() const {
  if (output_.split) return {gbuffer_image()};
  return {gbuffer_image(), background_image()};
}

std::vector<ImageDesc> ForwardPass::writes() const {
  if (output_.split) return {diffuse_image(output_.scale), specular_image(output_.scale)};
  return {colour_image()};
}

double ForwardPass::run(PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  Cache& c = *cache_;
  ShadingTables& t = c.shading.update(ctx);
  const bool split = output_.split;
  const uint32_t scale = output_.scale;
  ImageMemory& gbuffer = ctx.images.read(gbuffer_image());
  ImageMemory& background = split ? gbuffer : ctx.images.read(background_image());
  ImageMemory& out = ctx.images.write(split ? diffuse_image(scale) : colour_image());
  ImageMemory& specular = split ? ctx.images.write(specular_image(scale)) : out;
  const uint32_t count =
      diffuse_image(scale).width(ctx.images.width()) * diffuse_image(scale).height(ctx.images.height());
  if (ctx.host == Host::Vulkan) {
    if (!c.kernel) {
      const auto spirv =
          octree.pick_kernel(svo_spv_forward_single_comp, svo_spv_forward_address_comp, svo_spv_forward_switch_comp);
      c.kernel =
          std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 6 + octree.binding_count(), 4 * sizeof(uint32_t));
    }
    std::vector<const vk::Buffer*> bound{gbuffer.buffer(),
                                         background.buffer(),
                                         out.buffer(),
                                         c.shading.params_buffer(*ctx.vulkan),
                                         c.shading.tables_buffer(*ctx.vulkan),
                                         specular.buffer()};
    octree.bind(params, bound);
    // Dispatches of a few samples each, so that no invocation's loops pass
    // llvmpipe's limit of 65535 iterations together (forward.glsl); visibility
    // cones march hundreds of steps per sample.
    const uint32_t spp = t.params.sampling.x;
    const ShadingOptions& options = ctx.settings.shading;
    const uint32_t chunk = options.env_shadows || ctx.settings.shadows ? 8 : 64;
    double ms = 0;
    for (uint32_t first = 0; first < spp; first += chunk) {
      const uint32_t push[4] = {first, std::min(chunk, spp - first), split ? 1u : 0u, scale};
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
  auto* spec = static_cast<glm::vec4*>(specular.data());
  const uint32_t spp = t.params.sampling.x;
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 64), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) {
      if (!split) {
        colour[i] = kernel.svo_forward_texel(gbuffer_at(g + kGBufferVec4s * i), back[i], i, 0, spp, glm::vec4(0));
        continue;
      }
      const uint32_t at = kernel.svo_scaled_texel(i, scale);
      const auto f = kernel.svo_forward_split_texel(gbuffer_at(g + kGBufferVec4s * at), at, 0, spp, {});
      colour[i] = f.diffuse;
      spec[i] = f.specular;
    }
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace svo::render
