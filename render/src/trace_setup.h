// What the GPU and the CPU tracers share on the host: the octree packed as
// the tracer reads it, and the parameters of one trace.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

#include "common/shared_math.h"
#include "svo/octree/octree.h"
#include "svo/render/mask_table.h"
#include "svo/render/octree_access.h"
#include "svo/render/renderer.h"

namespace svo::render {

static_assert(sizeof(TraceParams) == 29 * 16, "std430 layout: vec4/uvec4 members only");

// Validates `settings` (throws std::invalid_argument naming the problem) and
// fills the parameters of a trace of `tree`.
TraceParams make_trace_params(const octree::Octree& tree, const PackedOctree& packed, const RenderSettings& settings);

// Pixels [x0, x1) x [y0, y1) of an image.
struct PixelRect {
  uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x0 >= x1 || y0 >= y1; }
};

// The pixels of a trace with `p` whose cones may meet the domain: the
// bounding rectangle of the domain box's projected corners, 2 pixels wider
// on each side (raymarch rays reach 0.56 pixel from the centre). Every pixel
// outside it is the background: its pinhole cone's axis (or each ray of
// raymarch mode) misses the box, the test svo_trace_pixel makes before the
// cone's set-up. The whole image when the eye is inside or beside the box
// (some corners in front of it, some not) and for a lens (a defocused cone
// is wider than the pixel); empty when the box is out of view.
PixelRect domain_pixel_rect(const TraceParams& p);

// Whether some element of a trace with `p` may read a level coarser than
// the finest, so that svo_step blends two levels (SVO_FLAG_LEVEL_BLEND):
// false when the widest cone inside the domain box (a pinhole's, at the
// box's farthest corner) is narrow enough that every element's voxel,
// (r + half length) / sqrt(2), is the finest level's, with 1% to spare.
// Always true for a lens (a defocused cone is wider, and its elements
// longer) and for shadow cones (from the surface, as wide as a light).
bool cones_may_blend(const TraceParams& p);

// The mask table the tracers use (built once, shared).
const MaskTable& tracer_mask_table();

// tracer_buffer(tracer_mask_table()), built once.
const std::vector<Mask>& tracer_mask_buffer();

// Threads of the native host's parallel loops.
int native_threads();

// Frame statistics from the per-pixel outputs already in `frame`.
void finish_frame_stats(Frame& frame);

}  // namespace svo::render
