// The loader on untrusted bytes: truncated, flipped, forged and absurd files
// are each one FileError naming the file, never a crash or a wrong tree.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>

#include "svo/octree/svo_file.h"
#include "svo_format.h"
#include "test_trees.h"

namespace svo::octree {
namespace {

using format::get_u32;
using format::put_u32;
using format::put_u64;
namespace at = format::at;

class SvoCorrupt : public ::testing::Test {
 protected:
  void SetUp() override {
    write_svo(dir_ / "good.svo", testing::make_test_tree(9));
    good_ = testing::read_bytes(dir_ / "good.svo");
    header_ = format::decode_header(good_.data());
  }

  // Writes `bytes` as bad.svo and expects load_svo to throw a FileError whose
  // message starts with the path and contains `what`.
  void expect_rejected(const std::vector<uint8_t>& bytes, const std::string& what) {
    std::string path = dir_ / "bad.svo";
    testing::write_bytes(path, bytes);
    try {
      load_svo(path);
      ADD_FAILURE() << "accepted a file that should fail with '" << what << "'";
    } catch (const FileError& e) {
      std::string message = e.what();
      EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(what), std::string::npos) << "expected '" << what << "' in: " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }

  // Applies `edit` to a copy of the good file, recomputes both checksums so
  // that validation (not the checksum) must catch it, and expects `what`.
  void expect_forged_rejected(const std::function<void(std::vector<uint8_t>&)>& edit, const std::string& what) {
    std::vector<uint8_t> bytes = good_;
    edit(bytes);
    format::seal(bytes);
    expect_rejected(bytes, what);
  }

  // `bytes` with the 32-bit value `value` at `offset` (resealed), or with
  // `bytes[offset]` = 0 when `nul`: refused with `what`.
  void expect_put_rejected(std::vector<uint8_t> bytes, size_t offset, uint32_t value, const std::string& what,
                           bool nul = false) {
    if (nul) {
      bytes[offset] = 0;
    } else {
      put_u32(bytes.data() + offset, value);
    }
    format::seal(bytes);
    expect_rejected(bytes, what);
  }

  uint8_t* node(std::vector<uint8_t>& b, size_t i) { return b.data() + header_.node_table_offset + 8 * i; }
  uint8_t* channel(std::vector<uint8_t>& b, size_t c) { return b.data() + header_.channel_table_offset + 32 * c; }
  uint8_t* depth(std::vector<uint8_t>& b, size_t d) { return b.data() + header_.depth_table_offset + 4 * d; }

  testing::TempDir dir_;
  std::vector<uint8_t> good_;
  format::Header header_;
};

TEST_F(SvoCorrupt, GoodFileLoads) { EXPECT_NO_THROW(load_svo(dir_ / "good.svo")); }

TEST_F(SvoCorrupt, EveryTruncationIsRejected) {
  std::string path = dir_ / "cut.svo";
  std::filesystem::copy_file(dir_ / "good.svo", path);
  for (uint64_t size = good_.size(); size-- > 0;) {
    std::filesystem::resize_file(path, size);
    try {
      MappedSvo mapped(path);
      FAIL() << "accepted the file cut to " << size << " bytes";
    } catch (const FileError& e) {
      ASSERT_NE(std::string(e.what()).find(path + ": truncated: "), std::string::npos) << e.what();
    }
  }
}

TEST_F(SvoCorrupt, TruncationMessageNamesSection) {
  std::vector<uint8_t> cut(good_.begin(), good_.begin() + long(header_.node_table_offset + 8));
  expect_rejected(cut, "truncated: node table needs 200 bytes at offset " + std::to_string(header_.node_table_offset) +
                           ", file has " + std::to_string(cut.size()));
  expect_rejected({good_.begin(), good_.begin() + 100}, "truncated: header needs 128 bytes at offset 0, file has 100");
  expect_rejected({}, "truncated: header needs 128 bytes at offset 0, file has 0");
}

TEST_F(SvoCorrupt, EveryFlippedByteIsRejected) {
  std::vector<uint8_t> bytes = good_;  // operator new: aligned for SvoView
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t mask : {uint8_t(0x01), uint8_t(0x80)}) {
      bytes[i] ^= mask;
      EXPECT_THROW(SvoView(bytes, "flip.svo"), FileError) << "byte " << i << " ^ " << int(mask);
      bytes[i] ^= mask;
    }
  }
  EXPECT_NO_THROW(SvoView(bytes, "flip.svo"));
}

TEST_F(SvoCorrupt, FlippedBytesInFileNameTheCause) {
  std::vector<uint8_t> bytes = good_;
  bytes[header_.node_table_offset + 3] ^= 0x10;
  expect_rejected(bytes, "corrupt data: checksum");
  bytes = good_;
  bytes[at::brick_count] ^= 0x01;
  expect_rejected(bytes, "corrupt header: checksum");
  bytes = good_;
  bytes.back() ^= 0x40;
  expect_rejected(bytes, "corrupt data: checksum");
}

TEST_F(SvoCorrupt, WrongMagicAndVersion) {
  std::vector<uint8_t> bytes = good_;
  bytes[0] = 'X';
  bytes[7] = 0;
  expect_rejected(bytes, "not an .svo file (magic is 'XVOCTRE\\x00', expected 'SVOCTREE')");
  // Version 1 stored (B + 1)^3 samples per brick; this build reads versions 2 to 5.
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::version, 1); },
                         "unsupported version 1 (this build reads versions 2 to 5)");
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::version, 6); }, "unsupported version 6");
  // Relabelled 4, its channel table is read as the detail and material blocks.
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::version, 4); }, "material block of");
  // A version-2 file relabelled 3 lacks the detail block its channel table must follow.
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::version, 3); },
                         "channel table offset 128 overlaps the previous section, which ends at 192");
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::version, 0); }, "unsupported version 0");
  expect_forged_rejected([](auto& b) { put_u32(b.data() + at::header_bytes, 64); }, "header_bytes is 64");
}

TEST_F(SvoCorrupt, AbsurdHeaderValues) {
  auto u32 = [](size_t offset, uint32_t v) { return [=](std::vector<uint8_t>& b) { put_u32(b.data() + offset, v); }; };
  auto u64 = [](size_t offset, uint64_t v) { return [=](std::vector<uint8_t>& b) { put_u64(b.data() + offset, v); }; };
  auto f32 = [](size_t offset, float v) {
    return [=](std::vector<uint8_t>& b) { format::put_f32(b.data() + offset, v); };
  };
  expect_forged_rejected(u64(at::node_count, uint64_t(1) << 40), "node_count is 1099511627776");
  expect_forged_rejected(u64(at::node_count, 0), "node_count is 0");
  expect_forged_rejected(u64(at::node_count, 5000), "truncated: node table needs 40000 bytes");
  expect_forged_rejected(u64(at::brick_count, 26), "brick_count 26 exceeds node_count 25");
  expect_forged_rejected(u64(at::brick_count, uint64_t(1) << 40), "brick_count 1099511627776 exceeds");
  expect_forged_rejected(u32(at::brick_size, 3), "brick_size is 3");
  expect_forged_rejected(u32(at::brick_size, 0), "brick_size is 0");
  expect_forged_rejected(u32(at::brick_size, 64), "brick_size is 64");
  expect_forged_rejected(u32(at::depth_count, 99), "depth_count is 99");
  expect_forged_rejected(u32(at::depth_count, 0), "depth_count is 0");
  expect_forged_rejected(u32(at::depth_count, 16), "finest resolution");  // 4 << 15 > 65536
  expect_forged_rejected(u32(at::channel_count, 17), "channel_count is 17");
  expect_forged_rejected(u32(at::channel_count, 0xFFFFFFFFu), "channel_count is 4294967295");
  expect_forged_rejected(u32(at::shell_count, 10), "shell_count 10 exceeds brick_count 9");
  // Sizes follow shell_count, so a wrong count fails there first; resized
  // sections reach the tree rule (bricks on the upper boundary are 0 .. 3).
  expect_forged_rejected(u32(at::shell_count, 3), "channel 0 (distance): data_bytes is 3280, expected");
  expect_forged_rejected(f32(at::origin + 4, NAN), "origin[1] is nan");
  expect_forged_rejected(f32(at::origin, INFINITY), "origin[0] is inf");
  expect_forged_rejected(f32(at::size, -1.0f), "size is -1");
  expect_forged_rejected(f32(at::size, 0.0f), "size is 0");
  expect_forged_rejected(f32(at::size, INFINITY), "size is inf");
  // Issue 22: a domain that cannot be rendered in float is refused by the
  // loader (and so by `svo info` as by `svo render`), not by the renderer.
  expect_forged_rejected(f32(at::size, 1e-45f),
                         "size 1.4013e-45 is too small to render: the finest voxel (size / 16 = 0) must be at least");
  expect_forged_rejected(f32(at::size, 1e-6f), "size 1e-06 is too small to render");  // below 2^-23 of the coordinate 2
  expect_forged_rejected(
      [&](auto& b) {
        f32(at::origin, 3e38f)(b);
        f32(at::size, 1e38f)(b);  // origin + size overflows
      },
      "the domain [origin, origin + size] spans [3e+38, inf] on axis 0");
  expect_forged_rejected(f32(at::origin + 8, -1e18f),
                         "spans [-1e+18, -1e+18] on axis 2 (origin and origin + size "
                         "must be within +-1e+17)");
  expect_forged_rejected(f32(at::sigma_rho2, -0.5f), "sigma_rho2 is -0.5");
  expect_forged_rejected(f32(at::constant_colour + 8, NAN), "constant_colour[2] is nan");
}

TEST_F(SvoCorrupt, SectionsOutOfPlace) {
  auto u64 = [](size_t offset, uint64_t v) { return [=](std::vector<uint8_t>& b) { put_u64(b.data() + offset, v); }; };
  const uint64_t far = uint64_t(1) << 40, huge = ~uint64_t(63);  // huge + size overflows
  expect_forged_rejected(u64(at::node_table, far), "truncated: node table needs 200 bytes at offset 1099511627776");
  expect_forged_rejected(u64(at::node_table, huge), "truncated: node table needs 200 bytes at offset");
  expect_forged_rejected(u64(at::channel_table, ~uint64_t(7)), "truncated: channel table needs 224 bytes");
  expect_forged_rejected(u64(at::depth_table, far), "truncated: depth table needs 16 bytes");
  expect_forged_rejected(u64(at::depth_table, header_.depth_table_offset + 4), "not a multiple of 8");
  expect_forged_rejected(u64(at::node_table, header_.node_table_offset + 8), "not a multiple of 64");
  expect_forged_rejected(u64(at::channel_table, 64), "overlaps the previous section, which ends at 128");
  expect_forged_rejected(u64(at::node_table, header_.node_table_offset - 64), "node table offset");
  expect_forged_rejected(u64(at::file_bytes, good_.size() + 1), "truncated: header records");
  expect_forged_rejected(u64(at::file_bytes, good_.size() - 1), "but its header records");
  expect_forged_rejected([](auto& b) { b.insert(b.end(), 64, 0); }, "but its header records");
  // Issue 22: no byte outside the sections, so that a stated size is never
  // more than the sections need.
  expect_forged_rejected(
      [&](auto& b) {
        b.insert(b.end(), 64, 0);
        put_u64(b.data() + at::file_bytes, b.size());
      },
      "header records " + std::to_string(good_.size() + 64) + " bytes but the sections end at " +
          std::to_string(good_.size()) + " (64 bytes after the last section)");
  expect_forged_rejected(
      [&](auto& b) {
        b.insert(b.begin() + long(header_.node_table_offset), 64, 0);
        put_u64(b.data() + at::node_table, header_.node_table_offset + 64);
        put_u64(b.data() + at::file_bytes, b.size());
      },
      "node table offset " + std::to_string(header_.node_table_offset + 64) + " leaves");
  expect_forged_rejected(
      [&](auto& b) {
        const uint64_t at0 = get_u32(channel(b, 0) + 16);
        b.insert(b.begin() + long(at0), 128, 0);
        for (size_t c = 0; c < header_.channel_count; ++c)
          put_u64(channel(b, c) + 16, get_u32(channel(b, c) + 16) + 128);
        put_u64(b.data() + at::file_bytes, b.size());
      },
      "channel 0 (distance) brick data offset");
  expect_forged_rejected(
      [&](auto& b) { put_u64(channel(b, 3) + 16, far); },
      "channel 3 (slope_dev) brick data needs 820 bytes at offset 1099511627776");  // 9 x 4^3 + 4 x 61
  expect_forged_rejected([&](auto& b) { put_u64(channel(b, 3) + 16, get_u32(channel(b, 2) + 16)); },
                         "channel 3 (slope_dev) brick data offset");
  expect_forged_rejected([&](auto& b) { put_u64(channel(b, 6) + 24, 3 * 820 + 3); },
                         "channel 6 (colour_slope): data_bytes is 2463, expected (brick_count * samples_per_brick + "
                         "shell_count * shell_samples) * 3 = 2460");
  // The version 1 size ((B + 1)^3 = 125 samples per brick) is wrong in version 2.
  expect_forged_rejected([&](auto& b) { put_u64(channel(b, 6) + 24, 3 * 125 * 9); },
                         "channel 6 (colour_slope): data_bytes is 3375, expected");
  expect_forged_rejected([&](auto& b) { put_u64(channel(b, 0) + 24, ~uint64_t(0)); }, "data_bytes is");
}

// Issue 22, case 7: a sparse file whose header states 16 GiB (its sections
// need a few KiB) is refused from its header and tables alone: no page of
// the hole is read, nothing is hashed.
TEST_F(SvoCorrupt, StatedSizeBeyondTheSectionsIsRefusedAtOnce) {
  const std::string path = dir_ / "sparse.svo";
  std::vector<uint8_t> bytes = good_;
  const uint64_t stated = uint64_t(16) << 30;
  put_u64(bytes.data() + at::file_bytes, stated);
  put_u64(bytes.data() + at::header_checksum, format::checksum(std::span(bytes).first(at::header_checksum)));
  testing::write_bytes(path, bytes);
  std::filesystem::resize_file(path, stated);
  const auto start = std::chrono::steady_clock::now();
  try {
    MappedSvo mapped(path);
    FAIL() << "accepted a 16 GiB file whose sections need " << good_.size() << " bytes";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": header records " + std::to_string(stated) +
                                         " bytes but the sections end at " + std::to_string(good_.size()) + " (" +
                                         std::to_string(stated - good_.size()) + " bytes after the last section)");
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
}

TEST_F(SvoCorrupt, BadChannelTable) {
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 2), 99); }, "channel 2: unknown channel id 99");
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 2), 0); }, "unknown channel id 0");
  expect_forged_rejected(
      [&](auto& b) {
        put_u32(channel(b, 2), uint32_t(Channel::Distance));  // a valid (channel, encoding) pair, twice
        put_u32(channel(b, 2) + 4, uint32_t(Encoding::F32));
      },
      "channel 2 (distance): same channel as channel 0");
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 1) + 4, 1); }, "encoding f32 cannot store this channel");
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 1) + 4, 42); }, "unknown encoding id 42");
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 1) + 8, 4); }, "bytes_per_sample is 4, oct24 has 3");
  expect_forged_rejected([&](auto& b) { put_u32(channel(b, 1) + 12, 7); }, "channel 1 (normal): reserved field");
}

TEST_F(SvoCorrupt, BadDepthTable) {
  expect_forged_rejected([&](auto& b) { put_u32(depth(b, 1), 2); }, "depth table starts 0, 2");
  expect_forged_rejected([&](auto& b) { put_u32(depth(b, 0), 1); }, "depth table starts 1, 1");
  expect_forged_rejected([&](auto& b) { put_u32(depth(b, 2), 8); }, "depth 1 spans nodes [1, 8)");
  expect_forged_rejected([&](auto& b) { put_u32(depth(b, 2), 30); }, "depth 1 spans nodes [1, 30)");
  expect_forged_rejected([&](auto& b) { put_u32(depth(b, 3), 17); }, "depth table ends at 17 but there are 25 nodes");
}

TEST_F(SvoCorrupt, BadNodes) {
  auto children = [&](size_t i, uint32_t v) { return [=, this](auto& b) { put_u32(node(b, i), v); }; };
  auto brick = [&](size_t i, uint32_t v) { return [=, this](auto& b) { put_u32(node(b, i) + 4, v); }; };
  expect_forged_rejected(children(0, 0), "node 0 (depth 0): children 0 is not a tile start at depth 1");
  expect_forged_rejected(children(1, 1), "node 1 (depth 1): children 1 is not a tile start");  // itself: a cycle
  expect_forged_rejected(children(9, 1), "node 9 (depth 2): children 1 is not a tile start at depth 3 (there is none)");
  expect_forged_rejected(children(2, 25),
                         "children 25 is not a tile start at depth 2 (tiles start at 9 + 8k, below 25)");
  expect_forged_rejected(children(2, 0xFFFFFFF0u), "children 4294967280");
  expect_forged_rejected(children(1, 10), "children 10 is not a tile start");
  expect_forged_rejected(children(2, 9), "node 2 (depth 1): children 9 already belong to another node");
  expect_forged_rejected(brick(3, 9), "node 3 (depth 1): brick 9 out of range (brick_count 9)");
  expect_forged_rejected(brick(3, 0), "node 3 (depth 1): brick 0 already belongs to another node");
  expect_forged_rejected(brick(20, 0xFFFFFFFEu), "brick 4294967294 out of range");
  // Shells belong to the bricks of nodes on the domain's upper boundary, numbered first.
  expect_forged_rejected(
      [&](auto& b) {
        put_u32(node(b, 1) + 4, 3);   // node 1: coordinates (0, 0, 0) at depth 1
        put_u32(node(b, 24) + 4, 7);  // node 24: (3, 3, 1) at depth 2
      },
      "node 1 (depth 1): brick 3 has a shell (shell_count is 4) but the node is not on the domain's upper boundary");
  expect_forged_rejected(
      [&](auto& b) {
        put_u32(node(b, 1) + 4, kNone);
        put_u32(node(b, 24) + 4, 7);
      },
      "node 24 (depth 2): brick 7 lies on the domain's upper boundary, so it needs a "
      "shell, but shell_count is 4 (bricks with shells come first)");
}

// Random edits to the tables with the checksums recomputed: every outcome is
// either a valid tree (which the writer accepts too) or a FileError.
TEST_F(SvoCorrupt, ResealedRandomEditsNeverCrash) {
  std::mt19937_64 rng(2024);
  const size_t tables_end = header_.node_table_offset + 25 * 8;
  int rejected = 0, accepted = 0;
  for (int round = 0; round < 3000; ++round) {
    std::vector<uint8_t> bytes = good_;
    int edits = 1 + int(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      size_t at = rng() % 4 ? rng() % tables_end : rng() % bytes.size();
      bytes[at] = rng() % 2 ? uint8_t(rng()) : uint8_t(bytes[at] ^ (1u << (rng() % 8)));
    }
    if (rng() % 8 == 0) bytes.resize(rng() % bytes.size());
    if (bytes.size() >= format::kHeaderBytes) format::seal(bytes);
    try {
      SvoView view(bytes, "edit.svo");
      EXPECT_NO_THROW(validate_octree(view.copy())) << "round " << round;
      ++accepted;
    } catch (const FileError& e) {
      ASSERT_EQ(std::string(e.what()).rfind("edit.svo: ", 0), 0u) << e.what();
      ++rejected;
    }
  }
  EXPECT_GT(rejected, 2500);
  EXPECT_GT(accepted, 0);  // edits of float fields and brick bytes stay valid
}

}  // namespace
// Version 3: the detail block is validated like the header.
TEST_F(SvoCorrupt, DetailBlockValues) {
  Octree tree = testing::make_test_tree(9);
  tree.detail = {4, 7, 0.002f, 0.02f, 0.5f, glm::vec3(1, 2, 3)};
  write_svo(dir_ / "detail.svo", tree);
  const std::vector<uint8_t> good = testing::read_bytes(dir_ / "detail.svo");
  ASSERT_EQ(format::decode_header(good.data()).version, 3u);
  EXPECT_EQ(load_svo(dir_ / "detail.svo").detail.octaves, 4u);
  auto forged = [&](size_t offset, uint32_t bits, const std::string& what) {
    std::vector<uint8_t> bytes = good;
    put_u32(bytes.data() + format::kHeaderBytes + offset, bits);
    format::seal(bytes);
    expect_rejected(bytes, what);
  };
  auto f32 = [](float v) {
    uint32_t u;
    std::memcpy(&u, &v, 4);
    return u;
  };
  forged(0, 0, "detail octaves is 0 (must be in [1, 32])");
  forged(0, 33, "detail octaves is 33");
  forged(8, f32(std::nanf("")), "detail amplitude is nan");
  forged(8, f32(0.5f), "detail amplitude is 0.5 (must be finite, > 0 and at most the wavelength)");
  forged(12, f32(-1.0f), "detail wavelength is -1");
  forged(16, f32(0.0f), "detail gain is 0");
  forged(20, f32(INFINITY), "detail colour_slope[0] is inf");
  std::vector<uint8_t> truncated(good.begin(), good.begin() + 150);
  expect_rejected(truncated, "truncated: detail block needs 64 bytes at offset 128, file has 150");
}

}  // namespace svo::octree

namespace svo::octree {

// Version 4: the material block and the material channel round-trip, and
// every count and length in the block is checked.
TEST_F(SvoCorrupt, MaterialBlock) {
  Octree tree = testing::make_test_tree(9);
  tree.materials = {R"({"brdf": "lambert"})", R"({"brdf": "ggx", "roughness": 0.3})", R"({"brdf": "phong"})"};
  tree.channels.push_back({Channel::Material, Encoding::MaterialShare8});
  tree.brick_data.emplace_back(tree.pool_samples() * 2);
  for (uint64_t b = 0; b < tree.brick_count; ++b) {
    for (uint32_t s = 0; s < tree.samples_per_brick(); ++s) {
      Voxel v = decode_voxel(tree, b, s, 0);
      v.material = uint32_t((b + s) % 3);
      v.material_share = float(s % 5) / 4.0f;
      encode_voxel(tree, b, s, 0, v);
    }
  }
  write_svo(dir_ / "materials.svo", tree);
  const std::vector<uint8_t> good = testing::read_bytes(dir_ / "materials.svo");
  ASSERT_EQ(format::decode_header(good.data()).version, 4u);
  const Octree back = load_svo(dir_ / "materials.svo");
  EXPECT_EQ(back.materials, tree.materials);
  EXPECT_EQ(back.brick_data, tree.brick_data);
  const Voxel v = decode_voxel(back, 2, 7, 0);
  EXPECT_EQ(v.material, (2u + 7u) % 3u);
  EXPECT_NEAR(v.material_share, float(7 % 5) / 4.0f, 0.51f / 255.0f);
  // The block starts after the (empty) detail block at 128 + 64.
  const size_t block = format::kHeaderBytes + format::kDetailBytes;
  auto forged = [&](size_t offset, uint32_t value, const std::string& what) {
    expect_put_rejected(good, block + offset, value, what);
  };
  forged(0, 0, "material count is 0 (must be in [1, 255])");
  forged(0, 256, "material count is 256");
  forged(0, 2, "bytes after the last material");
  forged(0, 4, "material 3 starts past the block's end");
  forged(4, 8, "does not fit 3 materials");
  forged(4, 0xFFFFFFF0u, "does not fit 3 materials");
  forged(8, 0xFFFFFFFFu, "material 0 has 4294967295 bytes (must be in [1, 65536])");
  forged(8, 1000, "material 0 has 1000 bytes, past the block's end");
  forged(8, 0, "material 0 has 0 bytes (must be in [1, 65536])");
  expect_put_rejected(good, block + 12 + 3, 0, "material 0 holds a NUL byte", true);
  std::vector<uint8_t> truncated(good.begin(), good.begin() + block + 4);
  expect_rejected(truncated, "truncated: material block needs 8 bytes at offset 192");
  // A material channel needs a choice of materials.
  Octree one = tree;
  one.materials.resize(1);
  EXPECT_THROW(write_svo(dir_ / "one.svo", one), std::invalid_argument);
  one.materials.clear();
  EXPECT_THROW(write_svo(dir_ / "one.svo", one), std::invalid_argument);
  // One material without the channel: version 4 all the same.
  one.channels.pop_back();
  one.brick_data.pop_back();
  one.materials = {R"({"brdf": "lambert"})"};
  write_svo(dir_ / "one.svo", one);
  EXPECT_EQ(load_svo(dir_ / "one.svo").materials, one.materials);
}

// Version 5: the source block (where the octree came from, svo info), after
// a material block that may then be empty.
TEST_F(SvoCorrupt, SourceBlock) {
  Octree tree = testing::make_test_tree(9);
  tree.source = R"({"input": "lion.off", "resolution": 64, "surface": "drawn two-sided"})";
  write_svo(dir_ / "source.svo", tree);
  const std::vector<uint8_t> good = testing::read_bytes(dir_ / "source.svo");
  ASSERT_EQ(format::decode_header(good.data()).version, 5u);
  const Octree back = load_svo(dir_ / "source.svo");
  EXPECT_EQ(back.source, tree.source);
  EXPECT_TRUE(back.materials.empty());
  EXPECT_EQ(back.brick_data, tree.brick_data);
  EXPECT_EQ(MappedSvo(dir_ / "source.svo")->version(), 5u);
  // After the detail block (128 + 64) and the empty material block (8 bytes).
  const size_t block = format::kHeaderBytes + format::kDetailBytes + 8;
  auto forged = [&](size_t offset, uint32_t value, const std::string& what) {
    expect_put_rejected(good, offset, value, what);
  };
  forged(block, 0, "source block states 0 bytes of text (must be in [1, 65536])");
  forged(block, 65537, "source block states 65537 bytes of text");
  forged(block, 60000, "source block of 60000 bytes at offset 200 does not fit");
  forged(block - 8, 256, "material count is 256 (must be in [0, 255])");
  expect_put_rejected(good, block + 4 + 5, 0, "source block holds a NUL byte", true);
  std::vector<uint8_t> truncated(good.begin(), good.begin() + block + 2);
  expect_rejected(truncated, "truncated: source block needs 4 bytes at offset 200");
  // The writer refuses what the reader would.
  Octree bad = tree;
  bad.source = std::string("a\0b", 3);
  EXPECT_THROW(write_svo(dir_ / "bad.svo", bad), std::invalid_argument);
  bad.source = std::string(kMaxSourceBytes + 1, 'x');
  EXPECT_THROW(write_svo(dir_ / "bad.svo", bad), std::invalid_argument);
  // With materials too: both blocks read back.
  Octree both = tree;
  both.materials = {R"({"brdf": "lambert"})"};
  write_svo(dir_ / "both.svo", both);
  const Octree both_back = load_svo(dir_ / "both.svo");
  EXPECT_EQ(both_back.materials, both.materials);
  EXPECT_EQ(both_back.source, both.source);
}

}  // namespace svo::octree
