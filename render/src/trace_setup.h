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
#include "svo/render/renderer.h"

namespace svo::render {

using TraceParams = svo::math::SvoTraceParams;
static_assert(sizeof(TraceParams) == 28 * 16, "std430 layout: vec4/uvec4 members only");

// The octree as the tracer reads it: nodes as (children, brick) pairs, and
// every brick's channels one after the other in one record of `brick_bytes`,
// so that one index finds all of a voxel. Channel sections start on a word;
// 3-byte samples are padded to 4 bytes, so that no sample straddles a word.
struct PackedOctree {
  std::vector<glm::uvec2> nodes;
  uint32_t brick_bytes = 0;
  uint64_t brick_count = 0;
  std::vector<uint8_t> bricks;  // brick_count * brick_bytes, then 4 bytes of padding
  glm::uvec4 offsets_a{0}, offsets_b{0}, encodings{0};
};

// Each pool brick holds the (B + 1)^3 lattice points of its node, x fastest
// (the tracer interpolates inside a node from its brick alone): the B^3 that
// the file stores plus the upper faces, copied from the neighbouring bricks or
// reconstructed where those are absent (octree::BrickFaces). Expects a valid
// octree (validate_octree); throws std::invalid_argument when it lacks the
// distance channel.
PackedOctree pack_octree(const octree::Octree& tree);

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
