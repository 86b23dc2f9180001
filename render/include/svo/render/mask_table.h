// Precomputed A-buffer masks of cone elements (Heitz & Neyret section 5.4):
// 128 Poisson-disc points in the unit disk of the pixel footprint, and for
// each cell of a (theta, v) grid the bits of the points covered by the
// half-plane w . (cos theta, sin theta) <= v. The renderer fetches the mask in
// nearest mode and combines masks along the cone A-buffer style.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace svo::render {

constexpr int kMaskBits = 128;

// `count` points in the unit disk, at least `min_distance` apart, by dart
// throwing with a shrinking radius from a fixed seed (deterministic).
std::vector<glm::vec2> poisson_disk(int count, uint32_t seed = 1);

// A 128-bit mask as four 32-bit words (bit i of the mask: word i / 32, bit i % 32).
using Mask = glm::uvec4;

struct MaskTable {
  int theta_bins = 256;  // theta in [-pi, pi), bin centres
  int v_bins = 256;      // v in (-1, 1), bin centres
  std::vector<glm::vec2> points;  // kMaskBits points
  std::vector<Mask> masks;        // theta-major: masks[theta * v_bins + v]

  const Mask& at(int theta, int v) const { return masks[size_t(theta) * size_t(v_bins) + size_t(v)]; }
};

// Builds the table over `points` (kMaskBits of them).
MaskTable build_mask_table(const std::vector<glm::vec2>& points, int theta_bins = 256, int v_bins = 256);

// The mask for (theta, v) as the renderer looks it up: all bits for v >= 1,
// none for v <= -1, else the nearest table cell.
Mask lookup_mask(const MaskTable& table, float theta, float v);

int popcount(const Mask& m);

// The table as the tracers read it (tracer.glsl svo_mask; masks.glsl
// states the layout): its masks, then its points two to an entry (the bit
// patterns of x, y, x, y), then the sums over all points of x, y, x^2, y^2
// and of x y (one entry and the first word of the next), then three decode
// tables of 256 floats, four to an entry, indexed by the byte: Srgb8 to
// linear (svo_decode_srgb8), U8LogRelative of scale 1
// (svo_decode_u8_log_relative(byte, 1)) and Signed8 (svo_decode_s8).
std::vector<Mask> tracer_buffer(const MaskTable& table);

}  // namespace svo::render
