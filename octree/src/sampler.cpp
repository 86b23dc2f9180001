#include "svo/octree/sampler.h"

#include <glm/common.hpp>

namespace svo::octree {

namespace {

uint32_t descend(const Octree& tree, uint32_t depth, glm::ivec3 brick) {
  uint32_t node = 0;
  for (uint32_t d = 1; d <= depth; ++d) {
    uint32_t children = tree.nodes[node].children;
    if (children == kNone) return kNone;
    glm::ivec3 c = brick >> int(depth - d);
    node = children + uint32_t((c.x & 1) | ((c.y & 1) << 1) | ((c.z & 1) << 2));
  }
  return node;
}

}  // namespace

uint32_t find_node(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  if (depth >= tree.depth_count || tree.nodes.empty()) return kNone;
  const int B = int(tree.brick_size), bricks = 1 << depth;
  if (glm::any(glm::lessThan(p, glm::ivec3(0))) || glm::any(glm::greaterThan(p, glm::ivec3(B * bricks)))) {
    return kNone;
  }
  glm::ivec3 upper = glm::min(p / B, glm::ivec3(bricks - 1));
  uint32_t node = descend(tree, depth, upper);
  if (node != kNone && tree.nodes[node].brick != kNone) return node;
  // On a face, the lower neighbour holds the point too.
  for (int i = 1; i < 8; ++i) {
    glm::ivec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1), c = upper - o;
    bool ok = true;
    for (int a = 0; a < 3; ++a) ok = ok && (!o[a] || (p[a] == (upper[a]) * B && c[a] >= 0));
    if (!ok) continue;
    uint32_t other = descend(tree, depth, c);
    if (other != kNone && tree.nodes[other].brick != kNone) return other;
  }
  return node;
}

std::optional<Voxel> lattice_voxel(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  uint32_t node = find_node(tree, depth, p);
  if (node == kNone || tree.nodes[node].brick == kNone) return std::nullopt;
  const int B = int(tree.brick_size);
  // Recover the brick's coordinates: the candidate among p / B and its lower neighbours that descends to node.
  glm::ivec3 upper = glm::min(p / B, glm::ivec3((1 << depth) - 1));
  for (int i = 0; i < 8; ++i) {
    glm::ivec3 c = upper - glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || descend(tree, depth, c) != node) continue;
    glm::ivec3 local = p - c * B;
    if (glm::any(glm::greaterThan(local, glm::ivec3(B))) || glm::any(glm::lessThan(local, glm::ivec3(0)))) continue;
    const int S = B + 1;
    return decode_voxel(tree, tree.nodes[node].brick, uint32_t((local.z * S + local.y) * S + local.x), depth);
  }
  return std::nullopt;
}

glm::vec3 lattice_position(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  return tree.origin + glm::vec3(p) * tree.voxel_size(depth);
}

}  // namespace svo::octree
