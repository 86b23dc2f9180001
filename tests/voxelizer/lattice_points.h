// Test helper: the lattice points of one depth of an octree, with their
// positions, so that tests loop over them without three nested loops each.
#pragma once

#include <glm/vec3.hpp>
#include <vector>

#include "svo/octree/sampler.h"

namespace svo::test {

struct LatticePoint {
  glm::ivec3 index;
  glm::vec3 position;
};

// Every lattice point of `depth` (0..brick_size << depth per axis), taking
// every step-th index per axis, x fastest.
inline std::vector<LatticePoint> lattice_points(const octree::Octree& tree, uint32_t depth,
                                                glm::ivec3 step = glm::ivec3(1)) {
  const int cells = int(tree.brick_size << depth);
  std::vector<LatticePoint> out;
  for (int z = 0; z <= cells; z += step.z)
    for (int y = 0; y <= cells; y += step.y)
      for (int x = 0; x <= cells; x += step.x)
        out.push_back({{x, y, z}, octree::lattice_position(tree, depth, {x, y, z})});
  return out;
}

}  // namespace svo::test
