#include "test_trees.h"

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

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
  t.nodes[0] = {1, 0};
  t.nodes[1] = {9, 3};
  t.nodes[2].brick = 1;
  t.nodes[4] = {17, kNone};
  t.nodes[8].brick = 2;
  t.nodes[9].brick = 8;
  t.nodes[12].brick = 4;
  t.nodes[16].brick = 5;
  t.nodes[17].brick = 6;
  t.nodes[24].brick = 7;
  t.brick_count = 9;
  for (size_t c = 0; c < t.channels.size(); ++c) {
    t.brick_data.emplace_back(t.brick_count * t.samples_per_brick() * encoding_bytes(t.channels[c].encoding));
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
  t.brick_data.emplace_back(t.samples_per_brick() * 4);
  for (uint32_t i = 0; i < t.samples_per_brick(); ++i) {
    float v = 0.25f * float(i) - 1.0f;
    std::memcpy(t.brick_data[0].data() + 4 * i, &v, 4);
  }
  return t;
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

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "svo-octree-test-XXXXXX").string();
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace svo::octree::testing
