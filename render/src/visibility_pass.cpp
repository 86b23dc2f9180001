#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>

#include "svo/render/octree_access.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "visibility_address.comp.spv.h"
#include "visibility_single.comp.spv.h"
#include "visibility_switch.comp.spv.h"

namespace svo::math {

struct NativeVisibility : render::NativeOctreeReader {
#include "common/visibility_pass.glsl"
};

}  // namespace svo::math

namespace svo::render {

VisibilityPass::VisibilityPass() = default;
VisibilityPass::~VisibilityPass() = default;

double VisibilityPass::run(PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  const TraceParams params = octree.params(ctx.settings);
  ImageMemory& in = ctx.images.read(gbuffer_image());
  ImageMemory& out = ctx.images.write(visibility_image());
  const uint32_t count = ctx.images.width() * ctx.images.height();
  if (ctx.host == Host::Vulkan) {
    if (!kernel_) {
      const auto spirv = octree.pick_kernel(svo_spv_visibility_single_comp, svo_spv_visibility_address_comp,
                                            svo_spv_visibility_switch_comp);
      kernel_ = std::make_unique<vk::ComputeKernel>(*ctx.vulkan, spirv, 2 + octree.binding_count(), 0);
    }
    std::vector<const vk::Buffer*> bound{in.buffer(), out.buffer()};
    octree.bind(params, bound);
    return kernel_->dispatch(bound, nullptr, (count + 63) / 64);
  }
  auto start = std::chrono::steady_clock::now();
  svo::math::NativeVisibility kernel{octree.native(params)};
  const auto* g = static_cast<const glm::vec4*>(in.data());
  auto* visible = static_cast<glm::vec4*>(out.data());
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 256), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i)
      visible[i] = kernel.svo_visibility_texel(gbuffer_at(g + kGBufferVec4s * i));
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::vector<std::string> pass_names() { return {"visibility", "forward", "adaptive"}; }

std::unique_ptr<Pass> make_pass(const std::string& name) {
  if (name == "visibility") return std::make_unique<VisibilityPass>();
  if (name == "forward") return std::make_unique<ForwardPass>();
  if (name == "adaptive") return std::make_unique<AdaptivePass>();
  std::string names;
  for (const auto& n : pass_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown pass '" + name + "' (passes: " + names + ")");
}

}  // namespace svo::render
