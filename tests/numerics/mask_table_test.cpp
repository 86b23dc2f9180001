// The A-buffer mask table (Heitz & Neyret 5.4): its coverage follows the
// exact covered fraction of the disk, it is monotonic in v, and combining
// the masks of correlated cone elements does not thicken a silhouette; the
// tracer reads the centre and spread of any set of bits exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/shared_math.h"
#include "svo/render/mask_table.h"

namespace svo::math {
// The tracer's code with the mask buffer alone (no octree).
struct MaskBufferReader {
  SvoTraceParams params{};
  const uvec4* masks;
  uvec2 svo_node(uint) const { return uvec2(0u); }
  uint svo_brick_bytes(uint, uint) const { return 0u; }
  uvec4 svo_mask(uint cell) const { return masks[cell]; }
  static constexpr uint SVO_SPEC_MODE = SVO_SPEC_ANY;
  static constexpr uint SVO_SPEC_FLAGS = SVO_SPEC_ANY;
#include "common/tracer.glsl"
};
}  // namespace svo::math

namespace {
using namespace svo::render;

const MaskTable& table() {
  static const MaskTable t = build_mask_table(poisson_disk(kMaskBits));
  return t;
}

TEST(MaskTable, PointsArePoissonDistributedInTheDisk) {
  const auto& p = table().points;
  ASSERT_EQ(p.size(), size_t(kMaskBits));
  float closest = 10;
  for (size_t i = 0; i < p.size(); ++i) {
    EXPECT_LE(glm::dot(p[i], p[i]), 1.0f);
    for (size_t j = 0; j < i; ++j) closest = std::min(closest, glm::length(p[i] - p[j]));
  }
  // Uniform random points would come as close as ~0.01; dart throwing keeps them apart.
  EXPECT_GT(closest, 0.1f);
}

TEST(MaskTable, CoverageFollowsTheExactFraction) {
  double worst = 0, sum = 0;
  int cells = 0;
  for (int t = 0; t < table().theta_bins; t += 3) {
    for (int v = 0; v < table().v_bins; ++v) {
      float vc = -1.0f + (v + 0.5f) * 2.0f / table().v_bins;
      double err = std::abs(popcount(table().at(t, v)) / double(kMaskBits) - svo::math::svo_mask_coverage(vc));
      worst = std::max(worst, err);
      sum += err;
      ++cells;
    }
  }
  EXPECT_LT(sum / cells, 0.02) << "mean coverage error";
  EXPECT_LT(worst, 0.06) << "largest coverage error";
  std::printf("mask coverage error: mean %.4f, max %.4f over %d cells\n", sum / cells, worst, cells);
}

TEST(MaskTable, MonotonicInVAndSaturatedOutsideTheDisk) {
  for (int t = 0; t < table().theta_bins; t += 7) {
    for (int v = 1; v < table().v_bins; ++v) {
      const Mask& lo = table().at(t, v - 1);
      const Mask& hi = table().at(t, v);
      EXPECT_EQ(lo & ~hi, Mask(0u)) << "a larger v must keep every covered point";
    }
  }
  EXPECT_EQ(popcount(lookup_mask(table(), 0.3f, 1.5f)), kMaskBits);
  EXPECT_EQ(popcount(lookup_mask(table(), 0.3f, -1.5f)), 0);
  EXPECT_EQ(popcount(lookup_mask(table(), 0.3f, svo::math::SVO_MASK_V_ALL)), kMaskBits);
}

// Paper Fig. 4: a pixel half covered by a silhouette whose plane is seen by
// many successive cone elements stays half covered when masks are OR-ed,
// while alpha blending of the same coverages tends to full opacity.
TEST(MaskTable, CorrelatedElementsKeepAHalfCoveredPixelAtOneHalf) {
  Mask alpha(0u);
  float opacity = 0;
  for (int element = 0; element < 32; ++element) {
    float theta = 0.4f + 0.001f * element;  // the same edge, seen again and again
    Mask m = lookup_mask(table(), theta, 0.0f);
    alpha |= m;
    float a = popcount(m) / float(kMaskBits);
    opacity += (1 - opacity) * a;
  }
  EXPECT_NEAR(popcount(alpha) / float(kMaskBits), 0.5f, 0.05f);
  EXPECT_GT(opacity, 0.99f);
}

// svo_footprint_part: the mean and covariance of the points of a set of
// bits, through both of its paths (the bits' points, the complement's taken
// from the sums over all), against a direct sum; all bits or none give the
// disk's exact moments, which the points approach.
TEST(MaskTable, TheTracerReadsTheCentreAndSpreadOfAnyBits) {
  const std::vector<Mask> buffer = tracer_buffer(table());
  ASSERT_EQ(buffer.size(), table().masks.size() + kMaskBits / 2 + 2 + 3 * 64);
  svo::math::MaskBufferReader reader;
  reader.masks = buffer.data();
  std::mt19937 rng(7);
  int checked = 0;
  for (int count = 1; count < kMaskBits; count += 3) {
    // `count` distinct bits at random.
    std::vector<int> order(kMaskBits);
    for (int i = 0; i < kMaskBits; ++i) order[size_t(i)] = i;
    std::shuffle(order.begin(), order.end(), rng);
    Mask bits(0u);
    glm::dvec2 mean(0.0);
    glm::dvec3 second(0.0);
    for (int k = 0; k < count; ++k) {
      const int i = order[size_t(k)];
      bits[i / 32] |= 1u << (i % 32);
      const glm::dvec2 p = table().points[size_t(i)];
      mean += p;
      second += glm::dvec3(p.x * p.x, p.y * p.y, p.x * p.y);
    }
    mean /= double(count);
    second = second / double(count) - glm::dvec3(mean.x * mean.x, mean.y * mean.y, mean.x * mean.y);
    const auto part = reader.svo_footprint_part(bits);
    EXPECT_NEAR(part.centre.x, mean.x, 1e-5) << count << " bits";
    EXPECT_NEAR(part.centre.y, mean.y, 1e-5) << count << " bits";
    EXPECT_NEAR(part.spread.x, second.x, 1e-5) << count << " bits";
    EXPECT_NEAR(part.spread.y, second.y, 1e-5) << count << " bits";
    EXPECT_NEAR(part.spread.z, second.z, 1e-5) << count << " bits";
    ++checked;
  }
  EXPECT_EQ(checked, 43);
  for (Mask all : {Mask(0u), Mask(~0u)}) {
    const auto part = reader.svo_footprint_part(all);
    EXPECT_EQ(part.centre, glm::vec2(0.0f));
    EXPECT_EQ(part.spread, glm::vec3(0.25f, 0.25f, 0.0f));
  }
  // A half-plane's bits: the centre of a half disk lies 4 / (3 pi) from the
  // middle, on the covered side.
  const auto half = reader.svo_footprint_part(lookup_mask(table(), 0.0f, 0.0f));
  EXPECT_NEAR(half.centre.x, -4.0 / (3.0 * M_PI), 0.03);
  EXPECT_NEAR(half.centre.y, 0.0, 0.03);
}

// The decode tables at the end of the buffer (masks.glsl): the tracer's
// table decode of every byte equals the formula of voxel_codec.glsl, bit
// for bit, for each encoding and scale the tracer reads.
TEST(MaskTable, TheTracerDecodeTablesEqualTheFormulas) {
  const std::vector<Mask> buffer = tracer_buffer(table());
  ASSERT_EQ(buffer.size(), size_t(svo::math::MaskBufferReader::SVO_TABLE_S8) + 64);
  svo::math::MaskBufferReader reader;
  reader.masks = buffer.data();
  for (uint32_t b = 0; b < 256; ++b) {
    EXPECT_EQ(reader.svo_table_srgb8(b), svo::math::svo_decode_srgb8(b)) << "Srgb8 byte " << b;
    EXPECT_EQ(reader.svo_table_u8_log_relative(b, 1.0f), svo::math::svo_decode_u8_log_relative(b, 1.0f))
        << "U8LogRelative byte " << b;
    EXPECT_EQ(reader.svo_table_u8_log_relative(b, 0.37f), svo::math::svo_decode_u8_log_relative(b, 0.37f))
        << "U8LogRelative byte " << b << ", scale 0.37";
    EXPECT_EQ(reader.svo_table_u8_log_slope(b), svo::math::svo_decode_u8_log_slope(b)) << "U8LogSlope byte " << b;
    EXPECT_EQ(reader.svo_table_s8(b), svo::math::svo_decode_s8(b)) << "Signed8 byte " << b;
    // Only the low byte is read.
    EXPECT_EQ(reader.svo_table_srgb8(b | 0x1200u), svo::math::svo_decode_srgb8(b)) << "Srgb8 byte " << b;
  }
  EXPECT_EQ(reader.svo_table_srgb8(0u), 0.0f);
  EXPECT_EQ(reader.svo_table_srgb8(255u), 1.0f);
  EXPECT_EQ(reader.svo_table_u8_log_relative(0u, 1.0f), 0.0f);
  EXPECT_EQ(reader.svo_table_u8_log_relative(255u, 1.0f), 1.0f);
  EXPECT_EQ(reader.svo_table_s8(127u), 1.0f);
  EXPECT_EQ(reader.svo_table_s8(129u), -1.0f);
}

}  // namespace
