#include "test_trees.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "svo_format.h"

namespace svo::octree::testing {

std::vector<ChannelInfo> all_encodings() {
  return {{Channel::Distance, Encoding::F32},
          {Channel::Normal, Encoding::Oct24},
          {Channel::HeightDev, Encoding::U8LogRelative},
          {Channel::SlopeDev, Encoding::U8LogSlope},
          {Channel::SlopeCov, Encoding::Cov3x8},
          {Channel::Colour, Encoding::Srgb8},
          {Channel::ColourSlope, Encoding::Signed8}};
}

void fill_random(std::vector<uint8_t>& bytes, uint64_t seed) {
  uint64_t x = seed;
  for (uint8_t& b : bytes) {
    uint64_t z = (x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    b = uint8_t(z ^ (z >> 31));
  }
}

Octree make_test_tree(uint64_t seed, uint32_t brick_size) {
  Octree t;
  t.brick_size = brick_size;
  t.depth_count = 3;
  t.origin = {-1.5f, 0.25f, 2.0f};
  t.size = 3.5f;
  t.sigma_rho2 = 0.01f;
  t.constant_colour = {0.2f, 0.4f, 0.6f};
  t.channels = all_encodings();
  t.depth_first_node = {0, 1, 9, 25};
  t.nodes.resize(25);
  // Bricks 0-3 belong to nodes on the domain's upper boundary (the root;
  // nodes 2 and 8 at depth 1, coordinates (1, 0, 0) and (1, 1, 1); node 24
  // at depth 2, (3, 3, 1)) and carry shells; the others lie inside.
  t.nodes[0] = {1, 0};
  t.nodes[1] = {9, 7};
  t.nodes[2].brick = 1;
  t.nodes[4] = {17, kNone};
  t.nodes[8].brick = 2;
  t.nodes[9].brick = 8;
  t.nodes[12].brick = 4;
  t.nodes[16].brick = 5;
  t.nodes[17].brick = 6;
  t.nodes[24].brick = 3;
  t.brick_count = 9;
  t.shell_count = 4;
  for (size_t c = 0; c < t.channels.size(); ++c) {
    t.brick_data.emplace_back(t.pool_samples() * encoding_bytes(t.channels[c].encoding));
    fill_random(t.brick_data.back(), seed * 1000 + c);
  }
  return t;
}

Octree make_tiny_tree() {
  Octree t;
  t.brick_size = 2;
  t.depth_count = 1;
  t.origin = {-1.0f, -2.0f, -3.0f};
  t.size = 4.0f;
  t.sigma_rho2 = 0.125f;
  t.constant_colour = {0.5f, 0.25f, 1.0f};
  t.channels = {{Channel::Distance, Encoding::F32}};
  t.depth_first_node = {0, 1};
  t.nodes = {{kNone, 0}};
  t.brick_count = 1;
  t.shell_count = 1;  // the root lies on the domain's upper boundary
  t.brick_data.emplace_back(t.pool_samples() * 4);
  for (uint32_t i = 0; i < t.pool_samples(); ++i) {
    float v = 0.25f * float(i) - 1.0f;
    std::memcpy(t.brick_data[0].data() + 4 * i, &v, 4);
  }
  return t;
}

std::vector<uint8_t> tiny_version1_file() {
  using namespace format;
  const Octree t = make_tiny_tree();
  std::vector<uint8_t> file(364, 0);
  Header h;
  h.version = 1;
  h.brick_size = t.brick_size;
  h.depth_count = t.depth_count;
  for (int i = 0; i < 3; ++i) h.origin[i] = t.origin[i], h.constant_colour[i] = t.constant_colour[i];
  h.size = t.size;
  h.sigma_rho2 = t.sigma_rho2;
  h.channel_count = 1;
  h.node_count = 1;
  h.brick_count = 1;
  h.channel_table_offset = 128;
  h.depth_table_offset = 160;
  h.node_table_offset = 192;
  h.file_bytes = 364;
  encode_header(h, file.data());
  encode_channel({uint32_t(Channel::Distance), uint32_t(Encoding::F32), 4, 0, 256, 27 * 4}, file.data() + 128);
  put_u32(file.data() + 160, 0);
  put_u32(file.data() + 164, 1);
  put_u32(file.data() + 192, kNone);  // the root: no children, brick 0
  put_u32(file.data() + 196, 0);
  for (uint32_t i = 0; i < 27; ++i) put_f32(file.data() + 256 + 4 * i, 0.25f * float(i) - 1.0f);
  seal(file);
  return file;
}

std::vector<uint8_t> read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace svo::octree::testing
