// Bricks store B^3 samples; a node's (B + 1)^3 block is rebuilt from its
// neighbours, or reconstructed where they are absent (octree.h). The
// expectations come from a reference written out here, point by point,
// independently of sampler.cpp.
#include "svo/octree/sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <glm/common.hpp>
#include <map>
#include <optional>
#include <string>
#include <tuple>

#include "test_trees.h"

namespace svo::octree {
namespace {

using Field = std::function<double(uint32_t depth, glm::ivec3 p)>;

// Rank of point l (some l[a] = B) among the shell points of a (B + 1)^3
// block in x-fastest order, by counting.
uint32_t shell_order(uint32_t B, glm::ivec3 l) {
  const int S = int(B) + 1;
  uint32_t rank = 0;
  for (int i = 0; i < S * S * S; ++i) {
    glm::ivec3 m(i % S, i / S % S, i / (S * S));
    if (m == l) return rank;
    rank += (m.x == int(B) || m.y == int(B) || m.z == int(B)) ? 1 : 0;
  }
  return ~0u;
}
using Key = std::tuple<uint32_t, int, int, int>;

// A complete tree: every node down to the finest depth has 8 children and a
// brick (those on the domain's upper boundary first, with shells; each group
// numbered backwards, so that brick != node). The distance at lattice point
// p of depth d is float(field(d, p)), in bricks and shells; the other
// channels hold pseudo-random bytes.
struct FieldTree {
  Octree tree;
  std::vector<glm::ivec3> coords;  // per node, computed here by construction
  std::vector<uint32_t> depth;
};

FieldTree full_tree(uint32_t B, uint32_t depth_count, const Field& field, uint64_t seed = 5) {
  FieldTree f;
  Octree& t = f.tree;
  t.brick_size = B;
  t.depth_count = depth_count;
  t.origin = {-1, -1, -1};
  t.size = 2;
  t.channels = {{Channel::Distance, Encoding::F32},
                {Channel::Normal, Encoding::Oct24},
                {Channel::HeightDev, Encoding::U8LogRelative},
                {Channel::Colour, Encoding::Srgb8}};
  t.nodes.push_back({});
  f.coords.push_back(glm::ivec3(0));
  f.depth.push_back(0);
  t.depth_first_node = {0, 1};
  for (uint32_t d = 0; d + 1 < depth_count; ++d) {
    for (uint32_t n = t.depth_first_node[d]; n < t.depth_first_node[d + 1]; ++n) {
      t.nodes[n].children = uint32_t(t.nodes.size());
      for (int i = 0; i < 8; ++i) {
        t.nodes.push_back({});
        f.coords.push_back(f.coords[n] * 2 + glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
        f.depth.push_back(d + 1);
      }
    }
    t.depth_first_node.push_back(uint32_t(t.nodes.size()));
  }
  t.brick_count = t.nodes.size();
  for (size_t n = 0; n < t.nodes.size(); ++n) t.shell_count += on_upper_boundary(f.depth[n], f.coords[n]) ? 1 : 0;
  uint32_t next[2] = {uint32_t(t.shell_count), uint32_t(t.brick_count)};  // one past the last of each group
  for (size_t n = 0; n < t.nodes.size(); ++n)
    t.nodes[n].brick = --next[on_upper_boundary(f.depth[n], f.coords[n]) ? 0 : 1];
  const int S = int(B) + 1;
  for (size_t c = 0; c < t.channels.size(); ++c) {
    t.brick_data.emplace_back(t.pool_samples() * encoding_bytes(t.channels[c].encoding));
    testing::fill_random(t.brick_data.back(), seed * 100 + c);
  }
  for (size_t n = 0; n < t.nodes.size(); ++n) {
    const uint32_t b = t.nodes[n].brick;
    for (int i = 0; i < S * S * S; ++i) {
      glm::ivec3 l(i % S, i / S % S, i / (S * S));
      const bool inside = l.x < int(B) && l.y < int(B) && l.z < int(B);
      if (!inside && b >= t.shell_count) continue;
      uint64_t at = inside ? uint64_t(b) * B * B * B + uint64_t((l.z * int(B) + l.y) * int(B) + l.x)
                           : t.brick_count * B * B * B + uint64_t(b) * (3 * B * B + 3 * B + 1) + shell_order(B, l);
      float v = float(field(f.depth[n], f.coords[n] * int(B) + l));
      std::memcpy(t.brick_data[0].data() + at * 4, &v, 4);
    }
  }
  return f;
}

// The rule of octree.h, spelled out: the owner's sample; otherwise the first
// present brick owner - S for S in x, y, z, xy, xz, yz, xyz (p on a face
// along every axis of S), the distance extrapolated by the explicit stencil
// and kept off the surface, the other channels copied from the nearest
// stored point.
class Reference {
 public:
  explicit Reference(const FieldTree& f) : t_(f.tree) {
    for (size_t n = 0; n < t_.nodes.size(); ++n) {
      if (t_.nodes[n].brick != kNone) {
        bricks_[{f.depth[n], f.coords[n].x, f.coords[n].y, f.coords[n].z}] = t_.nodes[n].brick;
      }
    }
  }

  // Per channel, the encoded bytes of lattice point p at depth d; nullopt when none.
  std::optional<std::vector<std::vector<uint8_t>>> bytes(uint32_t d, glm::ivec3 p, int* axes_used = nullptr) const {
    const int B = int(t_.brick_size);
    for (int a = 0; a < 3; ++a) {
      if (p[a] < 0 || p[a] > (B << d)) return std::nullopt;
    }
    const glm::ivec3 owner = p / B;
    if (auto b = brick(d, owner)) {
      if (axes_used) *axes_used = 0;
      return stored(*b, p - owner * B);
    }
    const std::vector<std::vector<int>> order = {{0}, {1}, {2}, {0, 1}, {0, 2}, {1, 2}, {0, 1, 2}};
    const bool domain_boundary = p.x == (B << d) || p.y == (B << d) || p.z == (B << d);
    for (const auto& axes : order) {
      glm::ivec3 e(0);
      bool on_faces = true;
      for (int a : axes) {
        e[a] = 1;
        on_faces = on_faces && p[a] > 0 && p[a] % B == 0;
      }
      if (!on_faces) continue;
      auto b = brick(d, owner - e);
      if (!b) continue;
      if (domain_boundary) {
        if (axes_used) *axes_used = -1;  // a shell sample
        return shell(*b, p - (owner - e) * B);
      }
      const glm::ivec3 q = p - e - (owner - e) * B;  // nearest stored point, local to the source
      auto out = stored(*b, q);
      auto f = [&](glm::ivec3 l) {
        float v;
        std::memcpy(&v, t_.brick_data[0].data() + (uint64_t(*b) * B * B * B + index(l)) * 4, 4);
        return double(v);
      };
      glm::ivec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
      double h = 0;
      if (axes.size() == 1) {
        glm::ivec3 u = axes[0] == 0 ? ex : axes[0] == 1 ? ey : ez;
        h = 2 * f(q) - f(q - u);
      } else if (axes.size() == 2) {
        glm::ivec3 u = axes[0] == 0 ? ex : ey, v = axes[1] == 1 ? ey : ez;
        h = 4 * f(q) - 2 * f(q - u) - 2 * f(q - v) + f(q - u - v);
      } else {
        h = 8 * f(q) - 4 * (f(q - ex) + f(q - ey) + f(q - ez)) +
            2 * (f(q - ex - ey) + f(q - ex - ez) + f(q - ey - ez)) - f(q - ex - ey - ez);
      }
      // At least the floor from zero; across the surface from q only when q's box may hold it.
      const double h_fine = t_.size / double(B << (t_.depth_count - 1)), voxel = t_.size / double(B << d);
      const double floor = std::max(0.5 * voxel - h_fine, 0.5 * h_fine);
      const double hq = f(q), side = hq < 0 ? -1 : 1;
      if (h * side < 0 && std::abs(hq) >= 0.8660254 * voxel) {
        h = side * std::max(floor, std::abs(hq));
      } else if (std::abs(h) < floor) {
        h = side * floor;
      }
      float hf = float(h);
      std::memcpy(out[0].data(), &hf, 4);
      if (axes_used) *axes_used = int(axes.size());
      return out;
    }
    return std::nullopt;
  }

 private:
  uint32_t index(glm::ivec3 l) const {
    const int B = int(t_.brick_size);
    return uint32_t((l.z * B + l.y) * B + l.x);
  }
  std::optional<uint32_t> brick(uint32_t d, glm::ivec3 c) const {
    auto it = bricks_.find({d, c.x, c.y, c.z});
    return it == bricks_.end() ? std::nullopt : std::optional<uint32_t>(it->second);
  }
  std::vector<std::vector<uint8_t>> shell(uint32_t b, glm::ivec3 l) const {
    const uint32_t B = t_.brick_size;
    std::vector<std::vector<uint8_t>> out;
    for (size_t c = 0; c < t_.channels.size(); ++c) {
      const uint32_t size = encoding_bytes(t_.channels[c].encoding);
      const uint8_t* p =
          t_.brick_data[c].data() +
          (t_.brick_count * B * B * B + uint64_t(b) * (3 * B * B + 3 * B + 1) + shell_order(B, l)) * size;
      out.emplace_back(p, p + size);
    }
    return out;
  }
  std::vector<std::vector<uint8_t>> stored(uint32_t b, glm::ivec3 l) const {
    const uint64_t spb = t_.samples_per_brick();
    std::vector<std::vector<uint8_t>> out;
    for (size_t c = 0; c < t_.channels.size(); ++c) {
      const uint32_t size = encoding_bytes(t_.channels[c].encoding);
      const uint8_t* p = t_.brick_data[c].data() + (b * spb + index(l)) * size;
      out.emplace_back(p, p + size);
    }
    return out;
  }

  const Octree& t_;
  std::map<Key, uint32_t> bricks_;
};

double smooth_field(uint32_t d, glm::ivec3 p) {
  glm::dvec3 x = glm::dvec3(p) / double(4 << d);
  return 0.3 * x.x * x.x - 0.7 * x.y * x.z + 0.2 * x.z * x.z * x.x + 0.1 * d - 0.25;
}

// For a failure message: the two distances when channel 0 differs.
std::string describe(size_t c, const uint8_t* got, const uint8_t* want) {
  if (c != 0) return "";
  float g, w;
  std::memcpy(&g, got, 4);
  std::memcpy(&w, want, 4);
  return ": got " + std::to_string(g) + ", expected " + std::to_string(w);
}

// Compares every stored node's (B + 1)^3 block, channel by channel and byte
// by byte, and every lattice point's lattice_voxel, against the reference.
// Returns how many block points were stored, reconstructed along 1, 2 and 3
// axes, and read from shells.
std::array<int, 5> expect_blocks_match(const FieldTree& f) {
  const Octree& t = f.tree;
  const Reference ref(f);
  const BrickFaces faces(t);
  const int B = int(t.brick_size), S = B + 1;
  std::array<int, 5> used{};
  std::vector<uint8_t> block;
  std::vector<Voxel> voxels;
  for (uint32_t n = 0; n < t.nodes.size(); ++n) {
    if (t.nodes[n].brick == kNone) {
      std::vector<LatticeSource> plan;
      EXPECT_THROW(faces.plan(n, plan), std::invalid_argument);
      continue;
    }
    EXPECT_EQ(faces.coords(n), f.coords[n]) << "node " << n;
    EXPECT_EQ(faces.depth(n), f.depth[n]) << "node " << n;
    faces.brick_with_faces(n, voxels);
    EXPECT_EQ(voxels.size(), size_t(S * S * S));
    for (size_t c = 0; c < t.channels.size(); ++c) {
      const uint32_t size = encoding_bytes(t.channels[c].encoding), stride = size == 3 ? 4 : size;
      block.assign(size_t(S * S * S) * stride, 0xAB);
      faces.channel_with_faces(n, c, block.data(), stride);
      for (int i = 0; i < S * S * S; ++i) {
        glm::ivec3 l(i % S, i / S % S, i / (S * S));
        int axes = -1;
        auto want = ref.bytes(f.depth[n], f.coords[n] * B + l, &axes);
        if (!want) {
          ADD_FAILURE() << "no reference value in the block of node " << n << " at " << l.x << "," << l.y << "," << l.z;
          return used;
        }
        if (c == 0) ++used[size_t(axes < 0 ? 4 : axes)];
        const uint8_t* got = block.data() + size_t(i) * stride;
        if (std::memcmp(got, (*want)[c].data(), size) != 0) {
          ADD_FAILURE() << "node " << n << " (depth " << f.depth[n] << ") channel " << c << " at " << l.x << "," << l.y
                        << "," << l.z << " (" << axes << " axes reconstructed)" << describe(c, got, (*want)[c].data());
          return used;
        }
        if (stride > size) {
          EXPECT_EQ(got[size], 0xAB) << "padding byte written";
        }
      }
    }
  }
  // lattice_voxel agrees at every point of every depth, and has no value where the reference has none.
  for (uint32_t d = 0; d < t.depth_count; ++d) {
    const int cells = B << d;
    for (int z = -1; z <= cells + 1; ++z)
      for (int y = -1; y <= cells + 1; ++y)
        for (int x = -1; x <= cells + 1; ++x) {
          auto want = ref.bytes(d, {x, y, z});
          auto got = lattice_voxel(t, d, {x, y, z});
          if (want.has_value() != got.has_value()) {
            ADD_FAILURE() << "depth " << d << " at " << x << "," << y << "," << z << ": reference "
                          << (want ? "has" : "has no") << " value";
            return used;
          }
          if (!want) continue;
          const uint8_t* samples[4] = {(*want)[0].data(), (*want)[1].data(), (*want)[2].data(), (*want)[3].data()};
          Voxel v = decode_sample(t, {samples, 4}, d);
          if (std::memcmp(&v, &*got, sizeof v) != 0) {
            ADD_FAILURE() << "lattice_voxel differs at depth " << d << ", " << x << "," << y << "," << z;
            return used;
          }
        }
  }
  return used;
}

TEST(BrickFaces, FullTreeFacesAreTheNeighboursSamples) {
  for (uint32_t B : {2u, 4u}) {
    SCOPED_TRACE("brick_size " + std::to_string(B));
    FieldTree f = full_tree(B, 3, smooth_field);
    std::array<int, 5> used = expect_blocks_match(f);
    // Inside the domain every owner exists; the domain's upper boundary comes from shells.
    EXPECT_GT(used[0], 0);
    EXPECT_EQ(used[1] + used[2] + used[3], 0);
    EXPECT_GT(used[4], 0);
  }
}

TEST(BrickFaces, AbsentNeighboursAreReconstructedCanonically) {
  for (uint32_t B : {2u, 4u, 8u}) {
    SCOPED_TRACE("brick_size " + std::to_string(B));
    FieldTree f = full_tree(B, B == 2 ? 4 : 3, smooth_field, B);
    // Drop about half of the bricks below the root, pseudo-randomly, so that
    // faces, edges and corners meet every combination of neighbours.
    int dropped = 0;
    for (size_t n = 1; n < f.tree.nodes.size(); ++n) {
      glm::ivec3 c = f.coords[n];
      uint64_t z = (uint64_t(c.x) | uint64_t(c.y) << 16 | uint64_t(c.z) << 32 | uint64_t(f.depth[n]) << 48) *
                   0x9E3779B97F4A7C15ull;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      if (((z ^ (z >> 31)) & 1) == 0) f.tree.nodes[n].brick = kNone, ++dropped;
    }
    ASSERT_GT(dropped, 20);
    std::array<int, 5> used = expect_blocks_match(f);
    EXPECT_GT(used[1], 0);
    EXPECT_GT(used[2], 0);
    EXPECT_GT(used[3], 0);
    EXPECT_GT(used[4], 0);
    std::printf("brick %u: %d points stored, reconstructed along 1, 2, 3 axes: %d, %d, %d; from shells: %d\n", B,
                used[0], used[1], used[2], used[3], used[4]);
  }
}

// A lone brick at depth 1 (its 7 neighbours dropped): a face, an edge and
// the corner extrapolate along 1, 2 and 3 axes; linear extrapolation is exact
// on a field linear per axis (x y z is), and other channels copy the nearest
// stored sample.
TEST(BrickFaces, LoneBrickExtrapolatesLinearlyPerAxis) {
  const int B = 4;
  for (const Field& field : {Field([](uint32_t, glm::ivec3 p) { return 0.5 * p.x - 0.25 * p.y + 0.125 * p.z + 1; }),
                             Field([](uint32_t, glm::ivec3 p) { return double(p.x) * p.y * p.z; })}) {
    FieldTree f = full_tree(B, 2, field);
    for (uint32_t n = 2; n < 9; ++n) f.tree.nodes[n].brick = kNone;  // keep node 1: coords (0, 0, 0)
    ASSERT_EQ(f.coords[1], glm::ivec3(0));
    std::vector<Voxel> block;
    brick_with_faces(f.tree, 1, block);
    const int S = B + 1;
    auto at = [&](int x, int y, int z) { return block[size_t((z * S + y) * S + x)]; };
    for (glm::ivec3 p :
         {glm::ivec3(4, 1, 2), glm::ivec3(1, 4, 3), glm::ivec3(4, 4, 2), glm::ivec3(2, 4, 4), glm::ivec3(4, 4, 4)}) {
      EXPECT_EQ(at(p.x, p.y, p.z).hbar, float(field(1, p))) << p.x << "," << p.y << "," << p.z;
      auto v = lattice_voxel(f.tree, 1, p);
      ASSERT_TRUE(v);
      EXPECT_EQ(v->hbar, float(field(1, p)));
      glm::ivec3 q = glm::min(p, glm::ivec3(B - 1));
      EXPECT_EQ(at(p.x, p.y, p.z).nbar, at(q.x, q.y, q.z).nbar);
      EXPECT_EQ(at(p.x, p.y, p.z).abar, at(q.x, q.y, q.z).abar);
    }
    // Depth 0: the root's upper faces are the domain's boundary.
    EXPECT_EQ(lattice_voxel(f.tree, 0, {4, 4, 4})->hbar, float(field(0, {4, 4, 4})));
    EXPECT_EQ(lattice_voxel(f.tree, 0, {1, 4, 2})->hbar, float(field(0, {1, 4, 2})));
    // Inside a dropped brick, beyond it or outside the domain: no value.
    EXPECT_FALSE(lattice_voxel(f.tree, 1, {5, 1, 1}));
    EXPECT_FALSE(lattice_voxel(f.tree, 1, {4, 5, 4}));
    EXPECT_FALSE(lattice_voxel(f.tree, 1, {-1, 0, 0}));
    EXPECT_FALSE(lattice_voxel(f.tree, 1, {9, 0, 0}));
    EXPECT_FALSE(lattice_voxel(f.tree, 2, {0, 0, 0}));
  }
}

// The reconstructed distance keeps off the surface: a lone brick at depth 1
// (voxel 0.25, finest voxel 0.25, floor 0.125) with a distance that depends
// on x only, read at the face x = 4 from samples x = 2 and x = 3.
TEST(BrickFaces, ReconstructedDistanceKeepsOffTheSurface) {
  auto face_value = [](double at2, double at3) {
    FieldTree f = full_tree(4, 2, [=](uint32_t, glm::ivec3 p) { return p.x == 2 ? at2 : p.x == 3 ? at3 : 7.0; });
    for (uint32_t n = 2; n < 9; ++n) f.tree.nodes[n].brick = kNone;
    EXPECT_FLOAT_EQ(reconstruction_floor(f.tree, 1), 0.125f);
    return lattice_voxel(f.tree, 1, {4, 1, 2})->hbar;
  };
  EXPECT_FLOAT_EQ(face_value(0.5, 0.75), 1.0f);    // linear extrapolation
  EXPECT_FLOAT_EQ(face_value(-0.4, -1.0), -1.6f);  // linear, moving away from the surface
  EXPECT_FLOAT_EQ(face_value(0.5, 0.3), 0.125f);   // short of the floor: the floor, on q's side
  EXPECT_FLOAT_EQ(face_value(-0.5, -0.3), -0.125f);
  EXPECT_FLOAT_EQ(face_value(0.5, 0.1), -0.3f);   // across q's surface, q's box may hold it: kept
  EXPECT_FLOAT_EQ(face_value(0.3, 0.1), 0.125f);  // the same, short of the floor: q's side
  EXPECT_FLOAT_EQ(face_value(0.9, 0.3), 0.3f);    // |hbar(q)| >= sqrt(3)/2 voxel: q's side, no closer than q
}

TEST(BrickFaces, FindNodeReturnsTheOwner) {
  FieldTree f = full_tree(4, 3, smooth_field);
  for (size_t n = 0; n < f.tree.nodes.size(); ++n) {
    glm::ivec3 lo = f.coords[n] * 4;
    EXPECT_EQ(find_node(f.tree, f.depth[n], lo), n);
    EXPECT_EQ(find_node(f.tree, f.depth[n], lo + 3), n);
  }
  EXPECT_EQ(find_node(f.tree, 1, {8, 0, 0}), kNone);  // the upper boundary has no owner
  EXPECT_EQ(find_node(f.tree, 3, {0, 0, 0}), kNone);
}

}  // namespace
}  // namespace svo::octree
