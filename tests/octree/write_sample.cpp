// Test-only: writes DIR/sample.svo (testing::make_test_tree),
// DIR/sample_truncated.svo (its first half) and DIR/sample_v1.svo (a version
// 1 file, testing::tiny_version1_file) for the `svo info` CLI tests.
#include <cstdio>
#include <exception>
#include <filesystem>

#include "svo/octree/svo_file.h"
#include "test_trees.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir);
    svo::octree::write_svo((dir / "sample.svo").string(), svo::octree::testing::make_test_tree(1));
    auto bytes = svo::octree::testing::read_bytes(dir / "sample.svo");
    bytes.resize(bytes.size() / 2);
    svo::octree::testing::write_bytes(dir / "sample_truncated.svo", bytes);
    svo::octree::testing::write_bytes(dir / "sample_v1.svo", svo::octree::testing::tiny_version1_file());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_sample: %s\n", e.what());
    return 1;
  }
  return 0;
}
