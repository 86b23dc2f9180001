// The A-buffer mask table (Heitz & Neyret 5.4): its coverage follows the
// exact covered fraction of the disk, it is monotonic in v, and combining
// the masks of correlated cone elements does not thicken a silhouette.
#include <gtest/gtest.h>

#include <cmath>

#include "common/shared_math.h"
#include "svo/render/mask_table.h"

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

}  // namespace
