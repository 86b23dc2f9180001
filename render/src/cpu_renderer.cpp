// The tracer of shaders/common/tracer.glsl compiled as C++: the reference for
// the GPU path. The GLSL expects a few globals and accessors; here they are
// members of CpuTracer, whose body includes the tracer source.
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstring>

#include "trace_setup.h"

namespace svo::math {

struct CpuTracer {
  SvoTraceParams params;
  const uvec2* nodes;
  const uint8_t* bricks;
  const uvec4* masks;

  uvec2 svo_node(uint index) const { return nodes[index]; }
  uint svo_brick_bytes(uint brick, uint offset) const {
    size_t at = size_t(brick) * params.pool.x + offset;
    uint v;
    std::memcpy(&v, bricks + (at & ~size_t(3)), 4);
    return v >> ((at & 3u) * 8u);
  }
  uvec4 svo_mask(uint cell) const { return masks[cell]; }

#include "common/tracer.glsl"
};

}  // namespace svo::math

namespace svo::render {

Frame render_cpu(const octree::Octree& tree, const RenderSettings& settings) {
  auto start = std::chrono::steady_clock::now();
  const PackedOctree packed = pack_octree(tree);
  svo::math::CpuTracer tracer{make_trace_params(tree, packed, settings), packed.nodes.data(), packed.bricks.data(),
                              tracer_mask_buffer().data()};
  Frame frame;
  frame.width = settings.width;
  frame.height = settings.height;
  const size_t pixels = size_t(frame.width) * frame.height;
  frame.colour.resize(pixels);
  frame.steps.resize(pixels);
  if (settings.gbuffer) frame.gbuffer.resize(pixels);
  tbb::parallel_for(tbb::blocked_range2d<uint32_t>(0, frame.height, 4, 0, frame.width, 32),
                    [&](const tbb::blocked_range2d<uint32_t>& r) {
                      for (uint32_t y = r.rows().begin(); y != r.rows().end(); ++y) {
                        for (uint32_t x = r.cols().begin(); x != r.cols().end(); ++x) {
                          auto px = tracer.svo_trace_pixel(glm::uvec2(x, y));
                          size_t i = size_t(y) * frame.width + x;
                          frame.colour[i] = px.colour;
                          frame.steps[i] = px.steps;
                          if (settings.gbuffer) {
                            frame.gbuffer[i] = {px.g0.x, glm::vec3(px.g0.y, px.g0.z, px.g0.w), glm::vec3(px.g1),
                                                px.g1.w, glm::vec3(px.g2), px.g2.w};
                          }
                        }
                      }
                    });
  finish_frame_stats(frame);
  frame.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

}  // namespace svo::render
