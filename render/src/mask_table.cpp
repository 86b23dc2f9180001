#include "svo/render/mask_table.h"

#include <bit>
#include <cmath>
#include <random>
#include <stdexcept>

#include "common/shared_math.h"

namespace svo::render {

std::vector<glm::vec2> poisson_disk(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  // Start from the radius of a hexagonal packing of `count` points in the
  // disk and shrink it whenever dart throwing stalls.
  float radius = 1.9f / std::sqrt(float(count));
  std::vector<glm::vec2> points;
  int misses = 0;
  while (int(points.size()) < count) {
    glm::vec2 p(u(rng), u(rng));
    if (p.x * p.x + p.y * p.y > 1.0f) continue;
    bool ok = true;
    for (const auto& q : points) {
      glm::vec2 d = p - q;
      if (d.x * d.x + d.y * d.y < radius * radius) {
        ok = false;
        break;
      }
    }
    if (ok) {
      points.push_back(p);
      misses = 0;
    } else if (++misses > 2000) {
      radius *= 0.97f;
      misses = 0;
    }
  }
  return points;
}

MaskTable build_mask_table(const std::vector<glm::vec2>& points, int theta_bins, int v_bins) {
  if (int(points.size()) != kMaskBits) throw std::invalid_argument("a mask table needs exactly 128 points");
  if (theta_bins < 1 || v_bins < 1) throw std::invalid_argument("a mask table needs at least one bin per axis");
  MaskTable table;
  table.theta_bins = theta_bins;
  table.v_bins = v_bins;
  table.points = points;
  table.masks.resize(size_t(theta_bins) * size_t(v_bins));
  for (int t = 0; t < theta_bins; ++t) {
    float theta = -svo::math::SVO_PI + (float(t) + 0.5f) * 2.0f * svo::math::SVO_PI / float(theta_bins);
    svo::math::SvoMaskParams p;
    p.theta = theta;
    for (int v = 0; v < v_bins; ++v) {
      p.v = -1.0f + (float(v) + 0.5f) * 2.0f / float(v_bins);
      Mask m(0u);
      for (int i = 0; i < kMaskBits; ++i) {
        if (svo::math::svo_mask_covers(points[size_t(i)], p)) m[i / 32] |= 1u << (i % 32);
      }
      table.masks[size_t(t) * size_t(v_bins) + size_t(v)] = m;
    }
  }
  return table;
}

Mask lookup_mask(const MaskTable& table, float theta, float v) {
  if (!(v > -1.0f)) return Mask(0u);
  if (v >= 1.0f) return Mask(~0u);
  float tf = (theta + svo::math::SVO_PI) / (2.0f * svo::math::SVO_PI) * float(table.theta_bins);
  int t = int(std::floor(tf)) % table.theta_bins;
  if (t < 0) t += table.theta_bins;
  int vi = std::min(int((v + 1.0f) * 0.5f * float(table.v_bins)), table.v_bins - 1);
  return table.at(t, vi);
}

int popcount(const Mask& m) {
  return std::popcount(m.x) + std::popcount(m.y) + std::popcount(m.z) + std::popcount(m.w);
}

std::vector<Mask> tracer_buffer(const MaskTable& table) {
  std::vector<Mask> b = table.masks;
  auto bits = [](float x) { return std::bit_cast<uint32_t>(x); };
  glm::vec2 sum(0.0f);
  glm::vec3 squares(0.0f);
  for (size_t i = 0; i + 1 < table.points.size(); i += 2) {
    const glm::vec2 p = table.points[i], q = table.points[i + 1];
    b.push_back(Mask(bits(p.x), bits(p.y), bits(q.x), bits(q.y)));
  }
  for (const glm::vec2& p : table.points) {
    sum += p;
    squares += glm::vec3(p.x * p.x, p.y * p.y, p.x * p.y);
  }
  b.push_back(Mask(bits(sum.x), bits(sum.y), bits(squares.x), bits(squares.y)));
  b.push_back(Mask(bits(squares.z), 0u, 0u, 0u));
  // The decode tables, each value computed by the formula the tracer would
  // otherwise evaluate per byte (voxel_codec.glsl).
  auto decode_table = [&](auto decode) {
    for (uint32_t i = 0; i < 256; i += 4) {
      b.push_back(Mask(bits(decode(i)), bits(decode(i + 1)), bits(decode(i + 2)), bits(decode(i + 3))));
    }
  };
  decode_table([](uint32_t byte) { return svo::math::svo_decode_srgb8(byte); });
  decode_table([](uint32_t byte) { return svo::math::svo_decode_u8_log_relative(byte, 1.0f); });
  decode_table([](uint32_t byte) { return svo::math::svo_decode_s8(byte); });
  return b;
}

}  // namespace svo::render
