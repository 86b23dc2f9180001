// write_svo replaces files atomically: a failed write leaves the old file and
// no temporary; an invalid tree writes nothing.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <cmath>
#include <csignal>
#include <filesystem>

#include "svo/octree/svo_file.h"
#include "test_trees.h"

namespace svo::octree {
namespace {

namespace fs = std::filesystem;
using testing::make_test_tree;
using testing::TempDir;
using svo::testing::FileSizeLimit;
using svo::testing::names_in;


TEST(SvoWrite, ReplacesExistingFileAndLeavesNoTemporary) {
  TempDir dir;
  testing::write_bytes(dir / "scene.svo", std::vector<uint8_t>(100000, 0xAB));
  Octree tree = make_test_tree(4);
  write_svo(dir / "scene.svo", tree);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"scene.svo"});
  EXPECT_EQ(load_svo(dir / "scene.svo").brick_data, tree.brick_data);
  write_svo(dir / "scene.svo", make_test_tree(5));  // and once more over a valid file
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"scene.svo"});
  EXPECT_EQ(load_svo(dir / "scene.svo").brick_data, make_test_tree(5).brick_data);
}

TEST(SvoWrite, MissingDirectoryThrowsAndCreatesNothing) {
  TempDir dir;
  std::string path = dir / "no/such/dir/scene.svo";
  try {
    write_svo(path, make_test_tree());
    FAIL() << "wrote into a missing directory";
  } catch (const FileError& e) {
    std::string message = e.what();
    EXPECT_EQ(message, path + ": directory " + (dir / "no/such/dir") + " does not exist");
  }
  EXPECT_TRUE(names_in(dir.path()).empty());
}

// A directory where the file should go is refused before anything is
// written (it used to fail at the rename).
TEST(SvoWrite, DirectoryAtTheNameIsRefusedFirst) {
  TempDir dir;
  fs::create_directory(dir / "scene.svo");
  testing::write_bytes(dir / "scene.svo/keep", {1, 2, 3});
  try {
    write_svo(dir / "scene.svo", make_test_tree());
    FAIL() << "renamed over a directory";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "scene.svo") + ": is a directory; outputs replace only regular files");
  }
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"scene.svo"});
  EXPECT_EQ(testing::read_bytes(dir / "scene.svo/keep"), (std::vector<uint8_t>{1, 2, 3}));
}

// A short write (here: the file size limit, as a full disk would) fails the
// write, keeps the old file byte for byte and removes the temporary.
TEST(SvoWrite, ShortWriteKeepsOldFile) {
  TempDir dir;
  Octree old_tree = make_test_tree(1);
  write_svo(dir / "scene.svo", old_tree);
  std::vector<uint8_t> old_bytes = testing::read_bytes(dir / "scene.svo");

  std::string message;
  {
    FileSizeLimit limit(4096);  // write() then fails with EFBIG
    try {
      write_svo(dir / "scene.svo", make_test_tree(2));
    } catch (const FileError& e) {
      message = e.what();
    }
  }

  EXPECT_NE(message.find(dir / "scene.svo: cannot write: writing "), std::string::npos) << message;
  EXPECT_NE(message.find("File too large"), std::string::npos) << message;
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"scene.svo"});
  EXPECT_EQ(testing::read_bytes(dir / "scene.svo"), old_bytes);
}

TEST(SvoWrite, InvalidTreeWritesNothing) {
  TempDir dir;
  auto expect_invalid = [&](Octree tree, const std::string& what) {
    try {
      write_svo(dir / "bad.svo", tree);
      ADD_FAILURE() << "wrote an invalid tree: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
    EXPECT_TRUE(names_in(dir.path()).empty());
  };
  Octree t = make_test_tree();
  t.brick_data[2].pop_back();
  expect_invalid(t,
                 "channel 2 (height_dev): brick_data has 819 bytes, (brick_count * samples_per_brick + shell_count * "
                 "shell_samples) * bytes = 820");
  t = make_test_tree();
  std::swap(t.nodes[1].brick, t.nodes[24].brick);  // node 24 lies on the upper boundary, node 1 inside
  expect_invalid(t,
                 "node 1 (depth 1): brick 3 has a shell (shell_count is 4) but the node is not on the domain's "
                 "upper boundary");
  t = make_test_tree();
  t.shell_count = 5;
  t.brick_data = make_test_tree().brick_data;
  for (size_t c = 0; c < t.channels.size(); ++c) {
    t.brick_data[c].resize(t.pool_samples() * encoding_bytes(t.channels[c].encoding));
  }
  expect_invalid(t, "brick 4 has a shell (shell_count is 5) but the node is not on the domain's upper boundary");
  t = make_test_tree();
  t.shell_count = 10;
  expect_invalid(t, "9 bricks and 10 shells");
  t = make_test_tree();
  t.nodes[5].children = 9;
  expect_invalid(t, "node 5 (depth 1): children 9 already belong to another node");
  t = make_test_tree();
  t.channels.push_back({Channel::Distance, Encoding::F32});
  t.brick_data.push_back(t.brick_data[0]);
  expect_invalid(t, "same channel as channel 0");
  t = make_test_tree();
  t.depth_first_node.pop_back();
  expect_invalid(t, "depth_first_node has 3 entries");
  t = make_test_tree();
  t.size = NAN;
  expect_invalid(t, "size is nan");
}

}  // namespace
}  // namespace svo::octree
