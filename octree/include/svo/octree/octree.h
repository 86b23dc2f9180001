// The bricked LoD octree in memory (DESIGN section 7, GigaVoxels style).
//
// Space is a cube [origin, origin + size]^3. Depth 0 is one brick covering
// the cube; depth d has brick_size * 2^d lattice cells per axis; the finest
// depth is depth_count - 1. Voxel values live on lattice points (cell
// corners): a brick of a node stores (brick_size + 1)^3 samples, its faces
// duplicated with its neighbours, so that trilinear interpolation anywhere
// inside the node reads that brick only. The value of a lattice point at depth
// d summarises the surface inside the box of side voxel_size(d) centred on it.
//
// Nodes are stored depth by depth; the children of a node are 8 consecutive
// nodes (a tile) at depth + 1, in x-fastest order. A node without surface
// near it has no brick; a node without children has no tile. Empty and
// uniform regions therefore cost nothing below their parent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace svo::octree {

constexpr uint32_t kNone = 0xFFFFFFFFu;

// What a channel holds. Values are part of the file format: never renumber.
enum class Channel : uint32_t {
  Distance = 1,     // hbar: signed distance to the voxel's mean plane (scene units)
  Normal = 2,       // nbar: unit mean normal
  HeightDev = 3,    // sigma_h: standard deviation of micro-heights (scene units)
  SlopeDev = 4,     // isotropic slope standard deviation sigma_n
  SlopeCov = 5,     // anisotropic slope covariance (xx, yy, xy) in the frame of nbar
  Colour = 6,       // abar: mean colour, linear RGB
  ColourSlope = 7,  // a_s: colour-height correlation, RGB
};

// How a channel is stored. Values are part of the file format: never renumber.
enum class Encoding : uint32_t {
  F32 = 1,            // 1 float
  Oct24 = 2,          // unit vector, octahedral map, 2 x 12 bits
  U8LogRelative = 3,  // value / voxel_size, log2 scale, 16 steps per octave down from 1 (HeightDev)
  U8LogSlope = 4,     // slope deviation, log2 scale, 16 steps per octave down from 16 (SlopeDev)
  Cov3x8 = 5,         // (sx, sy, rho): two U8LogSlope deviations and a correlation in [-1, 1]
  Srgb8 = 6,          // RGB in [0, 1], sRGB transfer, 3 x 8 bits
  Signed8 = 7,        // RGB in [-1, 1], 3 x 8 bits
};

const char* channel_name(Channel channel);     // "distance", "normal", ...
const char* encoding_name(Encoding encoding);  // "f32", "oct24", ...
// Bytes per sample of an encoding; 0 for an unknown value.
uint32_t encoding_bytes(Encoding encoding);
// Whether `encoding` is a valid way to store `channel`.
bool encoding_fits(Channel channel, Encoding encoding);

struct ChannelInfo {
  Channel channel;
  Encoding encoding;
};

// One voxel, decoded. Fields of channels that a file does not store take the
// octree's defaults (zero variances, constant colour, zero correlation).
struct Voxel {
  float hbar = 0;
  glm::vec3 nbar{0, 0, 1};
  float sigma_h = 0;
  glm::vec3 slope_cov{0, 0, 0};  // (var_x, var_y, cov_xy) of slopes in the frame of nbar
  glm::vec3 abar{0, 0, 0};
  glm::vec3 a_s{0, 0, 0};
};

struct Node {
  uint32_t children = kNone;  // index of the first of 8 child nodes, or kNone
  uint32_t brick = kNone;     // index of this node's brick, or kNone (no surface nearby)
};

struct Octree {
  uint32_t brick_size = 8;   // lattice cells per brick edge (power of two, 2..32)
  uint32_t depth_count = 1;  // levels; finest lattice has brick_size << (depth_count - 1) cells
  glm::vec3 origin{0, 0, 0};
  float size = 1;  // side of the cubic domain, scene units

  float sigma_rho2 = 0;                         // micro-BRDF slope variance (Heitz & Neyret 5.5), scene-wide
  glm::vec3 constant_colour{0.8f, 0.8f, 0.8f};  // abar when no Colour channel is stored

  std::vector<ChannelInfo> channels;       // in storage order
  std::vector<uint32_t> depth_first_node;  // size depth_count + 1; nodes of depth d: [first[d], first[d+1])
  std::vector<Node> nodes;                 // node 0 is the root (depth 0)
  uint64_t brick_count = 0;
  std::vector<std::vector<uint8_t>> brick_data;  // per channel: brick_count * samples_per_brick() * bytes

  uint32_t samples_per_edge() const { return brick_size + 1; }
  uint32_t samples_per_brick() const { return samples_per_edge() * samples_per_edge() * samples_per_edge(); }
  uint32_t finest_resolution() const { return brick_size << (depth_count - 1); }
  // Lattice spacing at depth d, scene units.
  float voxel_size(uint32_t depth) const { return size / float(brick_size << depth); }
  int channel_index(Channel channel) const;  // -1 when absent
  // Voxels for reporting: bricks x brick_size^3 (brick faces shared with neighbours are not counted twice).
  uint64_t voxel_count() const { return brick_count * uint64_t(brick_size) * brick_size * brick_size; }
};

// Encodes `v` into sample `sample` of brick `brick` for every channel of
// `tree`; `depth` gives the voxel size for relative encodings.
void encode_voxel(Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth, const Voxel& v);
// The inverse, with the tree's defaults for absent channels.
Voxel decode_voxel(const Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth);

}  // namespace svo::octree
