// Quad grids as triangle meshes, for tests of open and closed surfaces built
// from flat pieces (tests/voxelizer, tests/reference).
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <utility>

#include "svo/voxelizer/build.h"
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

// Appends the box [lo, hi] to `m`, n x n quads a face, outward.
inline void add_box(voxelizer::MeshArrays& m, glm::dvec3 lo, glm::dvec3 hi, int n) {
  const glm::dvec3 d = hi - lo;
  const glm::dvec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
  add_grid(m, lo, x, z, n);                  // -y
  add_grid(m, {lo.x, hi.y, lo.z}, z, x, n);  // +y
  add_grid(m, lo, z, y, n);                  // -x
  add_grid(m, {hi.x, lo.y, lo.z}, y, z, n);  // +x
  add_grid(m, lo, y, x, n);                  // -z
  add_grid(m, {lo.x, lo.y, hi.z}, x, y, n);  // +z
}

// `mesh` voxelized at resolution^3 (the default brick size).
inline octree::Octree voxelize_mesh(voxelizer::TriangleMesh mesh, uint32_t resolution) {
  auto source = voxelizer::mesh_source(std::move(mesh));
  voxelizer::VoxelizeOptions options;
  options.resolution = resolution;
  return voxelizer::voxelize(*source, options);
}

}  // namespace svo::test
