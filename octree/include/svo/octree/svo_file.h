// The .svo file: one octree (octree.h) on disk, written atomically, loaded
// with every count and offset validated, and readable in place through a
// read-only memory map (DESIGN section 7).
//
// Layout, version 2; version 3 = version 2 plus the detail block (an
// octree with procedural detail octaves, Octree::detail; the writer writes
// version 2 when there is none). All integers little-endian, floats
// IEEE-754 binary32. Offsets are bytes from the start of the file.
//
//   header, 128 bytes at offset 0
//     off size  field
//       0    8  magic "SVOCTREE"
//       8    4  u32 version = 2, 3, 4 or 5 (version 1 stored (brick_size + 1)^3
//                                   samples per brick; it is refused)
//      12    4  u32 header_bytes = 128
//      16    4  u32 brick_size        power of two in [2, 32]
//      20    4  u32 depth_count       [1, 16]; brick_size << (depth_count - 1) <= 65536
//      24   12  f32 origin[3]         origin[i] and origin[i] + size finite and within +-1e17
//      36    4  f32 size              > 0; the finest voxel, size / (brick_size << (depth_count - 1)),
//                                     at least 2^-60 and at least 2^-23 times the domain's largest
//                                     |coordinate| (so that a renderer in float can tell voxels apart,
//                                     and squared distances neither overflow nor underflow)
//      40    4  f32 sigma_rho2        finite, >= 0
//      44   12  f32 constant_colour[3] finite
//      56    4  u32 channel_count     [0, 16]
//      60    4  u32 shell_count       <= brick_count: bricks with a shell (octree.h)
//      64    8  u64 node_count        in [1, 2^32 - 1)
//      72    8  u64 brick_count       <= node_count
//      80    8  u64 channel_table_offset  8-aligned, >= 128
//      88    8  u64 depth_table_offset    8-aligned, >= end of channel table
//      96    8  u64 node_table_offset     64-aligned, >= end of depth table
//     104    8  u64 file_bytes        the size of the whole file = the end of the last section
//     112    8  u64 payload_checksum  XXH64 (seed 0) of bytes [128, file_bytes)
//     120    8  u64 header_checksum   XXH64 (seed 0) of bytes [0, 120)
//   detail block, version 3 only, 64 bytes at offset 128 (Octree::Detail)
//       0    4  u32 octaves           [1, 32]
//       4    4  u32 seed
//       8    4  f32 amplitude         finite, > 0, <= wavelength
//      12    4  f32 wavelength        finite, > 0, <= size
//      16    4  f32 gain              (0, 1]
//      20   12  f32 colour_slope[3]   finite
//      32   32  zero
//   version 4: the same detail block, whose octaves may be 0 (no detail),
//   then the material block at offset 192 (Octree::materials):
//       0    4  u32 count             [1, 255]
//       4    4  u32 bytes             of the block before its padding
//       8       per material: u32 length in [1, 65536], then that many bytes
//               of JSON text (no NUL), back to back; they fill exactly `bytes`
//               then zeros up to a multiple of 8
//   A Material channel needs two or more materials.
//   version 5: the same detail and material blocks (whose count may then be
//   0: the block is 8 bytes), then the source block (Octree::source):
//       0    4  u32 bytes             [1, 65536]
//       4       that many bytes of JSON text (no NUL): where the octree came
//               from; then zeros up to a multiple of 8
//   channel table, channel_count entries of 32 bytes (at or after the end
//   of the header, of the detail block in version 3, of the material block in 4,
//   of the source block in 5)
//       0    4  u32 channel           Channel, unique within the file
//       4    4  u32 encoding          Encoding, encoding_fits(channel, encoding)
//       8    4  u32 bytes_per_sample  = encoding_bytes(encoding)
//      12    4  u32 reserved = 0
//      16    8  u64 data_offset       64-aligned; channel i starts at or after the end of channel i - 1
//      24    8  u64 data_bytes        = (brick_count * brick_size^3 + shell_count *
//                                         (3 brick_size^2 + 3 brick_size + 1)) * bytes_per_sample
//   depth table, depth_count + 1 entries of u32: Octree::depth_first_node
//   node table, node_count entries of 8 bytes: u32 children, u32 brick (Node)
//   brick data, one section per channel in table order, each 64-aligned:
//     brick b's samples are bytes [b * samples_per_brick * bytes_per_sample, ...)
//     of the section, x-fastest, then y, then z; samples_per_brick =
//     brick_size^3: the lattice points c * B + [0, B)^3 of the node's brick
//     (octree.h). Upper faces are not stored: sampler.h rebuilds them from
//     the neighbouring bricks. After all bricks, the shells of bricks 0 ..
//     shell_count - 1, 3B^2 + 3B + 1 samples each, in shell_index order:
//     the points of the brick's (B + 1)^3 block on its upper faces, read
//     where they lie on the domain's upper boundary.
// Sections come in this order, back to back: each starts at the smallest
// offset at or after the end of the previous one that has its alignment (the
// writer pads with zeros), and the file ends where the last section
// ends (file_bytes). The reader refuses any other placement, and a file_bytes
// that differs from the size on disk or from the end of the last section,
// before it reads or hashes any byte past the tables: a header that states
// more bytes than its sections need costs nothing to refuse.
// A flipped byte anywhere is caught by one of the two checksums.
//
// Tree rules the reader checks (and the writer refuses to break):
// depth_first_node[0] = 0, [1] = 1 (one root), non-decreasing, last =
// node_count, and every depth below the root holds whole tiles of 8 nodes.
// A node's `children` is kNone or the start of a tile (a multiple of 8 from
// the start of its depth) at the NEXT depth, so the tree has no cycles; no
// tile has two parents. A node's `brick` is kNone or < brick_count, and no
// brick belongs to two nodes. The bricks of nodes on the domain's upper
// boundary (some coordinate 2^depth - 1 at their depth) are exactly bricks
// 0 .. shell_count - 1.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "svo/octree/files.h"
#include "svo/octree/octree.h"

namespace svo::octree {

// Any problem reading or writing a .svo file. The message is one line that
// starts with the path and says what is wrong.
// The same type as every file error of the engine (svo/octree/files.h).
using FileError = files::FileError;

// Checks the invariants of an in-memory octree that the file format relies on
// (header ranges, channels, brick data sizes, and the tree rules above).
// @throw std::invalid_argument naming the first broken rule.
void validate_octree(const Octree& tree);

// Writes `tree` to `path`: the bytes go to a temporary file in the same
// directory (`path` + ".tmp-<pid>-<n>"), which is flushed to disk and then
// renamed over `path`. A crash or an error never leaves a partial file under
// `path` nor alters an existing one; on error the temporary is removed.
// @throw std::invalid_argument when validate_octree(tree) fails (nothing is written).
// @throw FileError "<path>: cannot write: <step>: <strerror>" on any I/O failure.
void write_svo(const std::string& path, const Octree& tree);

// A validated .svo image held in memory by someone else. Safe for untrusted
// input: the constructor checks every field, count, offset and both checksums
// before anything is exposed, and never reads outside `bytes`. The spans it
// hands out point into `bytes`, which must outlive the view.
class SvoView {
 public:
  // @param bytes  the whole file; bytes.data() aligned to 4 (mmap and
  //               operator new are), else std::invalid_argument.
  // @param name   used in error messages (normally the path).
  // @throw FileError "<name>: <what is wrong>", one line.
  SvoView(std::span<const uint8_t> bytes, std::string name);

  const std::string& name() const { return name_; }
  uint64_t file_bytes() const { return bytes_.size(); }
  // 3: with the detail block, 4: with materials, 5: with a source block
  uint32_t version() const {
    return !shape_.source.empty() ? 5 : !shape_.materials.empty() ? 4 : shape_.detail.octaves > 0 ? 3 : 2;
  }

  // The header's scalar fields, channels and depth table, as an Octree with
  // no nodes and no brick data (its brick_count is set).
  const Octree& shape() const { return shape_; }
  uint32_t brick_size() const { return shape_.brick_size; }
  uint32_t depth_count() const { return shape_.depth_count; }
  const std::vector<ChannelInfo>& channels() const { return shape_.channels; }
  const std::vector<uint32_t>& depth_first_node() const { return shape_.depth_first_node; }
  uint64_t brick_count() const { return shape_.brick_count; }
  uint64_t voxel_count() const { return shape_.voxel_count(); }

  std::span<const Node> nodes() const { return nodes_; }
  // Channel c's whole brick pool, as stored; c < channels().size().
  std::span<const uint8_t> brick_data(size_t c) const { return brick_data_.at(c); }
  // One brick of channel c: samples_per_brick() * encoding_bytes bytes (its shell, if any, is in brick_data(c)).
  // @throw std::out_of_range when c or brick is out of range.
  std::span<const uint8_t> brick(size_t c, uint64_t brick) const;
  // Where channel c's pool starts in the file (for reading bricks on demand).
  uint64_t brick_data_offset(size_t c) const { return brick_offsets_.at(c); }

  // A full in-memory copy.
  Octree copy() const;

 private:
  std::span<const uint8_t> bytes_;
  std::string name_;
  Octree shape_;
  std::span<const Node> nodes_;
  std::vector<std::span<const uint8_t>> brick_data_;
  std::vector<uint64_t> brick_offsets_;
};

// A .svo file mapped read-only and validated (as SvoView). The mapping lives
// as long as this object; the file must not be truncated in place while
// mapped (write_svo replaces files by rename, which is safe).
class MappedSvo {
 public:
  // @throw FileError "<path>: <what is wrong>" (cannot open, not a regular
  //        file, or any validation failure of SvoView).
  explicit MappedSvo(const std::string& path);
  ~MappedSvo();
  MappedSvo(MappedSvo&& other) noexcept;
  MappedSvo& operator=(MappedSvo&&) = delete;
  MappedSvo(const MappedSvo&) = delete;
  MappedSvo& operator=(const MappedSvo&) = delete;

  const SvoView& view() const { return *view_; }
  const SvoView* operator->() const { return view_.get(); }

 private:
  void* map_ = nullptr;
  size_t map_bytes_ = 0;
  std::unique_ptr<SvoView> view_;
};

// Reads and validates `path` (through MappedSvo) and returns a copy.
// Safe for untrusted input. @throw FileError as MappedSvo.
Octree load_svo(const std::string& path);

}  // namespace svo::octree
