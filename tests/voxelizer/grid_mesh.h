// Quad grids as triangle meshes, for tests of open and closed surfaces built
// from flat pieces (tests/voxelizer, tests/reference).
#pragma once

#include <glm/vec3.hpp>

#include "svo/voxelizer/mesh.h"

namespace svo::test {

// Appends an n x n grid of quads from `origin` along u and v to `m`, two
// triangles each, u x v their front.
inline void add_grid(voxelizer::MeshArrays& m, glm::dvec3 origin, glm::dvec3 u, glm::dvec3 v, int n) {
  const int base = int(m.positions.size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back(origin + u * (double(i) / n) + v * (double(j) / n));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = base + j * (n + 1) + i, c = a + n + 1;
      m.triangles.emplace_back(a, a + 1, c + 1);
      m.triangles.emplace_back(a, c + 1, c);
    }
}

}  // namespace svo::test
