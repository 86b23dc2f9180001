#include "svo_format.h"

#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>

namespace svo::octree::format {

static_assert(std::endian::native == std::endian::little, "the .svo reader maps nodes in place: little-endian hosts");
static_assert(sizeof(Node) == kNodeBytes && alignof(Node) == 4, "Node is the on-disk node record");

uint32_t get_u32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}
uint64_t get_u64(const uint8_t* p) {
  uint64_t v;
  std::memcpy(&v, p, 8);
  return v;
}
float get_f32(const uint8_t* p) { return std::bit_cast<float>(get_u32(p)); }
void put_u32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
void put_u64(uint8_t* p, uint64_t v) { std::memcpy(p, &v, 8); }
void put_f32(uint8_t* p, float v) { put_u32(p, std::bit_cast<uint32_t>(v)); }

void encode_header(const Header& h, uint8_t* out) {
  std::memset(out, 0, kHeaderBytes);
  std::memcpy(out + at::magic, kMagic, 8);
  put_u32(out + at::version, h.version);
  put_u32(out + at::header_bytes, h.header_bytes);
  put_u32(out + at::brick_size, h.brick_size);
  put_u32(out + at::depth_count, h.depth_count);
  for (int i = 0; i < 3; ++i) put_f32(out + at::origin + 4 * i, h.origin[i]);
  put_f32(out + at::size, h.size);
  put_f32(out + at::sigma_rho2, h.sigma_rho2);
  for (int i = 0; i < 3; ++i) put_f32(out + at::constant_colour + 4 * i, h.constant_colour[i]);
  put_u32(out + at::channel_count, h.channel_count);
  put_u32(out + at::shell_count, h.shell_count);
  put_u64(out + at::node_count, h.node_count);
  put_u64(out + at::brick_count, h.brick_count);
  put_u64(out + at::channel_table, h.channel_table_offset);
  put_u64(out + at::depth_table, h.depth_table_offset);
  put_u64(out + at::node_table, h.node_table_offset);
  put_u64(out + at::file_bytes, h.file_bytes);
  put_u64(out + at::payload_checksum, h.payload_checksum);
  put_u64(out + at::header_checksum, h.header_checksum);
}

Header decode_header(const uint8_t* in) {
  Header h;
  h.version = get_u32(in + at::version);
  h.header_bytes = get_u32(in + at::header_bytes);
  h.brick_size = get_u32(in + at::brick_size);
  h.depth_count = get_u32(in + at::depth_count);
  for (int i = 0; i < 3; ++i) h.origin[i] = get_f32(in + at::origin + 4 * i);
  h.size = get_f32(in + at::size);
  h.sigma_rho2 = get_f32(in + at::sigma_rho2);
  for (int i = 0; i < 3; ++i) h.constant_colour[i] = get_f32(in + at::constant_colour + 4 * i);
  h.channel_count = get_u32(in + at::channel_count);
  h.shell_count = get_u32(in + at::shell_count);
  h.node_count = get_u64(in + at::node_count);
  h.brick_count = get_u64(in + at::brick_count);
  h.channel_table_offset = get_u64(in + at::channel_table);
  h.depth_table_offset = get_u64(in + at::depth_table);
  h.node_table_offset = get_u64(in + at::node_table);
  h.file_bytes = get_u64(in + at::file_bytes);
  h.payload_checksum = get_u64(in + at::payload_checksum);
  h.header_checksum = get_u64(in + at::header_checksum);
  return h;
}

void encode_channel(const ChannelEntry& e, uint8_t* out) {
  put_u32(out + 0, e.channel);
  put_u32(out + 4, e.encoding);
  put_u32(out + 8, e.bytes_per_sample);
  put_u32(out + 12, e.reserved);
  put_u64(out + 16, e.data_offset);
  put_u64(out + 24, e.data_bytes);
}

ChannelEntry decode_channel(const uint8_t* in) {
  return {get_u32(in + 0), get_u32(in + 4), get_u32(in + 8), get_u32(in + 12), get_u64(in + 16), get_u64(in + 24)};
}

uint64_t checksum(std::span<const uint8_t> bytes) { return XXH64(bytes.data(), bytes.size(), 0); }

void seal(std::span<uint8_t> file) {
  put_u64(file.data() + at::payload_checksum, checksum(file.subspan(kHeaderBytes)));
  put_u64(file.data() + at::header_checksum, checksum(file.first(at::header_checksum)));
}

void encode_detail(const Detail& d, uint8_t* out) {
  std::memset(out, 0, kDetailBytes);
  put_u32(out + 0, d.octaves);
  put_u32(out + 4, d.seed);
  put_f32(out + 8, d.amplitude);
  put_f32(out + 12, d.wavelength);
  put_f32(out + 16, d.gain);
  for (int i = 0; i < 3; ++i) put_f32(out + 20 + 4 * i, d.colour_slope[i]);
}

Detail decode_detail(const uint8_t* in) {
  Detail d;
  d.octaves = get_u32(in + 0);
  d.seed = get_u32(in + 4);
  d.amplitude = get_f32(in + 8);
  d.wavelength = get_f32(in + 12);
  d.gain = get_f32(in + 16);
  for (int i = 0; i < 3; ++i) d.colour_slope[i] = get_f32(in + 20 + 4 * i);
  return d;
}

std::string check_detail(const Detail& d, float size) {
  auto u = [](uint64_t v) { return std::to_string(v); };
  if (d.octaves < 1 || d.octaves > kMaxDetailOctaves) {
    return "detail octaves is " + u(d.octaves) + " (must be in [1, " + u(kMaxDetailOctaves) + "])";
  }
  if (!std::isfinite(d.wavelength) || !(d.wavelength > 0) || !(d.wavelength <= size)) {
    return "detail wavelength is " + str(d.wavelength) + " (must be finite, > 0 and at most the domain's size)";
  }
  if (!std::isfinite(d.amplitude) || !(d.amplitude > 0) || !(d.amplitude <= d.wavelength)) {
    return "detail amplitude is " + str(d.amplitude) + " (must be finite, > 0 and at most the wavelength)";
  }
  if (!std::isfinite(d.gain) || !(d.gain > 0) || !(d.gain <= 1)) {
    return "detail gain is " + str(d.gain) + " (must be in (0, 1])";
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(d.colour_slope[i])) {
      return "detail colour_slope[" + u(i) + "] is " + str(d.colour_slope[i]) + " (must be finite)";
    }
  }
  return {};
}

std::vector<uint8_t> encode_materials(const std::vector<std::string>& materials) {
  std::vector<uint8_t> out(8);
  put_u32(out.data(), uint32_t(materials.size()));
  for (const std::string& m : materials) {
    size_t at = out.size();
    out.resize(at + 4 + m.size());
    put_u32(out.data() + at, uint32_t(m.size()));
    std::memcpy(out.data() + at + 4, m.data(), m.size());
  }
  put_u32(out.data() + 4, uint32_t(out.size()));
  out.resize(align_up(out.size(), kTableAlign));
  return out;
}

std::string check_materials(const std::vector<std::string>& materials) {
  auto u = [](uint64_t v) { return std::to_string(v); };
  if (materials.empty() || materials.size() > kMaxMaterials) {
    return "material count is " + u(materials.size()) + " (must be in [1, " + u(kMaxMaterials) + "])";
  }
  for (size_t i = 0; i < materials.size(); ++i) {
    const std::string& m = materials[i];
    if (m.empty() || m.size() > kMaxMaterialBytes) {
      return "material " + u(i) + " has " + u(m.size()) + " bytes (must be in [1, " + u(kMaxMaterialBytes) + "])";
    }
    if (m.find('\0') != std::string::npos) return "material " + u(i) + " holds a NUL byte (must be JSON text)";
  }
  return {};
}

std::vector<uint8_t> encode_source(const std::string& source) {
  std::vector<uint8_t> out(4 + source.size());
  put_u32(out.data(), uint32_t(source.size()));
  std::memcpy(out.data() + 4, source.data(), source.size());
  out.resize(align_up(out.size(), kTableAlign));
  return out;
}

std::string check_source(const std::string& source) {
  if (source.empty() || source.size() > kMaxSourceBytes) {
    return "source block has " + std::to_string(source.size()) + " bytes of text (must be in [1, " +
           std::to_string(kMaxSourceBytes) + "])";
  }
  if (source.find('\0') != std::string::npos) return "source block holds a NUL byte (must be JSON text)";
  return {};
}

Layout plan_layout(const Octree& tree) {
  Layout l;
  l.version = !tree.source.empty()      ? kVersionSource
              : !tree.materials.empty() ? kVersionMaterials
              : tree.detail.octaves > 0 ? kVersionDetail
                                        : kVersion;
  l.channel_table = kHeaderBytes + (l.version >= kVersionDetail ? kDetailBytes : 0);
  if (l.version >= kVersionMaterials) {
    l.materials = l.channel_table;
    l.material_bytes = encode_materials(tree.materials).size();
    l.channel_table += l.material_bytes;
  }
  if (l.version >= kVersionSource) {
    l.source = l.channel_table;
    l.source_bytes = encode_source(tree.source).size();
    l.channel_table += l.source_bytes;
  }
  l.depth_table = align_up(l.channel_table + kChannelEntryBytes * tree.channels.size(), kTableAlign);
  l.node_table = align_up(l.depth_table + 4 * tree.depth_first_node.size(), kDataAlign);
  uint64_t end = l.node_table + kNodeBytes * tree.nodes.size();
  for (const ChannelInfo& c : tree.channels) {
    l.data_offset.push_back(align_up(end, kDataAlign));
    l.data_bytes.push_back(tree.pool_samples() * encoding_bytes(c.encoding));
    end = l.data_offset.back() + l.data_bytes.back();
  }
  l.file_bytes = end;
  return l;
}

std::string str(float v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string channel_label(size_t index, const ChannelInfo& c) {
  return "channel " + std::to_string(index) + " (" + channel_name(c.channel) + ")";
}

std::string check_shape(const Octree& t) {
  auto u = [](uint64_t v) { return std::to_string(v); };
  if (t.brick_size < kMinBrickSize || t.brick_size > kMaxBrickSize || !std::has_single_bit(t.brick_size)) {
    return "brick_size is " + u(t.brick_size) + " (must be a power of two in [2, 32])";
  }
  if (t.depth_count < 1 || t.depth_count > kMaxDepths) {
    return "depth_count is " + u(t.depth_count) + " (must be in [1, 16])";
  }
  uint64_t resolution = uint64_t(t.brick_size) << (t.depth_count - 1);
  if (resolution > kMaxResolution) {
    return "finest resolution brick_size << (depth_count - 1) is " + u(resolution) + " (at most 65536)";
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(t.origin[i])) return "origin[" + u(i) + "] is " + str(t.origin[i]) + " (must be finite)";
    if (!std::isfinite(t.constant_colour[i])) {
      return "constant_colour[" + u(i) + "] is " + str(t.constant_colour[i]) + " (must be finite)";
    }
  }
  if (!std::isfinite(t.size) || !(t.size > 0)) return "size is " + str(t.size) + " (must be finite and > 0)";
  float largest = 0;  // the domain's largest |coordinate|
  for (int i = 0; i < 3; ++i) {
    const float end = t.origin[i] + t.size;
    largest = std::max({largest, std::abs(t.origin[i]), std::abs(end)});
    if (!(std::abs(t.origin[i]) <= kMaxDomainCoordinate && std::abs(end) <= kMaxDomainCoordinate)) {
      return "the domain [origin, origin + size] spans [" + str(t.origin[i]) + ", " + str(end) + "] on axis " + u(i) +
             " (origin and origin + size must be within +-" + str(kMaxDomainCoordinate) + ")";
    }
  }
  const float voxel = t.voxel_size(t.depth_count - 1);
  if (!(voxel >= kMinVoxelSize) || !(voxel >= kMinVoxelRelative * largest)) {
    return "size " + str(t.size) + " is too small to render: the finest voxel (size / " + u(resolution) + " = " +
           str(voxel) + ") must be at least " + str(kMinVoxelSize) + " and at least 2^-23 of the domain's largest " +
           "coordinate " + str(largest) + " (float precision)";
  }
  if (!std::isfinite(t.sigma_rho2) || !(t.sigma_rho2 >= 0)) {
    return "sigma_rho2 is " + str(t.sigma_rho2) + " (must be finite and >= 0)";
  }
  if (t.channels.size() > kMaxChannels) return "channel count is " + u(t.channels.size()) + " (at most 16)";
  for (size_t i = 0; i < t.channels.size(); ++i) {
    const ChannelInfo& c = t.channels[i];
    std::string label = "channel " + u(i);
    if (std::string(channel_name(c.channel)) == "unknown") {
      return label + ": unknown channel id " + u(uint32_t(c.channel));
    }
    label += std::string(" (") + channel_name(c.channel) + ")";
    if (encoding_bytes(c.encoding) == 0) return label + ": unknown encoding id " + u(uint32_t(c.encoding));
    if (!encoding_fits(c.channel, c.encoding)) {
      return label + ": encoding " + encoding_name(c.encoding) + " cannot store this channel";
    }
    for (size_t j = 0; j < i; ++j) {
      if (t.channels[j].channel == c.channel) return label + ": same channel as channel " + u(j);
    }
  }
  return {};
}

std::string check_tree(std::span<const uint32_t> first, std::span<const Node> nodes, uint64_t brick_count,
                       uint64_t shell_count) {
  auto u = [](uint64_t v) { return std::to_string(v); };
  size_t depth_count = first.size() - 1;
  if (first[0] != 0 || first[1] != 1) {
    return "depth table starts " + u(first[0]) + ", " + u(first[1]) + " (must be 0, 1: one root node)";
  }
  for (size_t d = 1; d < depth_count; ++d) {
    if (first[d + 1] < first[d] || (first[d + 1] - first[d]) % 8 != 0) {
      return "depth table: depth " + u(d) + " spans nodes [" + u(first[d]) + ", " + u(first[d + 1]) +
             ") (must be a whole number of 8-node tiles)";
    }
  }
  if (first[depth_count] != nodes.size()) {
    return "depth table ends at " + u(first[depth_count]) + " but there are " + u(nodes.size()) + " nodes";
  }
  if (brick_count > nodes.size()) {
    return "brick_count " + u(brick_count) + " exceeds node count " + u(nodes.size());
  }
  if (shell_count > brick_count) {
    return "shell_count " + u(shell_count) + " exceeds brick_count " + u(brick_count);
  }
  std::vector<uint8_t> tile_used((nodes.size() - 1) / 8, 0);
  std::vector<uint8_t> brick_used(brick_count, 0);
  // Node coordinates, parents before children (tiles have one parent each, checked before use).
  std::vector<glm::ivec3> coords(nodes.size(), glm::ivec3(0));
  for (size_t d = 0; d < depth_count; ++d) {
    uint64_t lo = d + 1 < depth_count ? first[d + 1] : 0, hi = d + 1 < depth_count ? first[d + 2] : 0;
    for (uint64_t i = first[d]; i < first[d + 1]; ++i) {
      const Node& n = nodes[i];
      std::string where = "node " + u(i) + " (depth " + u(d) + ")";
      if (n.children != kNone) {
        if (n.children < lo || n.children >= hi || (n.children - lo) % 8 != 0) {
          return where + ": children " + u(n.children) + " is not a tile start at depth " + u(d + 1) +
                 (lo < hi ? " (tiles start at " + u(lo) + " + 8k, below " + u(hi) + ")" : " (there is none)");
        }
        uint8_t& used = tile_used[(n.children - 1) / 8];
        if (used) return where + ": children " + u(n.children) + " already belong to another node";
        used = 1;
        for (uint32_t k = 0; k < 8; ++k) {
          coords[n.children + k] = coords[i] * 2 + glm::ivec3(int(k & 1), int((k >> 1) & 1), int((k >> 2) & 1));
        }
      }
      if (n.brick != kNone) {
        if (n.brick >= brick_count) {
          return where + ": brick " + u(n.brick) + " out of range (brick_count " + u(brick_count) + ")";
        }
        if (brick_used[n.brick]) return where + ": brick " + u(n.brick) + " already belongs to another node";
        brick_used[n.brick] = 1;
        const bool boundary = on_upper_boundary(uint32_t(d), coords[i]);
        if (boundary != (n.brick < shell_count)) {
          return where + ": brick " + u(n.brick) +
                 (boundary ? " lies on the domain's upper boundary, so it needs a shell, but shell_count is "
                           : " has a shell (shell_count is ") +
                 u(shell_count) +
                 (boundary ? " (bricks with shells come first)"
                           : ") but the node is not on the domain's upper boundary");
        }
      }
    }
  }
  return {};
}

}  // namespace svo::octree::format
