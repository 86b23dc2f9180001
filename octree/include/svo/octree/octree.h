// The bricked LoD octree in memory (DESIGN section 7, GigaVoxels style).
//
// Space is a cube [origin, origin + size]^3. Depth 0 is one brick covering
// the cube; depth d has brick_size * 2^d lattice cells per axis; the finest
// depth is depth_count - 1. Voxel values live on lattice points (cell
// corners). The brick of node c (integer coordinates at depth d) stores the
// brick_size^3 lattice points c * B + i, i in [0, B) per axis, x fastest:
// every lattice point is stored once, by the brick that owns it (floor(p / B)).
// The value of a lattice point at depth d summarises the surface inside the
// box of side voxel_size(d) centred on it.
//
// Trilinear interpolation inside a node needs the node's (B + 1)^3 points:
// its own block plus its upper faces, edges and corner, which belong to the
// neighbours c + o, o in {0, 1}^3 (sampler.h: BrickFaces). A point whose
// owner has no brick takes its value, canonically (the same from every brick
// that needs it), from a candidate brick: the bricks owner - S for the
// non-empty S within A(p), A(p) = the axes a where p[a] is a positive
// multiple of B (p lies on a brick face along a), tried by |S| (1, 2, 3),
// then by the bits of S (x = 1, y = 2, z = 4): x, y, z, xy, xz, yz, xyz. The
// first that exists is the source; p lies on its upper face along every axis
// of S. A stored brick holds p in its closed range, so it is always a
// candidate: every point of a stored brick's (B + 1)^3 block has a value.
//
// Shells: points on the domain's upper boundary (p[a] = B << d) have no
// owner inside the domain, yet at coarse depths their footprint may hold the
// surface. Every brick whose node lies on that boundary (some coordinate c[a]
// = 2^d - 1) therefore also stores its shell: the 3B^2 + 3B + 1 points of its
// (B + 1)^3 block with some local coordinate equal to B (shell_index gives
// their order). Those bricks are numbered first, 0 .. shell_count - 1, so
// that shell b belongs to brick b; a point on the domain boundary takes the
// source's shell sample. Shell samples are read only there.
//
// Elsewhere the source's value is reconstructed, where no surface is near
// p (the voxelizer stores every brick whose closed range holds a surface
// point, so an absent owner means an empty footprint). With q = p - e_S, the
// source's stored point nearest to p:
//   - Distance: linear extrapolation along each axis of S from the source's
//     two inner samples, 2 hbar(q) - hbar(q - e_a), applied per axis (for an
//     edge or a corner, the product of the per-axis stencils: the separable
//     bilinear/trilinear extrapolation), in double, rounded once to float.
//     Then kept off the surface: at least reconstruction_floor(depth) =
//     max(voxel / 2 - h, h / 2) from zero (h the finest voxel: an empty
//     footprint is at least that far from the surface), on q's side when the
//     extrapolation falls short of it; and on q's side, no closer than q, if
//     it crossed zero while |hbar(q)| >= sqrt(3) / 2 voxel (then q's box
//     holds no surface either, and a surface between q and p is unlikely).
//   - Every other channel: the encoded bytes of the nearest stored sample q.
// On the built-in scenes this puts the reconstructed distance on the
// surface's side at all but a few in 10^4 points (docs/RESULTS.md). At the
// finest depth the voxelizer leaves none: where the rule would take q's
// side against the extrapolation, or from one short of the floor, it
// stores the owner's brick instead (voxelizer/src/build.cpp).
//
// Nodes are stored depth by depth; the children of a node are 8 consecutive
// nodes (a tile) at depth + 1, in x-fastest order. A node without surface
// near it has no brick; a node without children has no tile. Empty and
// uniform regions therefore cost nothing below their parent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
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
  Material = 8,     // the dominant material (index into Octree::materials) by covered area, and its share
  ShadingNormal = 9,  // the unit normal shading reads where it is not nbar: the face's at an open edge's cap
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
  MaterialShare8 = 8,  // material index (8 bits), its share of the covered area (8 bits, share * 255)
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
  uint32_t material = 0;      // dominant material, an index into Octree::materials
  float material_share = 1;   // its share of the footprint's surface area, in [0, 1]
  // The normal shading reads (Channel::ShadingNormal), where it is not nbar:
  // zero stands for nbar (encoded as nbar; decoded as stored).
  glm::vec3 n_shading{0, 0, 0};
};

// Most materials an octree carries: a material index is 8 bits.
constexpr uint32_t kMaxMaterials = 255;
// Longest material description, bytes of JSON text.
constexpr uint32_t kMaxMaterialBytes = 65536;
// Longest provenance text (Octree::source), bytes.
constexpr uint32_t kMaxSourceBytes = 65536;

struct Node {
  uint32_t children = kNone;  // index of the first of 8 child nodes, or kNone
  uint32_t brick = kNone;     // index of this node's brick, or kNone (no surface nearby)
};

// Procedural detail octaves below the stored resolution (issue 6; the math
// is shaders/common/detail.glsl): octave k adds amplitude gain^k times
// gradient noise of wavelength wavelength 2^-k to the height along the
// normal, and colour_slope times that height to the colour. The octaves the
// finest level cannot draw are folded into every level's statistics; the
// renderer draws them where its footprint is finer.
struct Detail {
  uint32_t octaves = 0;  // 0: none
  uint32_t seed = 0;
  float amplitude = 0;   // of octave 0, scene units
  float wavelength = 0;  // of octave 0, scene units
  float gain = 0.5f;     // amplitude ratio of consecutive octaves, (0, 1]
  glm::vec3 colour_slope{0, 0, 0};  // linear RGB per scene unit of detail height
};

struct Octree {
  uint32_t brick_size = 8;   // lattice cells per brick edge (power of two, 2..32)
  uint32_t depth_count = 1;  // levels; finest lattice has brick_size << (depth_count - 1) cells
  glm::vec3 origin{0, 0, 0};
  float size = 1;  // side of the cubic domain, scene units

  float sigma_rho2 = 0;                         // micro-BRDF slope variance (Heitz & Neyret 5.5), scene-wide
  glm::vec3 constant_colour{0.8f, 0.8f, 0.8f};  // abar when no Colour channel is stored
  Detail detail;                                // octaves = 0: none
  // The scene's materials as JSON texts (render::parse_material reads them;
  // DESIGN 10.2), empty when the scene has none of its own. With two or
  // more, the Material channel says which one each voxel shows.
  std::vector<std::string> materials;
  // Where the octree came from, as JSON text (the voxelizer's input, its
  // settings, what it decided about the surface: `svo info` shows it);
  // empty: not recorded. At most kMaxSourceBytes, no NUL byte.
  std::string source;

  std::vector<ChannelInfo> channels;       // in storage order
  std::vector<uint32_t> depth_first_node;  // size depth_count + 1; nodes of depth d: [first[d], first[d+1])
  std::vector<Node> nodes;                 // node 0 is the root (depth 0)
  uint64_t brick_count = 0;
  uint64_t shell_count = 0;  // bricks on the domain's upper boundary: bricks 0 .. shell_count - 1
  // Per channel, in samples of encoding_bytes each: brick_count *
  // samples_per_brick() brick samples, then shell_count * shell_samples()
  // shell samples (shell b after shell b - 1).
  std::vector<std::vector<uint8_t>> brick_data;

  // Stored samples per brick edge: brick_size (faces are not duplicated).
  uint32_t samples_per_edge() const { return brick_size; }
  uint32_t samples_per_brick() const { return samples_per_edge() * samples_per_edge() * samples_per_edge(); }
  // Lattice points per edge of a node's brick with its upper faces: brick_size + 1.
  uint32_t samples_per_edge_with_faces() const { return brick_size + 1; }
  // Points of a shell: (B + 1)^3 - B^3.
  uint32_t shell_samples() const { return 3 * brick_size * brick_size + 3 * brick_size + 1; }
  // Samples per channel pool: brick samples and shells.
  uint64_t pool_samples() const { return brick_count * samples_per_brick() + shell_count * shell_samples(); }
  // Index in a pool (in samples) of sample i of brick b, and of point l (some
  // l[a] = B) of the shell of brick b < shell_count.
  uint64_t brick_sample(uint64_t b, uint32_t i) const { return b * samples_per_brick() + i; }
  uint64_t shell_sample(uint64_t b, glm::ivec3 l) const;
  uint32_t finest_resolution() const { return brick_size << (depth_count - 1); }
  // Lattice spacing at depth d, scene units.
  float voxel_size(uint32_t depth) const { return size / float(brick_size << depth); }
  int channel_index(Channel channel) const;  // -1 when absent
  // Voxels for reporting: bricks x brick_size^3 (the samples stored).
  uint64_t voxel_count() const { return brick_count * uint64_t(brick_size) * brick_size * brick_size; }
};

// Whether the node of coordinates `c` at `depth` lies on the domain's upper
// boundary (some c[a] = 2^depth - 1): its brick, if any, has a shell.
bool on_upper_boundary(uint32_t depth, glm::ivec3 c);

// Order of point l of a (B + 1)^3 block within the shell (some l[a] = B):
// the shell's points in x-fastest order of the block. In [0, 3B^2 + 3B + 1).
uint32_t shell_index(uint32_t brick_size, glm::ivec3 l);

// Encodes `v` into sample `sample` of brick `brick` for every channel of
// `tree`; `depth` gives the voxel size for relative encodings.
void encode_voxel(Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth, const Voxel& v);
// The same at any pool sample (brick_sample or shell_sample).
void encode_pool_voxel(Octree& tree, uint64_t pool_sample, uint32_t depth, const Voxel& v);
// The inverse, with the tree's defaults for absent channels.
Voxel decode_voxel(const Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth);
// The same from encoded bytes: samples[c] points at one encoded sample of
// channel c (samples.size() == tree.channels.size()).
Voxel decode_sample(const Octree& tree, std::span<const uint8_t* const> samples, uint32_t depth);

}  // namespace svo::octree
