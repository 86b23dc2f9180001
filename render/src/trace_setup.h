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

static_assert(sizeof(TraceParams) == 28 * 16, "std430 layout: vec4/uvec4 members only");

// Validates `settings` (throws std::invalid_argument naming the problem) and
// fills the parameters of a trace of `tree`.
TraceParams make_trace_params(const octree::Octree& tree, const PackedOctree& packed, const RenderSettings& settings);

// The mask table the tracers use (built once, shared).
const MaskTable& tracer_mask_table();

// tracer_buffer(tracer_mask_table()), built once.
const std::vector<Mask>& tracer_mask_buffer();

// Threads of the native host's parallel loops.
int native_threads();

// Frame statistics from the per-pixel outputs already in `frame`.
void finish_frame_stats(Frame& frame);

}  // namespace svo::render
