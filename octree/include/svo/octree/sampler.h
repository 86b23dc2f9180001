// Reading the octree on the CPU: lattice values by depth and index (for the
// tests and the CPU reference of the renderer).
#pragma once

#include <glm/vec3.hpp>
#include <optional>

#include "svo/octree/octree.h"

namespace svo::octree {

// The node at `depth` whose brick covers lattice point `p` (0 <= p <=
// brick_size << depth per axis), found by descending from the root; kNone if
// the descent ends early (no surface there). A point on a brick face belongs
// to the brick on its upper side when that one exists.
uint32_t find_node(const Octree& tree, uint32_t depth, glm::ivec3 p);

// Decoded value of lattice point `p` at `depth`, or nullopt when no brick holds it.
std::optional<Voxel> lattice_voxel(const Octree& tree, uint32_t depth, glm::ivec3 p);

// World position of lattice point p at depth.
glm::vec3 lattice_position(const Octree& tree, uint32_t depth, glm::ivec3 p);

}  // namespace svo::octree
