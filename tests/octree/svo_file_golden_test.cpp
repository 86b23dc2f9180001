// Freezes the version 2 header (svo_file.h): a tiny fixed tree must produce
// exactly these bytes. The payload checksum at offset 112 freezes the rest
// of the file too. If this fails after a deliberate format change, bump the
// version and update the array. The two checksums were also reproduced by an
// independent XXH64 (written from the xxHash spec) over the bytes that
// svo_file.h describes; the same script reproduces version 1's.
//
// Updated deliberately for version 2 (B^3 samples per brick instead of
// (B + 1)^3, plus shells for the bricks on the domain's upper boundary):
// version byte 2 and shell_count 1 at offset 60 (reserved in version 1). The
// tiny tree's root lies on the boundary, so it stores 2^3 brick samples and a
// 19-sample shell: 27 samples, as many as version 1's 3^3, hence the same
// payload and payload checksum; the header checksum changed. The layout of
// a tree with inner bricks is frozen in TestTreeSizes. Version 1 files are
// refused by name (VersionOneFileIsRefused).
#include <gtest/gtest.h>

#include <cstdio>

#include "svo/octree/svo_file.h"
#include "svo_format.h"
#include "test_trees.h"

namespace svo::octree {
namespace {

// clang-format off
constexpr uint8_t kGoldenHeader[128] = {
  0x53, 0x56, 0x4F, 0x43, 0x54, 0x52, 0x45, 0x45,  // magic "SVOCTREE"
  0x02, 0x00, 0x00, 0x00,                          // version 2
  0x80, 0x00, 0x00, 0x00,                          // header_bytes 128
  0x02, 0x00, 0x00, 0x00,                          // brick_size 2
  0x01, 0x00, 0x00, 0x00,                          // depth_count 1
  0x00, 0x00, 0x80, 0xBF, 0x00, 0x00, 0x00, 0xC0, 0x00, 0x00, 0x40, 0xC0,  // origin (-1, -2, -3)
  0x00, 0x00, 0x80, 0x40,                          // size 4
  0x00, 0x00, 0x00, 0x3E,                          // sigma_rho2 0.125
  0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x80, 0x3E, 0x00, 0x00, 0x80, 0x3F,  // constant_colour (0.5, 0.25, 1)
  0x01, 0x00, 0x00, 0x00,                          // channel_count 1
  0x01, 0x00, 0x00, 0x00,                          // shell_count 1
  0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // node_count 1
  0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // brick_count 1
  0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // channel table at 128
  0xA0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // depth table at 160
  0xC0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // node table at 192
  0x6C, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // file_bytes 364
  0x80, 0x6F, 0x42, 0xCD, 0x0F, 0x1A, 0x46, 0xB3,  // payload checksum, XXH64 of bytes [128, 364)
  0x91, 0xD8, 0xD3, 0xC8, 0x19, 0x9B, 0x26, 0xB2,  // header checksum, XXH64 of bytes [0, 120)
};
// clang-format on

TEST(SvoGolden, HeaderBytesAreFrozen) {
  testing::TempDir dir;
  write_svo(dir / "tiny.svo", testing::make_tiny_tree());
  std::vector<uint8_t> bytes = testing::read_bytes(dir / "tiny.svo");
  ASSERT_GE(bytes.size(), sizeof kGoldenHeader);
  std::string dump;
  for (size_t i = 0; i < sizeof kGoldenHeader; ++i) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X,%s", bytes[i], i % 16 == 15 ? "\n" : " ");
    dump += hex;
  }
  for (size_t i = 0; i < sizeof kGoldenHeader; ++i) {
    ASSERT_EQ(int(bytes[i]), int(kGoldenHeader[i])) << "header byte " << i << " differs; this build writes:\n" << dump;
  }
}

TEST(SvoGolden, TinyFileLayout) {
  testing::TempDir dir;
  write_svo(dir / "tiny.svo", testing::make_tiny_tree());
  std::vector<uint8_t> bytes = testing::read_bytes(dir / "tiny.svo");
  // header 128 + channel table 32 + depth table 8 -> nodes at 192 (8 bytes)
  // -> distance at 256: 2^3 brick samples and the root's shell of 3 * 2^2 +
  // 3 * 2 + 1 = 19 samples, x 4 bytes -> 364 bytes.
  ASSERT_EQ(bytes.size(), 364u);
  const uint8_t channel[32] = {1, 0, 0, 0, 1, 0, 0, 0, 4,   0, 0, 0, 0, 0, 0, 0,
                               0, 1, 0, 0, 0, 0, 0, 0, 108, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 128, bytes.begin() + 160),
            std::vector<uint8_t>(channel, channel + 32));
  const uint8_t depth_table[8] = {0, 0, 0, 0, 1, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 160, bytes.begin() + 168),
            std::vector<uint8_t>(depth_table, depth_table + 8));
  EXPECT_TRUE(std::all_of(bytes.begin() + 168, bytes.begin() + 192, [](uint8_t b) { return b == 0; }));
  const uint8_t root[8] = {0xFF, 0xFF, 0xFF, 0xFF, 0, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 192, bytes.begin() + 200), std::vector<uint8_t>(root, root + 8));
  EXPECT_TRUE(std::all_of(bytes.begin() + 200, bytes.begin() + 256, [](uint8_t b) { return b == 0; }));
  const uint8_t first_samples[8] = {0x00, 0x00, 0x80, 0xBF, 0x00, 0x00, 0x40, 0xBF};  // -1.0f, -0.75f
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 256, bytes.begin() + 264),
            std::vector<uint8_t>(first_samples, first_samples + 8));
  const uint8_t first_shell_sample[4] = {0x00, 0x00, 0x80, 0x3F};  // pool sample 8: 1.0f
  EXPECT_EQ(std::vector<uint8_t>(bytes.begin() + 288, bytes.begin() + 292),
            std::vector<uint8_t>(first_shell_sample, first_shell_sample + 4));
}

// Section sizes of the test tree (brick_size 4, 9 bricks, 4 of them on the
// domain's upper boundary): per channel (9 x 4^3 + 4 x 61) samples.
TEST(SvoGolden, TestTreeSizes) {
  testing::TempDir dir;
  write_svo(dir / "tree.svo", testing::make_test_tree(5));
  std::vector<uint8_t> bytes = testing::read_bytes(dir / "tree.svo");
  EXPECT_EQ(format::get_u32(bytes.data() + format::at::shell_count), 4u);
  const uint64_t samples = 9 * 64 + 4 * 61;
  const uint64_t sample_bytes[7] = {4, 3, 1, 1, 3, 3, 3};
  for (int c = 0; c < 7; ++c) {
    EXPECT_EQ(format::decode_channel(bytes.data() + 128 + 32 * c).data_bytes, samples * sample_bytes[c]) << c;
  }
}

// The same tiny tree as version 1 wrote it ((B + 1)^3 = 27 samples, 364
// bytes): its checksums are the ones version 1's golden header froze, so the
// bytes are genuine; this build refuses them with one line naming the version.
TEST(SvoGolden, VersionOneFileIsRefused) {
  std::vector<uint8_t> v1 = testing::tiny_version1_file();
  ASSERT_EQ(v1.size(), 364u);
  const uint8_t v1_checksums[16] = {0x80, 0x6F, 0x42, 0xCD, 0x0F, 0x1A, 0x46, 0xB3,
                                    0xA6, 0x2A, 0x14, 0x57, 0xF3, 0xDB, 0x51, 0x1B};
  EXPECT_EQ(std::vector<uint8_t>(v1.begin() + 112, v1.begin() + 128),
            std::vector<uint8_t>(v1_checksums, v1_checksums + 16));
  testing::TempDir dir;
  testing::write_bytes(dir / "v1.svo", v1);
  try {
    load_svo(dir / "v1.svo");
    ADD_FAILURE() << "loaded a version 1 file";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), dir / "v1.svo" + ": unsupported version 1 (this build reads versions 2 to 5)");
  }
}

}  // namespace
}  // namespace svo::octree
