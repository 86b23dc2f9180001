// Synthetic octrees and file helpers for the octree tests.
#pragma once

#include "../render/temp_dir.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "svo/octree/octree.h"

namespace svo::octree::testing {

// Every channel, each in a different encoding: together they use every Encoding.
std::vector<ChannelInfo> all_encodings();

// A 3-depth tree (root, one full tile, two tiles at depth 2) with 9 bricks
// assigned out of order (4 of them on the domain's upper boundary, with
// shells), the channels of all_encodings() and deterministic pseudo-random
// brick bytes drawn from `seed`.
Octree make_test_tree(uint64_t seed = 1, uint32_t brick_size = 4);

// The smallest useful tree: brick_size 2, one root with brick 0 and its
// shell, one F32 distance channel holding pool sample i = 0.25 i - 1 (8
// brick samples, then 19 shell samples).
Octree make_tiny_tree();

// make_tiny_tree() as the version 1 format wrote it: (brick_size + 1)^3 =
// 27 samples (0.25 i - 1), 364 bytes, both checksums valid.
std::vector<uint8_t> tiny_version1_file();

// Fills `bytes` deterministically from `seed` (splitmix64).
void fill_random(std::vector<uint8_t>& bytes, uint64_t seed);

std::vector<uint8_t> read_bytes(const std::filesystem::path& path);
void write_bytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes);

using svo::testing::TempDir;  // ../render/temp_dir.h

}  // namespace svo::octree::testing
