// Reading .svo files: validation of untrusted bytes (SvoView), the read-only
// memory map (MappedSvo) and the copying loader.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <utility>

#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo_format.h"

namespace svo::octree {

namespace {

using namespace format;

std::string u(uint64_t v) { return std::to_string(v); }

// Magic bytes for a message: printable ASCII as is, the rest as \xNN.
std::string printable(const uint8_t* p, size_t n) {
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    if (p[i] >= 0x20 && p[i] < 0x7F && p[i] != '\\') {
      s += char(p[i]);
    } else {
      static const char* hex = "0123456789ABCDEF";
      s += std::string("\\x") + hex[p[i] >> 4] + hex[p[i] & 15];
    }
  }
  return s;
}

// Checks the section [offset, offset + count * unit) against the file size,
// the end of the previous section and its alignment, and that it starts
// right there (at the first multiple of `align` at or after previous_end),
// so that no byte of the file lies outside the sections; returns its end.
// Uses only header and table values: no byte of the section is read.
uint64_t check_section(const std::string& name, uint64_t file_size, const std::string& what, uint64_t offset,
                       uint64_t count, uint64_t unit, uint64_t previous_end, uint64_t align) {
  auto fail = [&](const std::string& why) { throw FileError(name + ": " + why); };
  if (offset % align != 0) fail(what + " offset " + u(offset) + " is not a multiple of " + u(align));
  if (offset < previous_end) {
    fail(what + " offset " + u(offset) + " overlaps the previous section, which ends at " + u(previous_end));
  }
  uint64_t room = offset <= file_size ? file_size - offset : 0;
  if (count > room / unit) {
    std::string need = count <= std::numeric_limits<uint64_t>::max() / unit ? u(count * unit) + " bytes"
                                                                            : u(count) + " x " + u(unit) + " bytes";
    fail("truncated: " + what + " needs " + need + " at offset " + u(offset) + ", file has " + u(file_size));
  }
  if (const uint64_t expected = align_up(previous_end, align); offset != expected) {
    fail(what + " offset " + u(offset) + " leaves " + u(offset - previous_end) +
         " bytes unused after the previous section, which ends at " + u(previous_end) + " (sections follow at " +
         u(expected) + ", the next multiple of " + u(align) + ")");
  }
  return offset + count * unit;
}

}  // namespace

SvoView::SvoView(std::span<const uint8_t> bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {
  auto fail = [&](const std::string& why) { throw FileError(name_ + ": " + why); };
  const uint64_t n = bytes.size();
  const uint8_t* p = bytes.data();
  if (n < kHeaderBytes) fail("truncated: header needs 128 bytes at offset 0, file has " + u(n));
  if (reinterpret_cast<uintptr_t>(p) % alignof(Node) != 0) {
    throw std::invalid_argument(name_ + ": SvoView needs a buffer aligned to " + u(alignof(Node)) + " bytes");
  }
  if (std::memcmp(p, kMagic, 8) != 0) {
    fail("not an .svo file (magic is '" + printable(p, 8) + "', expected 'SVOCTREE')");
  }
  Header h = decode_header(p);
  if (h.version < kVersion || h.version > kVersionSource) {
    fail("unsupported version " + u(h.version) + " (this build reads versions " + u(kVersion) + " to " +
         u(kVersionSource) + ")");
  }
  if (h.header_bytes != kHeaderBytes) {
    fail("header_bytes is " + u(h.header_bytes) + " (version " + u(h.version) + " has 128)");
  }
  uint64_t header_sum = checksum(bytes.first(at::header_checksum));
  if (header_sum != h.header_checksum) {
    fail("corrupt header: checksum is " + u(header_sum) + ", header records " + u(h.header_checksum));
  }

  // Header-level values; the channel list is added after its table is bounded.
  shape_.brick_size = h.brick_size;
  shape_.depth_count = h.depth_count;
  shape_.origin = {h.origin[0], h.origin[1], h.origin[2]};
  shape_.size = h.size;
  shape_.sigma_rho2 = h.sigma_rho2;
  shape_.constant_colour = {h.constant_colour[0], h.constant_colour[1], h.constant_colour[2]};
  if (h.channel_count > kMaxChannels) fail("channel_count is " + u(h.channel_count) + " (at most 16)");

  if (h.node_count < 1 || h.node_count >= kNone) {
    fail("node_count is " + u(h.node_count) + " (must be in [1, 2^32 - 1))");
  }
  if (h.brick_count > h.node_count) {
    fail("brick_count " + u(h.brick_count) + " exceeds node_count " + u(h.node_count));
  }
  if (h.shell_count > h.brick_count) {
    fail("shell_count " + u(h.shell_count) + " exceeds brick_count " + u(h.brick_count));
  }
  shape_.brick_count = h.brick_count;
  shape_.shell_count = h.shell_count;

  uint64_t end = kHeaderBytes;
  if (h.version >= kVersionDetail) {
    if (n < kHeaderBytes + kDetailBytes) {
      fail("truncated: detail block needs 64 bytes at offset 128, file has " + u(n));
    }
    shape_.detail = decode_detail(p + kHeaderBytes);
    end += kDetailBytes;
  }
  if (h.version >= kVersionMaterials) {
    // u32 count, u32 bytes (of the block before its padding), then per
    // material u32 length and the JSON text; padded with zeros to 8 bytes.
    // Version 5 has the block even without materials (count 0).
    if (n < end + 8) fail("truncated: material block needs 8 bytes at offset " + u(end) + ", file has " + u(n));
    const uint32_t count = get_u32(p + end), bytes = get_u32(p + end + 4);
    const uint32_t fewest = h.version >= kVersionSource ? 0 : 1;
    if (count < fewest || count > kMaxMaterials) {
      fail("material count is " + u(count) + " (must be in [" + u(fewest) + ", " + u(kMaxMaterials) + "])");
    }
    if (bytes < 8 + 4 * uint64_t(count) || bytes > n - end) {
      fail("material block of " + u(bytes) + " bytes at offset " + u(end) + " does not fit " + u(count) +
           " materials in a file of " + u(n) + " bytes");
    }
    uint64_t at = end + 8;
    for (uint32_t i = 0; i < count; ++i) {
      if (at + 4 > end + bytes) fail("material block: material " + u(i) + " starts past the block's end");
      const uint32_t length = get_u32(p + at);
      if (length < 1 || length > kMaxMaterialBytes) {
        fail("material " + u(i) + " has " + u(length) + " bytes (must be in [1, " + u(kMaxMaterialBytes) + "])");
      }
      if (length > end + bytes - at - 4) {
        fail("material block: material " + u(i) + " has " + u(length) + " bytes, past the block's end");
      }
      shape_.materials.emplace_back(reinterpret_cast<const char*>(p + at + 4), length);
      at += 4 + length;
    }
    if (at != end + bytes) fail("material block: " + u(end + bytes - at) + " bytes after the last material");
    if (count > 0) {
      if (std::string why = check_materials(shape_.materials); !why.empty()) fail(why);
    }
    end = align_up(end + bytes, kTableAlign);
  }
  if (h.version >= kVersionSource) {
    // u32 bytes, then that much JSON text; padded with zeros to 8 bytes.
    if (n < end + 4) fail("truncated: source block needs 4 bytes at offset " + u(end) + ", file has " + u(n));
    const uint32_t bytes = get_u32(p + end);
    if (bytes < 1 || bytes > kMaxSourceBytes) {
      fail("source block states " + u(bytes) + " bytes of text (must be in [1, " + u(kMaxSourceBytes) + "])");
    }
    if (bytes > n - end - 4) {
      fail("source block of " + u(bytes) + " bytes at offset " + u(end) + " does not fit in a file of " + u(n) +
           " bytes");
    }
    shape_.source.assign(reinterpret_cast<const char*>(p + end + 4), bytes);
    if (std::string why = check_source(shape_.source); !why.empty()) fail(why);
    end = align_up(end + 4 + uint64_t(bytes), kTableAlign);
  }
  end = check_section(name_, n, "channel table", h.channel_table_offset, h.channel_count, kChannelEntryBytes, end,
                      kTableAlign);
  std::vector<ChannelEntry> entries;
  for (uint32_t i = 0; i < h.channel_count; ++i) {
    entries.push_back(decode_channel(p + h.channel_table_offset + i * kChannelEntryBytes));
    shape_.channels.push_back({Channel(entries.back().channel), Encoding(entries.back().encoding)});
  }
  if (std::string why = check_shape(shape_); !why.empty()) fail(why);
  if (h.version == kVersionDetail || (h.version >= kVersionMaterials && shape_.detail.octaves != 0)) {
    if (std::string why = check_detail(shape_.detail, shape_.size); !why.empty()) fail(why);
  }
  if (const int m = shape_.channel_index(Channel::Material); m >= 0 && shape_.materials.size() < 2) {
    fail(channel_label(size_t(m), shape_.channels[size_t(m)]) +
         ": a material channel needs two or more materials, the file has " + u(shape_.materials.size()));
  }

  end = check_section(name_, n, "depth table", h.depth_table_offset, uint64_t(h.depth_count) + 1, 4, end, kTableAlign);
  end = check_section(name_, n, "node table", h.node_table_offset, h.node_count, kNodeBytes, end, kDataAlign);
  // brick_size <= 32: at most 32768 + 3169 samples per brick, so no overflow below.
  const uint64_t samples = shape_.pool_samples();
  for (size_t c = 0; c < entries.size(); ++c) {
    const ChannelEntry& e = entries[c];
    std::string label = channel_label(c, shape_.channels[c]);
    uint32_t sample_bytes = encoding_bytes(shape_.channels[c].encoding);
    if (e.bytes_per_sample != sample_bytes) {
      fail(label + ": bytes_per_sample is " + u(e.bytes_per_sample) + ", " +
           encoding_name(shape_.channels[c].encoding) + " has " + u(sample_bytes));
    }
    if (e.reserved != 0) fail(label + ": reserved field is " + u(e.reserved) + " (must be 0)");
    uint64_t expected = samples * sample_bytes;  // < 2^32 * 2^16 * 4: no overflow
    if (e.data_bytes != expected) {
      fail(label + ": data_bytes is " + u(e.data_bytes) +
           ", expected (brick_count * samples_per_brick + shell_count * shell_samples) * " + u(sample_bytes) + " = " +
           u(expected));
    }
    end = check_section(name_, n, label + " brick data", e.data_offset, e.data_bytes, 1, end, kDataAlign);
    brick_data_.push_back(bytes.subspan(e.data_offset, e.data_bytes));
    brick_offsets_.push_back(e.data_offset);
  }
  // Sizes against each other before any byte past the tables is read or hashed:
  // a stated size that the sections do not need is refused here, in time
  // independent of the file's size.
  if (h.file_bytes > n) fail("truncated: header records " + u(h.file_bytes) + " bytes, file has " + u(n));
  if (h.file_bytes < n) fail("file has " + u(n) + " bytes but its header records " + u(h.file_bytes));
  if (h.file_bytes != end) {
    fail("header records " + u(h.file_bytes) + " bytes but the sections end at " + u(end) + " (" +
         u(h.file_bytes - end) + " bytes after the last section)");
  }
  uint64_t payload_sum = checksum(bytes.subspan(kHeaderBytes));
  if (payload_sum != h.payload_checksum) {
    fail("corrupt data: checksum of bytes [128, " + u(n) + ") is " + u(payload_sum) + ", header records " +
         u(h.payload_checksum));
  }

  for (uint64_t d = 0; d <= h.depth_count; ++d) {
    shape_.depth_first_node.push_back(get_u32(p + h.depth_table_offset + 4 * d));
  }
  nodes_ = {reinterpret_cast<const Node*>(p + h.node_table_offset), size_t(h.node_count)};
  if (std::string why = check_tree(shape_.depth_first_node, nodes_, h.brick_count, h.shell_count); !why.empty()) {
    fail(why);
  }
}

std::span<const uint8_t> SvoView::brick(size_t c, uint64_t b) const {
  if (c >= brick_data_.size() || b >= brick_count()) {
    throw std::out_of_range(name_ + ": brick " + u(b) + " of channel " + u(c) + " out of range");
  }
  uint64_t bytes = uint64_t(shape_.samples_per_brick()) * encoding_bytes(shape_.channels[c].encoding);
  return brick_data_[c].subspan(b * bytes, bytes);
}

Octree SvoView::copy() const {
  Octree t = shape_;
  t.nodes.assign(nodes_.begin(), nodes_.end());
  for (const auto& data : brick_data_) t.brick_data.emplace_back(data.begin(), data.end());
  return t;
}

MappedSvo::MappedSvo(const std::string& path) {
  auto fail = [&](const std::string& why) { throw FileError(path + ": " + why); };
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) fail(std::string("cannot open: ") + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    int err = errno;
    ::close(fd);
    fail(std::string("cannot stat: ") + std::strerror(err));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    fail("is " + files::file_kind_of_mode(st.st_mode) + ", expected a .svo file");
  }
  size_t size = size_t(st.st_size);
  if (size > 0) {
    void* map = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
    int err = errno;
    ::close(fd);
    if (map == MAP_FAILED) fail(std::string("cannot map: ") + std::strerror(err));
    map_ = map;
    map_bytes_ = size;
  } else {
    ::close(fd);
  }
  try {
    view_ = std::make_unique<SvoView>(std::span<const uint8_t>(static_cast<const uint8_t*>(map_), map_bytes_), path);
  } catch (...) {
    if (map_) ::munmap(map_, map_bytes_);
    throw;
  }
}

MappedSvo::MappedSvo(MappedSvo&& other) noexcept
    : map_(std::exchange(other.map_, nullptr)),
      map_bytes_(std::exchange(other.map_bytes_, 0)),
      view_(std::move(other.view_)) {}

MappedSvo::~MappedSvo() {
  if (map_) ::munmap(map_, map_bytes_);
}

Octree load_svo(const std::string& path) { return MappedSvo(path).view().copy(); }

}  // namespace svo::octree
