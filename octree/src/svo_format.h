// Internal to svo_octree (and its tests): the byte layout of the .svo file
// described in svo/octree/svo_file.h, its encoders and decoders, and the
// rules that the writer and the reader share.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "svo/octree/octree.h"

namespace svo::octree::format {

inline constexpr char kMagic[8] = {'S', 'V', 'O', 'C', 'T', 'R', 'E', 'E'};
// Version 2 (B^3 samples per brick, faces not duplicated) replaced version 1
// ((B + 1)^3 samples per brick). Version 3 is version 2 plus the detail
// block; the writer writes version 2 for an octree without detail, so such
// files keep their bytes. Version 4 is version 3 (its detail block may say
// "no detail": octaves 0) plus the material block. This build reads
// versions 2, 3 and 4.
inline constexpr uint32_t kVersion = 2;
inline constexpr uint32_t kVersionDetail = 3;
inline constexpr uint32_t kVersionMaterials = 4;
inline constexpr uint32_t kVersionSource = 5;
inline constexpr uint64_t kHeaderBytes = 128;
inline constexpr uint64_t kDetailBytes = 64;  // version 3: the detail block at offset 128
inline constexpr uint32_t kMaxDetailOctaves = 32;
inline constexpr uint64_t kChannelEntryBytes = 32;
inline constexpr uint64_t kNodeBytes = 8;
inline constexpr uint64_t kTableAlign = 8;  // channel and depth tables
inline constexpr uint64_t kDataAlign = 64;  // node table and brick data sections
inline constexpr uint32_t kMaxChannels = 16;
inline constexpr uint32_t kMaxDepths = 16;
inline constexpr uint32_t kMaxResolution = 65536;
inline constexpr uint32_t kMinBrickSize = 2, kMaxBrickSize = 32;
// The domain must be renderable in float (check_shape): its coordinates
// within +-kMaxDomainCoordinate (a preset camera a few domain sizes away
// keeps squared distances finite), and the finest voxel at least
// kMinVoxelSize (its square, 2^-120, is a normal float) and at least
// kMinVoxelRelative times the largest |coordinate| (one float step: voxels
// that coordinates cannot tell apart cannot be rendered).
inline constexpr float kMaxDomainCoordinate = 1e17f;
inline constexpr float kMinVoxelSize = 0x1p-60f;
inline constexpr float kMinVoxelRelative = 0x1p-23f;

// Byte offsets of the header fields (svo_file.h).
namespace at {
inline constexpr size_t magic = 0, version = 8, header_bytes = 12, brick_size = 16, depth_count = 20, origin = 24,
                        size = 36, sigma_rho2 = 40, constant_colour = 44, channel_count = 56, shell_count = 60,
                        node_count = 64, brick_count = 72, channel_table = 80, depth_table = 88, node_table = 96,
                        file_bytes = 104, payload_checksum = 112, header_checksum = 120;
}  // namespace at

struct Header {
  uint32_t version = kVersion;
  uint32_t header_bytes = uint32_t(kHeaderBytes);
  uint32_t brick_size = 0;
  uint32_t depth_count = 0;
  float origin[3] = {0, 0, 0};
  float size = 0;
  float sigma_rho2 = 0;
  float constant_colour[3] = {0, 0, 0};
  uint32_t channel_count = 0;
  uint32_t shell_count = 0;
  uint64_t node_count = 0;
  uint64_t brick_count = 0;
  uint64_t channel_table_offset = 0;
  uint64_t depth_table_offset = 0;
  uint64_t node_table_offset = 0;
  uint64_t file_bytes = 0;
  uint64_t payload_checksum = 0;
  uint64_t header_checksum = 0;
};

struct ChannelEntry {
  uint32_t channel = 0;
  uint32_t encoding = 0;
  uint32_t bytes_per_sample = 0;
  uint32_t reserved = 0;
  uint64_t data_offset = 0;
  uint64_t data_bytes = 0;
};

// Little-endian field access; `p` needs 2, 4 or 8 readable bytes.
uint32_t get_u32(const uint8_t* p);
uint64_t get_u64(const uint8_t* p);
float get_f32(const uint8_t* p);
void put_u32(uint8_t* p, uint32_t v);
void put_u64(uint8_t* p, uint64_t v);
void put_f32(uint8_t* p, float v);

// Header <-> its kHeaderBytes bytes (magic included); checksums copied as given.
void encode_header(const Header& h, uint8_t* out);
Header decode_header(const uint8_t* in);
void encode_channel(const ChannelEntry& e, uint8_t* out);
ChannelEntry decode_channel(const uint8_t* in);
// Detail <-> its kDetailBytes bytes (svo_file.h).
void encode_detail(const Detail& d, uint8_t* out);
Detail decode_detail(const uint8_t* in);
// The rules on a detail block that is present (octaves > 0); "" or what is wrong.
std::string check_detail(const Detail& d, float size);
// The material block (svo_file.h): its bytes, and its rules; "" or what is wrong.
std::vector<uint8_t> encode_materials(const std::vector<std::string>& materials);
std::string check_materials(const std::vector<std::string>& materials);
// The source block (svo_file.h, version 5): its bytes, and the rules on
// its text; "" or what is wrong.
std::vector<uint8_t> encode_source(const std::string& source);
std::string check_source(const std::string& source);

// XXH64 with seed 0.
uint64_t checksum(std::span<const uint8_t> bytes);
// Rewrites both checksums of a whole file image (size >= kHeaderBytes) so
// that they match its contents: payload first, then header.
void seal(std::span<uint8_t> file);

inline uint64_t align_up(uint64_t x, uint64_t a) { return (x + a - 1) / a * a; }

// Where the writer puts each section of `tree` (validated).
struct Layout {
  uint32_t version = kVersion;  // kVersionDetail when the octree has detail, kVersionMaterials with materials
  uint64_t materials = 0, material_bytes = 0;  // versions 4 and 5: the material block
  uint64_t source = 0, source_bytes = 0;       // version 5: the source block
  uint64_t channel_table = 0, depth_table = 0, node_table = 0, file_bytes = 0;
  std::vector<uint64_t> data_offset, data_bytes;
};
Layout plan_layout(const Octree& tree);

// The rules on the header-level fields of an octree: brick_size, depth_count,
// resolution, origin, size, sigma_rho2, constant_colour and the channel list.
// Uses neither nodes nor brick_data. Returns "" or what is wrong.
std::string check_shape(const Octree& shape);

// The tree rules of svo_file.h for a depth table of depth_count + 1 entries
// (already checked by check_shape to be sane) and the node array, including
// the shell rule (the bricks of nodes on the domain's upper boundary are
// exactly 0 .. shell_count - 1). Linear in nodes + brick_count; shell_count
// <= brick_count <= nodes.size() is required. Returns "" or what is wrong.
std::string check_tree(std::span<const uint32_t> depth_first_node, std::span<const Node> nodes, uint64_t brick_count,
                       uint64_t shell_count);

// Printing helpers for messages.
std::string str(float v);
std::string channel_label(size_t index, const ChannelInfo& c);  // "channel 2 (normal)"

}  // namespace svo::octree::format
