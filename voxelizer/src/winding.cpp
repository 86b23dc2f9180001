#include "svo/voxelizer/winding.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace svo::voxelizer {

namespace {

constexpr uint32_t kLeafTriangles = 8;
constexpr double kInvFourPi = 0.25 / M_PI;

}  // namespace

double WindingNumber::triangle(glm::dvec3 q, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 A = a - q, B = b - q, C = c - q;
  const double la = glm::length(A), lb = glm::length(B), lc = glm::length(C);
  const double det = glm::determinant(glm::dmat3(A, B, C));
  const double den = la * lb * lc + glm::dot(A, B) * lc + glm::dot(B, C) * la + glm::dot(C, A) * lb;
  return 2.0 * std::atan2(det, den) * kInvFourPi;
}

WindingNumber::WindingNumber(const std::vector<glm::dvec3>& positions, const std::vector<glm::ivec3>& triangles,
                             double accuracy)
    : beta2_(accuracy * accuracy) {
  const uint32_t n = uint32_t(triangles.size());
  order_.resize(n);
  std::vector<glm::dvec3> centroids(n);
  for (uint32_t t = 0; t < n; ++t) {
    order_[t] = t;
    const glm::ivec3 i = triangles[t];
    centroids[t] = (positions[size_t(i.x)] + positions[size_t(i.y)] + positions[size_t(i.z)]) / 3.0;
  }
  corners_.resize(3 * size_t(n));
  // Corners in the input's order while build() permutes order_; in order_'s after.
  for (uint32_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) corners_[3 * size_t(t) + size_t(k)] = positions[size_t(triangles[t][k])];
  }
  nodes_.reserve(2 * size_t(n / kLeafTriangles + 1));
  if (n > 0) build(0, n, centroids);
  std::vector<glm::dvec3> ordered(corners_.size());
  for (uint32_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) ordered[3 * size_t(t) + size_t(k)] = corners_[3 * size_t(order_[t]) + size_t(k)];
  }
  corners_ = std::move(ordered);
}

uint32_t WindingNumber::build(uint32_t first, uint32_t count, std::vector<glm::dvec3>& centroids) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.push_back({});
  Node node;
  double area = 0;
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (uint32_t i = first; i < first + count; ++i) {
    const uint32_t t = order_[i];
    const glm::dvec3 a = corners_[3 * size_t(t)], b = corners_[3 * size_t(t) + 1], c = corners_[3 * size_t(t) + 2];
    const glm::dvec3 vector_area = 0.5 * glm::cross(b - a, c - a);
    const double s = glm::length(vector_area);
    node.dipole += vector_area;
    node.centre += s * centroids[t];
    area += s;
    lo = glm::min(lo, centroids[t]);
    hi = glm::max(hi, centroids[t]);
  }
  node.centre = area > 0 ? node.centre / area : 0.5 * (lo + hi);
  for (uint32_t i = first; i < first + count; ++i) {
    const uint32_t t = order_[i];
    const glm::dvec3 a = corners_[3 * size_t(t)], b = corners_[3 * size_t(t) + 1], c = corners_[3 * size_t(t) + 2];
    node.moment += glm::outerProduct(0.5 * glm::cross(b - a, c - a), centroids[t] - node.centre);
  }
  for (uint32_t i = first; i < first + count; ++i) {
    for (int k = 0; k < 3; ++k) {
      node.radius = std::max(node.radius, glm::length(corners_[3 * size_t(order_[i]) + size_t(k)] - node.centre));
    }
  }
  if (count <= kLeafTriangles) {
    node.first = first;
    node.count = count;
    nodes_[index] = node;
    return index;
  }
  // Median split along the widest extent of the centroids.
  const glm::dvec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half, order_.begin() + first + count,
                   [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  nodes_[index] = node;
  build(first, half, centroids);  // the left child is node index + 1
  nodes_[index].right = build(first + half, count - half, centroids);
  return index;
}

double WindingNumber::operator()(glm::dvec3 q) const {
  if (nodes_.empty()) return 0;
  double w = 0;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const glm::dvec3 d = node.centre - q;
    const double d2 = glm::dot(d, d);
    if (d2 > beta2_ * node.radius * node.radius) {
      // The first two terms of the Taylor series of a n . r / |r|^3 about
      // the centre: the dipole, and the moment M = sum (a n)(c - centre)^T
      // against the Jacobian I / r^3 - 3 r r^T / r^5 (r = centre - q).
      const double r = std::sqrt(d2), inv3 = 1.0 / (d2 * r);
      const double trace = node.moment[0][0] + node.moment[1][1] + node.moment[2][2];
      const double rmr = glm::dot(d, node.moment * d);
      w += (glm::dot(d, node.dipole) * inv3 + trace * inv3 - 3.0 * rmr * inv3 / d2) * kInvFourPi;
    } else if (node.count > 0) {
      for (uint32_t i = node.first; i < node.first + node.count; ++i) {
        w += triangle(q, corners_[3 * size_t(i)], corners_[3 * size_t(i) + 1], corners_[3 * size_t(i) + 2]);
      }
    } else {
      stack[top++] = uint32_t(&node - nodes_.data()) + 1;
      stack[top++] = node.right;
    }
  }
  return w;
}

double WindingNumber::exact(glm::dvec3 q) const {
  double w = 0;
  for (size_t i = 0; i + 2 < corners_.size(); i += 3) w += triangle(q, corners_[i], corners_[i + 1], corners_[i + 2]);
  return w;
}

}  // namespace svo::voxelizer
