#include "svo/octree/sampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <glm/vector_relational.hpp>
#include <stdexcept>
#include <string>

namespace svo::octree {

namespace {

// The file allows at most 16 channels (svo_file.h); samples are at most 4 bytes.
constexpr size_t kMaxChannels = 16, kMaxSampleBytes = 4;

// Reconstruction candidates owner - S, in the order of octree.h: by |S|,
// then by the bits of S (x = 1, y = 2, z = 4).
constexpr uint32_t kCandidates[7] = {1, 2, 4, 3, 5, 6, 7};

// |hbar| / voxel of a lattice point whose footprint (a box of one voxel) may
// hold the surface: the mean plane passes through the box, at most half its
// diagonal from the centre.
constexpr float kMayHoldSurface = 0.8660254f;  // sqrt(3) / 2

glm::ivec3 axis_bits(uint32_t mask) { return {int(mask & 1u), int((mask >> 1) & 1u), int((mask >> 2) & 1u)}; }

uint32_t local_index(glm::ivec3 l, int B) { return uint32_t((l.z * B + l.y) * B + l.x); }

// The node at `depth` with brick coordinates `c` (inside the domain), or
// kNone when the descent ends early.
uint32_t descend(const Octree& tree, uint32_t depth, glm::ivec3 c) {
  uint32_t node = 0;
  for (uint32_t d = 1; d <= depth; ++d) {
    uint32_t children = tree.nodes[node].children;
    if (children == kNone) return kNone;
    glm::ivec3 b = c >> int(depth - d);
    node = children + uint32_t((b.x & 1) | ((b.y & 1) << 1) | ((b.z & 1) << 2));
  }
  return node;
}

// The brick of coordinates `c` at `depth`, or kNone (outside, not reached, no brick).
uint32_t brick_at(const Octree& tree, uint32_t depth, glm::ivec3 c) {
  const int bricks = 1 << depth;
  if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, glm::ivec3(bricks)))) {
    return kNone;
  }
  uint32_t node = descend(tree, depth, c);
  return node == kNone ? kNone : tree.nodes[node].brick;
}

// The rule of octree.h for lattice point p >= 0 of `depth`; brick_of(c) is
// the brick of coordinates c at that depth, or kNone.
template <class BrickOf>
LatticeSource resolve(const Octree& tree, uint32_t depth, glm::ivec3 p, const BrickOf& brick_of) {
  const int B = int(tree.brick_size);
  const glm::ivec3 owner = p / B;
  if (uint32_t b = brick_of(owner); b != kNone) {
    return {b, tree.brick_sample(b, local_index(p - owner * B, B)), 0, depth};
  }
  uint32_t on_face = 0;
  for (int a = 0; a < 3; ++a) on_face |= (p[a] > 0 && p[a] % B == 0) ? 1u << a : 0u;
  const bool domain_boundary = glm::any(glm::equal(p, glm::ivec3(B << depth)));
  for (uint32_t s : kCandidates) {
    if (s & ~on_face) continue;
    const glm::ivec3 c = owner - axis_bits(s);
    const uint32_t b = brick_of(c);
    if (b == kNone) continue;
    // A candidate holding a point of the domain's upper boundary lies on it:
    // its shell has the point (always, in a valid tree).
    if (domain_boundary && b < tree.shell_count) return {b, tree.shell_sample(b, p - c * B), 0, depth};
    return {b, tree.brick_sample(b, local_index(p - axis_bits(s) - c * B, B)), s, depth};
  }
  return {};
}

// Decodes the value at `source` (brick != kNone) through source_bytes.
Voxel decode_source(const Octree& tree, const LatticeSource& source, uint32_t depth) {
  uint8_t bytes[kMaxChannels][kMaxSampleBytes];
  const uint8_t* samples[kMaxChannels];
  const size_t n = std::min(tree.channels.size(), kMaxChannels);
  for (size_t c = 0; c < n; ++c) {
    source_bytes(tree, c, source, bytes[c]);
    samples[c] = bytes[c];
  }
  return decode_sample(tree, {samples, n}, depth);
}

}  // namespace

uint32_t find_node(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  if (depth >= tree.depth_count || tree.nodes.empty()) return kNone;
  const int B = int(tree.brick_size);
  if (glm::any(glm::lessThan(p, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(p, glm::ivec3(B << depth)))) {
    return kNone;
  }
  return descend(tree, depth, p / B);
}

LatticeSource lattice_source(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  if (depth >= tree.depth_count || tree.nodes.empty()) return {};
  const int B = int(tree.brick_size);
  if (glm::any(glm::lessThan(p, glm::ivec3(0))) || glm::any(glm::greaterThan(p, glm::ivec3(B << depth)))) return {};
  return resolve(tree, depth, p, [&](glm::ivec3 c) { return brick_at(tree, depth, c); });
}

float reconstruction_floor(const Octree& tree, uint32_t depth) {
  const float finest = tree.voxel_size(tree.depth_count - 1);
  return std::max(0.5f * tree.voxel_size(depth) - finest, 0.5f * finest);
}

void source_bytes(const Octree& tree, size_t c, const LatticeSource& source, uint8_t* out) {
  const uint32_t bytes = encoding_bytes(tree.channels[c].encoding);
  const uint8_t* pool = tree.brick_data[c].data();
  if (source.axes == 0 || tree.channels[c].channel != Channel::Distance) {
    std::memcpy(out, pool + source.sample * bytes, bytes);
    return;
  }
  // The distance is F32 (encoding_fits).
  const uint32_t B = tree.brick_size, step[3] = {1, B, B * B};
  double sum = 0;
  for (uint32_t t = 0; t < 8; ++t) {
    const double w = extrapolation_weight(source.axes, t);
    if (w == 0) continue;
    uint64_t i = source.sample;
    for (int a = 0; a < 3; ++a) i -= ((t >> a) & 1u) * step[a];
    float v;
    std::memcpy(&v, pool + i * 4, 4);
    sum += w * double(v);
  }
  float nearest;
  std::memcpy(&nearest, pool + source.sample * 4, 4);
  const float value =
      reconstructed_distance(sum, nearest, reconstruction_floor(tree, source.depth), tree.voxel_size(source.depth));
  std::memcpy(out, &value, 4);
}

double extrapolation_weight(uint32_t axes, uint32_t t) {
  // Per axis of S the stencil is 2 f(B - 1) - f(B - 2); over several axes,
  // the product of the stencils.
  if (t & ~axes) return 0;
  double w = 1;
  for (int a = 0; a < 3; ++a) {
    if ((axes >> a) & 1u) w *= ((t >> a) & 1u) ? -1.0 : 2.0;
  }
  return w;
}

float reconstructed_distance(double extrapolated, float nearest, float floor, float voxel) {
  // No surface is near p (its owner has no brick): at least the floor away
  // from zero. It may lie across the surface from the nearest stored sample
  // q only if q's footprint may hold the surface (a voxel's mean plane passes
  // through its box: |hbar(q)| < sqrt(3) / 2 voxel); otherwise, and when the
  // extrapolation falls short of the floor, it stays on q's side.
  const float side = std::signbit(nearest) ? -1.0f : 1.0f;
  float value = float(extrapolated);
  const bool crosses = value * side < 0;
  if (std::isnan(value) || (crosses && !(std::abs(nearest) < kMayHoldSurface * voxel))) {
    value = side * std::max(floor, std::abs(nearest));
  } else if (!(std::abs(value) >= floor)) {
    value = side * floor;
  }
  return value;
}

std::optional<Voxel> lattice_voxel(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  const LatticeSource source = lattice_source(tree, depth, p);
  if (source.brick == kNone) return std::nullopt;
  return decode_source(tree, source, depth);
}

glm::vec3 lattice_position(const Octree& tree, uint32_t depth, glm::ivec3 p) {
  return tree.origin + glm::vec3(p) * tree.voxel_size(depth);
}

BrickFaces::BrickFaces(const Octree& tree) : tree_(tree), coords_(tree.nodes.size()), depth_(tree.nodes.size()) {
  for (uint32_t d = 0; d < tree.depth_count; ++d) {
    for (uint32_t n = tree.depth_first_node[d]; n < tree.depth_first_node[d + 1]; ++n) {
      depth_[n] = uint8_t(d);
      const uint32_t children = tree.nodes[n].children;
      if (children == kNone) continue;
      for (uint32_t i = 0; i < 8; ++i) coords_[children + i] = coords_[n] * 2 + axis_bits(i);
    }
  }
}

void BrickFaces::plan(uint32_t node, std::vector<LatticeSource>& out) const {
  if (node >= tree_.nodes.size() || tree_.nodes[node].brick == kNone) {
    throw std::invalid_argument("BrickFaces::plan: node " + std::to_string(node) +
                                (node >= tree_.nodes.size() ? " out of range" : " has no brick"));
  }
  const int B = int(tree_.brick_size), S = B + 1;
  const uint32_t d = depth_[node], own = tree_.nodes[node].brick;
  const glm::ivec3 c = coords_[node];
  // Every candidate of a point of this block lies in c + {-1, 0, 1}^3.
  uint32_t around[27];
  for (int k = 0; k < 27; ++k) {
    glm::ivec3 o(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
    around[k] = k == 13 ? own : brick_at(tree_, d, c + o);
  }
  auto brick_of = [&](glm::ivec3 q) {
    glm::ivec3 o = q - c + 1;
    if (glm::any(glm::lessThan(o, glm::ivec3(0))) || glm::any(glm::greaterThan(o, glm::ivec3(2)))) {
      return brick_at(tree_, d, q);  // not reached (see above); kept exact regardless
    }
    return around[(o.z * 3 + o.y) * 3 + o.x];
  };
  out.resize(size_t(S) * S * S);
  size_t i = 0;
  for (int z = 0; z < S; ++z)
    for (int y = 0; y < S; ++y)
      for (int x = 0; x < S; ++x, ++i) {
        if (x < B && y < B && z < B) {
          out[i] = {own, tree_.brick_sample(own, local_index({x, y, z}, B)), 0, d};
        } else {
          out[i] = resolve(tree_, d, c * B + glm::ivec3(x, y, z), brick_of);
        }
      }
}

void BrickFaces::channel_with_faces(uint32_t node, size_t c, uint8_t* out, uint32_t stride) const {
  std::vector<LatticeSource> sources;
  plan(node, sources);
  for (size_t i = 0; i < sources.size(); ++i) source_bytes(tree_, c, sources[i], out + i * stride);
}

void BrickFaces::brick_with_faces(uint32_t node, std::vector<Voxel>& out) const {
  std::vector<LatticeSource> sources;
  plan(node, sources);
  out.resize(sources.size());
  for (size_t i = 0; i < sources.size(); ++i) out[i] = decode_source(tree_, sources[i], depth_[node]);
}

void brick_with_faces(const Octree& tree, uint32_t node, std::vector<Voxel>& out) {
  BrickFaces(tree).brick_with_faces(node, out);
}

}  // namespace svo::octree
