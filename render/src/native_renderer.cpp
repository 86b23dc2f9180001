// The native host: the tracer of shaders/common/tracer.glsl compiled as C++
// and run over the pixels in parallel. The GLSL expects a few globals and
// accessors (NativeOctreeReader); the body of NativeTracer includes the
// tracer source. The octree is packed once, when the renderer is made.
#include <tbb/blocked_range2d.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstring>

#include "trace_setup.h"

namespace svo::math {

struct NativeTracer : render::NativeOctreeReader {
#include "common/tracer.glsl"
};

}  // namespace svo::math

namespace svo::render {

int native_threads() { return tbb::info::default_concurrency(); }

namespace {

// The cone tracer as the first pass on the native host: writes "colour",
// "background", "gbuffer" (when the settings ask for it) and "steps".
class NativeTracePass : public Pass {
 public:
  explicit NativeTracePass(const OctreeAccess& octree) : octree_(octree) {}

  std::string name() const override { return "trace"; }
  std::vector<ImageDesc> reads() const override { return {}; }
  std::vector<ImageDesc> writes() const override { return trace_images(); }

  double run(PassContext& ctx) override {
    auto start = std::chrono::steady_clock::now();
    const RenderSettings& settings = ctx.settings;
    FrameImages& images = ctx.images;
    svo::math::NativeTracer tracer{octree_.native(octree_.params(settings))};
    auto colour = images.texels<glm::vec4>(images.write(colour_image()));
    auto background = images.texels<glm::vec4>(images.write(background_image()));
    auto steps = images.texels<uint32_t>(images.write(steps_image()));
    auto gbuffer = settings.gbuffer ? images.texels<glm::vec4>(images.write(gbuffer_image())) : std::span<glm::vec4>();
    const uint32_t width = settings.width;
    constexpr uint32_t n4 = svo::math::SVO_GBUFFER_VEC4S;
    tbb::parallel_for(tbb::blocked_range2d<uint32_t>(0, settings.height, 4, 0, width, 32),
                      [&](const tbb::blocked_range2d<uint32_t>& r) {
                        for (uint32_t y = r.rows().begin(); y != r.rows().end(); ++y) {
                          for (uint32_t x = r.cols().begin(); x != r.cols().end(); ++x) {
                            const auto px = tracer.svo_trace_pixel(glm::uvec2(x, y));
                            const size_t i = size_t(y) * width + x;
                            colour[i] = px.colour;
                            background[i] = px.background;
                            steps[i] = px.steps;
                            if (!gbuffer.empty()) {
                              for (uint32_t k = 0; k < n4; ++k)
                                gbuffer[n4 * i + k] = svo::math::svo_gbuffer_pack(px.g, k);
                            }
                          }
                        }
                      });
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

 private:
  const OctreeAccess& octree_;
};

}  // namespace

NativeRenderer::NativeRenderer(const octree::Octree& tree) : Renderer(Host::Native, nullptr, nullptr) {
  set_octree(std::make_unique<OctreeAccess>(tree));
  set_trace(std::make_unique<NativeTracePass>(octree()));
}

}  // namespace svo::render
