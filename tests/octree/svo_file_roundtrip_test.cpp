// write_svo -> load_svo / MappedSvo reproduce the tree bit for bit, and the
// sections sit where svo_file.h says.
#include <gtest/gtest.h>

#include <cstring>

#include "svo/octree/svo_file.h"
#include "svo_format.h"
#include "test_trees.h"

namespace svo::octree {
namespace {

using testing::make_test_tree;
using testing::TempDir;

bool same_floats(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_tree(const Octree& a, const Octree& b) {
  EXPECT_EQ(a.brick_size, b.brick_size);
  EXPECT_EQ(a.depth_count, b.depth_count);
  EXPECT_TRUE(same_floats(a.origin, b.origin));
  EXPECT_EQ(std::bit_cast<uint32_t>(a.size), std::bit_cast<uint32_t>(b.size));
  EXPECT_EQ(std::bit_cast<uint32_t>(a.sigma_rho2), std::bit_cast<uint32_t>(b.sigma_rho2));
  EXPECT_TRUE(same_floats(a.constant_colour, b.constant_colour));
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (size_t c = 0; c < a.channels.size(); ++c) {
    EXPECT_EQ(a.channels[c].channel, b.channels[c].channel) << "channel " << c;
    EXPECT_EQ(a.channels[c].encoding, b.channels[c].encoding) << "channel " << c;
  }
  EXPECT_EQ(a.depth_first_node, b.depth_first_node);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].children, b.nodes[i].children) << "node " << i;
    EXPECT_EQ(a.nodes[i].brick, b.nodes[i].brick) << "node " << i;
  }
  EXPECT_EQ(a.brick_count, b.brick_count);
  EXPECT_EQ(a.shell_count, b.shell_count);
  ASSERT_EQ(a.brick_data.size(), b.brick_data.size());
  for (size_t c = 0; c < a.brick_data.size(); ++c) EXPECT_TRUE(a.brick_data[c] == b.brick_data[c]) << "channel " << c;
}

TEST(SvoFile, RoundTripIsBitExact) {
  TempDir dir;
  for (uint32_t brick_size : {2u, 4u, 8u}) {
    SCOPED_TRACE("brick_size " + std::to_string(brick_size));
    Octree tree = make_test_tree(7, brick_size);
    write_svo(dir / "tree.svo", tree);
    expect_same_tree(tree, load_svo(dir / "tree.svo"));
  }
}

TEST(SvoFile, RoundTripKeepsSpecialFloats) {
  TempDir dir;
  Octree tree = make_test_tree(3);
  // Negative zero, denormal-adjacent, and at the domain's limit (svo_file.h:
  // within +-1e17, the finest voxel at least 2^-23 of the largest coordinate).
  tree.origin = {-0.0f, 1e-38f, -1e17f};
  tree.size = 0x1.8p38f;  // finest voxel 1.5 * 2^34 (resolution 16), above 2^-23 * 1e17
  tree.sigma_rho2 = 0.0f;
  write_svo(dir / "f.svo", tree);
  expect_same_tree(tree, load_svo(dir / "f.svo"));
}

TEST(SvoFile, MinimalTreesRoundTrip) {
  TempDir dir;
  Octree empty;  // one root, no channels, no bricks
  empty.depth_first_node = {0, 1};
  empty.nodes = {Node{}};
  write_svo(dir / "empty.svo", empty);
  expect_same_tree(empty, load_svo(dir / "empty.svo"));

  Octree no_bricks = make_test_tree();  // channels present, every pool empty
  no_bricks.brick_count = 0;
  no_bricks.shell_count = 0;
  for (auto& n : no_bricks.nodes) n.brick = kNone;
  for (auto& pool : no_bricks.brick_data) pool.clear();
  write_svo(dir / "no_bricks.svo", no_bricks);
  expect_same_tree(no_bricks, load_svo(dir / "no_bricks.svo"));
}

TEST(SvoFile, MappedViewAgreesWithTree) {
  TempDir dir;
  Octree tree = make_test_tree(11);
  write_svo(dir / "tree.svo", tree);
  MappedSvo mapped(dir / "tree.svo");
  const SvoView& v = mapped.view();
  EXPECT_EQ(v.name(), dir / "tree.svo");
  EXPECT_EQ(v.file_bytes(), std::filesystem::file_size(dir / "tree.svo"));
  EXPECT_EQ(v.brick_size(), tree.brick_size);
  EXPECT_EQ(v.depth_count(), tree.depth_count);
  EXPECT_EQ(v.depth_first_node(), tree.depth_first_node);
  EXPECT_EQ(v.brick_count(), tree.brick_count);
  EXPECT_EQ(v.voxel_count(), tree.voxel_count());
  ASSERT_EQ(v.nodes().size(), tree.nodes.size());
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    EXPECT_EQ(v.nodes()[i].children, tree.nodes[i].children);
    EXPECT_EQ(v.nodes()[i].brick, tree.nodes[i].brick);
  }
  ASSERT_EQ(v.channels().size(), tree.channels.size());
  const uint32_t spb = tree.samples_per_brick();
  for (size_t c = 0; c < tree.channels.size(); ++c) {
    SCOPED_TRACE("channel " + std::to_string(c));
    auto pool = v.brick_data(c);
    ASSERT_EQ(pool.size(), tree.brick_data[c].size());
    EXPECT_TRUE(std::equal(pool.begin(), pool.end(), tree.brick_data[c].begin()));
    EXPECT_EQ(v.brick_data_offset(c) % format::kDataAlign, 0u);
    uint32_t bytes = encoding_bytes(tree.channels[c].encoding);
    for (uint64_t b = 0; b < tree.brick_count; ++b) {
      auto brick = v.brick(c, b);
      ASSERT_EQ(brick.size(), spb * bytes);
      EXPECT_EQ(std::memcmp(brick.data(), tree.brick_data[c].data() + b * spb * bytes, brick.size()), 0);
    }
    EXPECT_THROW(v.brick(c, tree.brick_count), std::out_of_range);
  }
  EXPECT_THROW(v.brick(tree.channels.size(), 0), std::out_of_range);
  // Spans point into the mapping (no copy) and survive a move of the owner.
  const Node* nodes = v.nodes().data();
  MappedSvo moved(std::move(mapped));
  EXPECT_EQ(moved->nodes().data(), nodes);
  expect_same_tree(tree, moved->copy());
}

TEST(SvoFile, WriterPlacesSectionsAsDocumented) {
  TempDir dir;
  Octree tree = make_test_tree(5);
  write_svo(dir / "tree.svo", tree);
  auto bytes = testing::read_bytes(dir / "tree.svo");
  auto h = format::decode_header(bytes.data());
  EXPECT_EQ(h.channel_table_offset, 128u);
  EXPECT_EQ(h.depth_table_offset, 128u + 7 * 32);
  EXPECT_EQ(h.node_table_offset, format::align_up(h.depth_table_offset + 4 * 4, 64));
  EXPECT_EQ(h.node_count, 25u);
  EXPECT_EQ(h.file_bytes, bytes.size());
  uint64_t end = h.node_table_offset + 25 * 8;
  for (uint32_t c = 0; c < 7; ++c) {
    auto e = format::decode_channel(bytes.data() + 128 + 32 * c);
    EXPECT_EQ(e.data_offset, format::align_up(end, 64)) << "channel " << c;
    EXPECT_EQ(e.data_bytes, tree.brick_data[c].size()) << "channel " << c;
    end = e.data_offset + e.data_bytes;
  }
  EXPECT_EQ(end, bytes.size());
}

}  // namespace
}  // namespace svo::octree
