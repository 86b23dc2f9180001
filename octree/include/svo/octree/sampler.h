// Reading the octree on the CPU: lattice values by depth and index (for the
// tests and the CPU reference of the renderer), and a node's brick with its
// upper faces rebuilt from its neighbours (for the renderer's pools).
//
// Every function here expects a tree that satisfies validate_octree
// (svo_file.h): a loaded file or the voxelizer's output.
#pragma once

#include <glm/vec3.hpp>
#include <optional>
#include <vector>

#include "svo/octree/octree.h"

namespace svo::octree {

// The node at `depth` whose brick owns lattice point `p` (the brick of
// integer coordinates p / brick_size), found by descending from the root;
// kNone when p lies outside [0, brick_size << depth) on some axis or the
// descent ends early (no surface there). The node returned may lack a brick.
uint32_t find_node(const Octree& tree, uint32_t depth, glm::ivec3 p);

// Where the value of one lattice point comes from (octree.h states the rule).
struct LatticeSource {
  uint32_t brick = kNone;  // brick holding the stored sample q; kNone: p has no value
  uint64_t sample = 0;     // pool index of q (Octree::brick_sample, or shell_sample on the domain boundary)
  uint32_t axes = 0;       // extrapolation axes S (x = 1, y = 2, z = 4); 0: p itself is stored, q = p
  uint32_t depth = 0;      // depth of p (and of the brick)
};

// The smallest distance magnitude of a reconstructed lattice point at
// `depth` (octree.h): max(voxel_size(depth) / 2 - h, h / 2), h the finest
// voxel size, scene units.
float reconstruction_floor(const Octree& tree, uint32_t depth);

// The distance reconstruction of octree.h, in two parts, for the source
// (voxelizer) and the reader alike. A point whose owner is absent, with S
// its axes on the upper faces (bits x = 1, y = 2, z = 4) and q = p - e_S:
// - extrapolation_weight(S, t): the weight of the stored distance at
//   q - e_t (t a subset of S) in the extrapolation, the product over the
//   axes of S of 2 (a not in t) or -1 (a in t); 0 when t is not in S.
// - reconstructed_distance: what the rule keeps of the extrapolation, given
//   the distance at q, the floor and the depth's voxel size.
double extrapolation_weight(uint32_t axes, uint32_t t);
float reconstructed_distance(double extrapolated, float nearest, float floor, float voxel);

// The source of lattice point `p` (0 <= p <= brick_size << depth per axis) at
// `depth`: the owner's stored sample; for a point of a stored brick's closed
// range whose owner is absent, a shell sample on the domain's upper boundary
// and the canonical reconstruction of octree.h elsewhere; brick = kNone
// otherwise (p in no stored brick's closed range, or outside).
LatticeSource lattice_source(const Octree& tree, uint32_t depth, glm::ivec3 p);

// Channel c's encoded bytes (encoding_bytes of its encoding) of the value at
// `source` (brick != kNone): the stored bytes, or for the distance with
// source.axes != 0 the float reconstructed as octree.h says (extrapolated,
// then kept at least reconstruction_floor away from zero).
void source_bytes(const Octree& tree, size_t c, const LatticeSource& source, uint8_t* out);

// Decoded value of lattice point `p` at `depth` (stored or reconstructed, as
// lattice_source), or nullopt when it has none.
std::optional<Voxel> lattice_voxel(const Octree& tree, uint32_t depth, glm::ivec3 p);

// World position of lattice point p at depth.
glm::vec3 lattice_position(const Octree& tree, uint32_t depth, glm::ivec3 p);

// Node coordinates and the (B + 1)^3 blocks of bricks with their faces.
// Construction is one pass over the nodes (O(nodes) time and 16 bytes per
// node); queries then descend from the root for the 26 neighbours of a node.
// Holds a reference to `tree`, which must outlive it and not change.
class BrickFaces {
 public:
  explicit BrickFaces(const Octree& tree);

  const Octree& tree() const { return tree_; }
  uint32_t depth(uint32_t node) const { return depth_.at(node); }
  // Integer coordinates of `node` at its depth: its brick owns lattice points
  // coords * B + [0, B)^3 and interpolates over coords * B + [0, B]^3.
  glm::ivec3 coords(uint32_t node) const { return coords_.at(node); }

  // The sources of the (B + 1)^3 lattice points of `node`'s brick, x
  // fastest; each has brick != kNone. @throw std::invalid_argument when
  // `node` is out of range or has no brick.
  void plan(uint32_t node, std::vector<LatticeSource>& out) const;

  // Channel c of `node`'s brick with its faces: the (B + 1)^3 encoded
  // samples of plan(node), sample i at out + i * stride (stride >=
  // encoding_bytes; the bytes between samples are left as they are).
  void channel_with_faces(uint32_t node, size_t c, uint8_t* out, uint32_t stride) const;

  // The same block decoded, every channel.
  void brick_with_faces(uint32_t node, std::vector<Voxel>& out) const;

 private:
  const Octree& tree_;
  std::vector<glm::ivec3> coords_;
  std::vector<uint8_t> depth_;
};

// BrickFaces(tree).brick_with_faces(node, out): O(nodes) per call, for tests
// and one-off reads; keep a BrickFaces for many nodes.
void brick_with_faces(const Octree& tree, uint32_t node, std::vector<Voxel>& out);

}  // namespace svo::octree
