// The bricks a narrow-band level set asks the voxelizer to sample: those
// that overlap a leaf of the grid holding a value within `surface_within` of
// zero (the surface passes through it). Shared by the mesh source (whose
// grid is in voxel units) and the .vdb input (resampled to the lattice).
#pragma once

#include <openvdb/openvdb.h>

#include <algorithm>
#include <cmath>
#include <glm/vec3.hpp>
#include <tuple>
#include <vector>

namespace svo::voxelizer {

// Brick coordinates in [0, limit)^3, sorted by (z, y, x), without repeats.
inline std::vector<glm::ivec3> bricks_near_surface(const openvdb::FloatGrid& grid, float surface_within, int brick,
                                                   int limit) {
  std::vector<glm::ivec3> out;
  for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
    bool surface = false;
    for (auto v = leaf->cbeginValueOn(); v && !surface; ++v) surface = std::abs(*v) <= surface_within;
    if (!surface) continue;
    const openvdb::CoordBBox box = leaf->getNodeBoundingBox();
    const glm::ivec3 lo(box.min().x(), box.min().y(), box.min().z()), hi(box.max().x(), box.max().y(), box.max().z());
    const glm::ivec3 blo = glm::max(glm::ivec3(0), glm::ivec3(glm::floor(glm::vec3(lo) / float(brick))));
    const glm::ivec3 bhi = glm::min(glm::ivec3(limit - 1), glm::ivec3(glm::floor(glm::vec3(hi) / float(brick))));
    for (int z = blo.z; z <= bhi.z; ++z)
      for (int y = blo.y; y <= bhi.y; ++y)
        for (int x = blo.x; x <= bhi.x; ++x) out.emplace_back(x, y, z);
  }
  std::sort(out.begin(), out.end(),
            [](glm::ivec3 a, glm::ivec3 b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); });
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace svo::voxelizer
