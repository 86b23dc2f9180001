// Writing .svo files: temporary file, streamed payload with its checksum,
// header last, fsync, rename.
#include <fcntl.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo_format.h"

namespace svo::octree {

namespace {

using namespace format;

[[noreturn]] void io_fail(const std::string& path, const std::string& step, int err) {
  throw FileError(path + ": cannot write: " + step + ": " + std::strerror(err));
}

// Buffered sequential writer that hashes what it writes.
class Stream {
 public:
  explicit Stream(files::OutputFile& file) : file_(file), state_(XXH64_createState()) {
    if (!state_) throw std::bad_alloc();
    XXH64_reset(state_.get(), 0);
    buffer_.reserve(kBuffer);
  }
  void put(const void* data, size_t n) {
    if (n == 0) return;
    XXH64_update(state_.get(), data, n);
    offset_ += n;
    const uint8_t* p = static_cast<const uint8_t*>(data);
    if (buffer_.size() + n > kBuffer) flush();
    if (n >= kBuffer) return write_all(p, n);
    buffer_.insert(buffer_.end(), p, p + n);
  }
  void pad_to(uint64_t offset) {
    static const uint8_t zeros[kDataAlign] = {};
    while (offset_ < offset) put(zeros, size_t(std::min<uint64_t>(offset - offset_, sizeof zeros)));
  }
  void flush() {
    write_all(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  uint64_t offset() const { return offset_; }
  uint64_t digest() const { return XXH64_digest(state_.get()); }

 private:
  static constexpr size_t kBuffer = size_t(1) << 20;
  struct FreeState {
    void operator()(XXH64_state_t* s) const { XXH64_freeState(s); }
  };
  void write_all(const uint8_t* p, size_t n) { file_.write(p, n); }

  files::OutputFile& file_;
  std::unique_ptr<XXH64_state_t, FreeState> state_;
  std::vector<uint8_t> buffer_;
  uint64_t offset_ = kHeaderBytes;  // the header is written last, at offset 0
};

}  // namespace

void validate_octree(const Octree& t) {
  auto fail = [](const std::string& why) { throw std::invalid_argument("invalid octree: " + why); };
  if (std::string why = check_shape(t); !why.empty()) fail(why);
  if (t.detail.octaves > 0) {
    if (std::string why = check_detail(t.detail, t.size); !why.empty()) fail(why);
  }
  if (!t.source.empty()) {
    if (std::string why = check_source(t.source); !why.empty()) fail(why);
  }
  if (!t.materials.empty()) {
    if (std::string why = check_materials(t.materials); !why.empty()) fail(why);
  }
  if (t.channel_index(Channel::Material) >= 0 && t.materials.size() < 2) {
    fail("a material channel needs two or more materials, the octree has " + std::to_string(t.materials.size()));
  }
  if (t.depth_first_node.size() != size_t(t.depth_count) + 1) {
    fail("depth_first_node has " + std::to_string(t.depth_first_node.size()) +
         " entries, depth_count + 1 = " + std::to_string(t.depth_count + 1));
  }
  if (t.brick_data.size() != t.channels.size()) {
    fail("brick_data has " + std::to_string(t.brick_data.size()) + " pools for " + std::to_string(t.channels.size()) +
         " channels");
  }
  if (t.nodes.size() >= kNone || t.brick_count > t.nodes.size() || t.shell_count > t.brick_count) {
    fail(std::to_string(t.nodes.size()) + " nodes, " + std::to_string(t.brick_count) + " bricks and " +
         std::to_string(t.shell_count) + " shells (need nodes < 2^32 - 1 and shells <= bricks <= nodes)");
  }
  for (size_t c = 0; c < t.channels.size(); ++c) {
    uint64_t expected = t.pool_samples() * encoding_bytes(t.channels[c].encoding);
    if (t.brick_data[c].size() != expected) {
      fail(channel_label(c, t.channels[c]) + ": brick_data has " + std::to_string(t.brick_data[c].size()) +
           " bytes, (brick_count * samples_per_brick + shell_count * shell_samples) * bytes = " +
           std::to_string(expected));
    }
  }
  if (std::string why = check_tree(t.depth_first_node, t.nodes, t.brick_count, t.shell_count); !why.empty()) {
    fail(why);
  }
}

void write_svo(const std::string& path, const Octree& tree) {
  validate_octree(tree);
  const Layout layout = plan_layout(tree);

  files::OutputFile file(path);
  Stream out(file);
  // Skip the header for now: it carries the payload checksum, so it is written last.
  if (::lseek(file.fd(), off_t(kHeaderBytes), SEEK_SET) < 0) io_fail(path, "seeking in " + file.temporary(), errno);
  if (layout.version >= kVersionDetail) {
    uint8_t detail[kDetailBytes];
    encode_detail(tree.detail, detail);
    out.put(detail, sizeof detail);
  }
  if (layout.version >= kVersionMaterials) {
    std::vector<uint8_t> block = encode_materials(tree.materials);
    out.put(block.data(), block.size());
  }
  if (layout.version >= kVersionSource) {
    std::vector<uint8_t> block = encode_source(tree.source);
    out.put(block.data(), block.size());
  }

  for (size_t c = 0; c < tree.channels.size(); ++c) {
    const ChannelInfo& info = tree.channels[c];
    uint8_t entry[kChannelEntryBytes];
    encode_channel({uint32_t(info.channel), uint32_t(info.encoding), encoding_bytes(info.encoding), 0,
                    layout.data_offset[c], layout.data_bytes[c]},
                   entry);
    out.put(entry, sizeof entry);
  }
  out.pad_to(layout.depth_table);
  for (uint32_t first : tree.depth_first_node) {
    uint8_t b[4];
    put_u32(b, first);
    out.put(b, 4);
  }
  out.pad_to(layout.node_table);
  out.put(tree.nodes.data(), tree.nodes.size() * kNodeBytes);  // little-endian host (svo_format.cpp)
  for (size_t c = 0; c < tree.channels.size(); ++c) {
    out.pad_to(layout.data_offset[c]);
    out.put(tree.brick_data[c].data(), tree.brick_data[c].size());
  }
  out.pad_to(layout.file_bytes);
  out.flush();

  Header h;
  h.version = layout.version;
  h.brick_size = tree.brick_size;
  h.depth_count = tree.depth_count;
  for (int i = 0; i < 3; ++i) h.origin[i] = tree.origin[i], h.constant_colour[i] = tree.constant_colour[i];
  h.size = tree.size;
  h.sigma_rho2 = tree.sigma_rho2;
  h.channel_count = uint32_t(tree.channels.size());
  h.node_count = tree.nodes.size();
  h.brick_count = tree.brick_count;
  h.shell_count = uint32_t(tree.shell_count);
  h.channel_table_offset = layout.channel_table;
  h.depth_table_offset = layout.depth_table;
  h.node_table_offset = layout.node_table;
  h.file_bytes = layout.file_bytes;
  h.payload_checksum = out.digest();
  uint8_t header[kHeaderBytes];
  encode_header(h, header);
  put_u64(header + at::header_checksum, checksum({header, at::header_checksum}));
  file.write_at(header, kHeaderBytes, 0);
  file.commit();  // its test hook stalls before the rename
}

}  // namespace svo::octree
