// Splitting a polygon into triangles: its fan where that is right (convex),
// ear clipping where the fan would leave the polygon.
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "svo/voxelizer/mesh.h"

namespace svo::voxelizer {

namespace {

double cross2(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

std::vector<glm::ivec3> fan(int k) {
  std::vector<glm::ivec3> out;
  for (int i = 1; i + 1 < k; ++i) out.emplace_back(0, i, i + 1);
  return out;
}

}  // namespace

std::vector<glm::ivec3> triangulate_polygon(std::span<const glm::dvec3> corners) {
  const int k = int(corners.size());
  if (k <= 3) return fan(k);
  // Newell's normal: robust for a polygon that is not quite planar.
  glm::dvec3 n(0.0);
  for (int i = 0; i < k; ++i) {
    const glm::dvec3 a = corners[size_t(i)], b = corners[size_t((i + 1) % k)];
    n += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  const double length = glm::length(n);
  if (!(length > 0.0) || !std::isfinite(length)) return fan(k);  // degenerate: nothing better to do
  n /= length;
  // Project onto the plane with the polygon counter-clockwise.
  const int axis = std::abs(n.x) > std::abs(n.y) ? (std::abs(n.x) > std::abs(n.z) ? 0 : 2)
                                                 : (std::abs(n.y) > std::abs(n.z) ? 1 : 2);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  const double sign = n[axis] < 0.0 ? -1.0 : 1.0;
  std::vector<glm::dvec2> p(static_cast<size_t>(k));
  double extent = 0.0;
  for (int i = 0; i < k; ++i) {
    p[size_t(i)] = glm::dvec2(corners[size_t(i)][u], sign * corners[size_t(i)][v]);
    extent = std::max({extent, std::abs(p[size_t(i)].x), std::abs(p[size_t(i)].y)});
  }
  const double eps = 1e-12 * extent * extent;
  bool convex = true;
  for (int i = 0; i < k && convex; ++i) {
    convex = cross2(p[size_t((i + k - 1) % k)], p[size_t(i)], p[size_t((i + 1) % k)]) >= -eps;
  }
  if (convex) return fan(k);
  // Ear clipping: cut a convex corner whose triangle holds no other corner.
  std::vector<int> left(static_cast<size_t>(k));
  for (int i = 0; i < k; ++i) left[size_t(i)] = i;
  std::vector<glm::ivec3> out;
  out.reserve(size_t(k - 2));
  while (left.size() > 3) {
    const size_t m = left.size();
    bool cut = false;
    for (size_t j = 0; j < m && !cut; ++j) {
      const int a = left[(j + m - 1) % m], b = left[j], c = left[(j + 1) % m];
      const glm::dvec2 pa = p[size_t(a)], pb = p[size_t(b)], pc = p[size_t(c)];
      if (cross2(pa, pb, pc) <= eps) continue;  // reflex or flat
      bool empty = true;
      for (size_t t = 0; t < m && empty; ++t) {
        const int q = left[t];
        if (q == a || q == b || q == c) continue;
        const glm::dvec2 pq = p[size_t(q)];
        if (pq == pa || pq == pb || pq == pc) continue;  // a repeated position touches, it is not inside
        empty = !(cross2(pa, pb, pq) >= -eps && cross2(pb, pc, pq) >= -eps && cross2(pc, pa, pq) >= -eps);
      }
      if (!empty) continue;
      out.emplace_back(a, b, c);
      left.erase(left.begin() + std::ptrdiff_t(j));
      cut = true;
    }
    if (!cut) {
      // No ear (a self-intersecting polygon): the rest as a fan.
      for (size_t j = 1; j + 1 < left.size(); ++j) out.emplace_back(left[0], left[j], left[j + 1]);
      return out;
    }
  }
  out.emplace_back(left[0], left[1], left[2]);
  return out;
}

}  // namespace svo::voxelizer
