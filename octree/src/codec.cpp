#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>

#include "common/shared_math.h"
#include "svo/octree/octree.h"

namespace svo::octree {

const char* channel_name(Channel channel) {
  switch (channel) {
    case Channel::Distance:
      return "distance";
    case Channel::Normal:
      return "normal";
    case Channel::HeightDev:
      return "height_dev";
    case Channel::SlopeDev:
      return "slope_dev";
    case Channel::SlopeCov:
      return "slope_cov";
    case Channel::Colour:
      return "colour";
    case Channel::ColourSlope:
      return "colour_slope";
    case Channel::Material:
      return "material";
    case Channel::ShadingNormal:
      return "shading_normal";
  }
  return "unknown";
}

const char* encoding_name(Encoding encoding) {
  switch (encoding) {
    case Encoding::F32:
      return "f32";
    case Encoding::Oct24:
      return "oct24";
    case Encoding::U8LogRelative:
      return "u8_log_relative";
    case Encoding::U8LogSlope:
      return "u8_log_slope";
    case Encoding::Cov3x8:
      return "cov3x8";
    case Encoding::Srgb8:
      return "srgb8";
    case Encoding::Signed8:
      return "s8x3";
    case Encoding::MaterialShare8:
      return "material_share8";
  }
  return "unknown";
}

uint32_t encoding_bytes(Encoding encoding) {
  switch (encoding) {
    case Encoding::F32:
      return 4;
    case Encoding::Oct24:
      return 3;
    case Encoding::U8LogRelative:
      return 1;
    case Encoding::U8LogSlope:
      return 1;
    case Encoding::Cov3x8:
      return 3;
    case Encoding::Srgb8:
      return 3;
    case Encoding::Signed8:
      return 3;
    case Encoding::MaterialShare8:
      return 2;
  }
  return 0;
}

bool encoding_fits(Channel channel, Encoding encoding) {
  switch (channel) {
    case Channel::Distance:
      return encoding == Encoding::F32;
    case Channel::Normal:
    case Channel::ShadingNormal:
      return encoding == Encoding::Oct24;
    case Channel::HeightDev:
      return encoding == Encoding::U8LogRelative || encoding == Encoding::F32;
    case Channel::SlopeDev:
      return encoding == Encoding::U8LogSlope || encoding == Encoding::F32;
    case Channel::SlopeCov:
      return encoding == Encoding::Cov3x8;
    case Channel::Colour:
      return encoding == Encoding::Srgb8;
    case Channel::ColourSlope:
      return encoding == Encoding::Signed8;
    case Channel::Material:
      return encoding == Encoding::MaterialShare8;
  }
  return false;
}

int Octree::channel_index(Channel channel) const {
  for (size_t i = 0; i < channels.size(); ++i) {
    if (channels[i].channel == channel) return int(i);
  }
  return -1;
}

namespace {

// Height deviations are stored relative to the voxel size: a box of side s
// holds heights within +-s sqrt(3)/2, so sigma_h <= s.
float height_scale(const Octree& tree, uint32_t depth) { return tree.voxel_size(depth); }

uint8_t* pool_ptr(Octree& tree, size_t c, uint64_t pool_sample) {
  return tree.brick_data[c].data() + pool_sample * encoding_bytes(tree.channels[c].encoding);
}

const uint8_t* sample_ptr(const Octree& tree, size_t c, uint64_t brick, uint32_t sample) {
  uint32_t bytes = encoding_bytes(tree.channels[c].encoding);
  return tree.brick_data[c].data() + (brick * tree.samples_per_brick() + sample) * bytes;
}

// The file allows at most 16 channels, one per Channel value (9 today).
constexpr size_t kMaxSampleChannels = 16;

void put3(uint8_t* p, uint32_t a, uint32_t b, uint32_t c) { p[0] = uint8_t(a), p[1] = uint8_t(b), p[2] = uint8_t(c); }

}  // namespace

bool on_upper_boundary(uint32_t depth, glm::ivec3 c) {
  const int last = (1 << depth) - 1;
  return c.x == last || c.y == last || c.z == last;
}

uint32_t shell_index(uint32_t brick_size, glm::ivec3 l) {
  const uint32_t B = brick_size;
  // Layers z < B hold B points with x = B (rows y < B) and the row y = B;
  // the layer z = B is whole.
  if (uint32_t(l.z) < B) return uint32_t(l.z) * (2 * B + 1) + (uint32_t(l.y) < B ? uint32_t(l.y) : B + uint32_t(l.x));
  return B * (2 * B + 1) + uint32_t(l.y) * (B + 1) + uint32_t(l.x);
}

uint64_t Octree::shell_sample(uint64_t b, glm::ivec3 l) const {
  return brick_count * samples_per_brick() + b * shell_samples() + shell_index(brick_size, l);
}

void encode_voxel(Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth, const Voxel& v) {
  encode_pool_voxel(tree, tree.brick_sample(brick, sample), depth, v);
}

void encode_pool_voxel(Octree& tree, uint64_t pool_sample, uint32_t depth, const Voxel& v) {
  using namespace svo::math;
  for (size_t c = 0; c < tree.channels.size(); ++c) {
    uint8_t* p = pool_ptr(tree, c, pool_sample);
    const ChannelInfo& info = tree.channels[c];
    switch (info.encoding) {
      case Encoding::F32: {
        float x = info.channel == Channel::Distance ? v.hbar
                  : info.channel == Channel::HeightDev
                      ? v.sigma_h
                      : std::sqrt(std::max(0.0f, 0.5f * (v.slope_cov.x + v.slope_cov.y)));
        std::memcpy(p, &x, 4);
        break;
      }
      case Encoding::Oct24: {
        const bool shading = info.channel == Channel::ShadingNormal && glm::dot(v.n_shading, v.n_shading) > 0.0f;
        uint32_t bits = svo_encode_oct24(shading ? v.n_shading : v.nbar);
        put3(p, bits & 255u, (bits >> 8) & 255u, (bits >> 16) & 255u);
        break;
      }
      case Encoding::U8LogRelative:
        p[0] = uint8_t(svo_encode_u8_log_relative(v.sigma_h, height_scale(tree, depth)));
        break;
      case Encoding::U8LogSlope:
        p[0] = uint8_t(svo_encode_u8_log_slope(std::sqrt(std::max(0.0f, 0.5f * (v.slope_cov.x + v.slope_cov.y)))));
        break;
      case Encoding::Cov3x8: {
        float sx = std::sqrt(std::max(0.0f, v.slope_cov.x)), sy = std::sqrt(std::max(0.0f, v.slope_cov.y));
        float rho = sx > 0 && sy > 0 ? v.slope_cov.z / (sx * sy) : 0.0f;
        put3(p, svo_encode_u8_log_slope(sx), svo_encode_u8_log_slope(sy), svo_encode_s8(rho));
        break;
      }
      case Encoding::Srgb8:
        put3(p, svo_encode_srgb8(v.abar.x), svo_encode_srgb8(v.abar.y), svo_encode_srgb8(v.abar.z));
        break;
      case Encoding::Signed8:
        put3(p, svo_encode_s8(v.a_s.x), svo_encode_s8(v.a_s.y), svo_encode_s8(v.a_s.z));
        break;
      case Encoding::MaterialShare8:
        p[0] = uint8_t(std::min(v.material, kMaxMaterials - 1));
        p[1] = uint8_t(std::lround(255.0f * std::clamp(v.material_share, 0.0f, 1.0f)));
        break;
    }
  }
}

Voxel decode_sample(const Octree& tree, std::span<const uint8_t* const> samples, uint32_t depth) {
  using namespace svo::math;
  Voxel v;
  v.abar = tree.constant_colour;
  for (size_t c = 0; c < std::min(tree.channels.size(), samples.size()); ++c) {
    const uint8_t* p = samples[c];
    const ChannelInfo& info = tree.channels[c];
    switch (info.encoding) {
      case Encoding::F32: {
        float x;
        std::memcpy(&x, p, 4);
        if (info.channel == Channel::Distance) v.hbar = x;
        if (info.channel == Channel::HeightDev) v.sigma_h = x;
        if (info.channel == Channel::SlopeDev) v.slope_cov = glm::vec3(x * x, x * x, 0.0f);
        break;
      }
      case Encoding::Oct24:
        (info.channel == Channel::ShadingNormal ? v.n_shading : v.nbar) =
            svo_decode_oct24(uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16));
        break;
      case Encoding::U8LogRelative:
        v.sigma_h = svo_decode_u8_log_relative(p[0], height_scale(tree, depth));
        break;
      case Encoding::U8LogSlope: {
        float s = svo_decode_u8_log_slope(p[0]);
        v.slope_cov = glm::vec3(s * s, s * s, 0.0f);
        break;
      }
      case Encoding::Cov3x8: {
        float sx = svo_decode_u8_log_slope(p[0]), sy = svo_decode_u8_log_slope(p[1]), rho = svo_decode_s8(p[2]);
        v.slope_cov = glm::vec3(sx * sx, sy * sy, rho * sx * sy);
        break;
      }
      case Encoding::Srgb8:
        v.abar = glm::vec3(svo_decode_srgb8(p[0]), svo_decode_srgb8(p[1]), svo_decode_srgb8(p[2]));
        break;
      case Encoding::Signed8:
        v.a_s = glm::vec3(svo_decode_s8(p[0]), svo_decode_s8(p[1]), svo_decode_s8(p[2]));
        break;
      case Encoding::MaterialShare8:
        v.material = p[0];
        v.material_share = float(p[1]) / 255.0f;
        break;
    }
  }
  return v;
}

Voxel decode_voxel(const Octree& tree, uint64_t brick, uint32_t sample, uint32_t depth) {
  const uint8_t* samples[kMaxSampleChannels];
  const size_t n = std::min(tree.channels.size(), kMaxSampleChannels);
  for (size_t c = 0; c < n; ++c) samples[c] = sample_ptr(tree, c, brick, sample);
  return decode_sample(tree, {samples, n}, depth);
}

}  // namespace svo::octree
