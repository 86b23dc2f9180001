// A dense sweep over (mu, sigma) through every shared function (the probe
// that the GPU test also runs): no NaN, no Inf, every value in its range.
#include <gtest/gtest.h>

#include <cmath>

#include "common/shared_math.h"
#include "svo/render/math_probe.h"

namespace {
using namespace svo::math;

TEST(Sweep, DenseMuSigmaHasNoNaNOrInf) {
  auto inputs = svo::render::probe_sweep(600);  // 606 x 603 pairs
  auto values = svo::render::probe_cpu(inputs);
  ASSERT_EQ(values.size(), inputs.size() * svo::render::kProbeValues);
  size_t bad = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      if (++bad <= 10) {
        const vec4& in = inputs[i / svo::render::kProbeValues];
        ADD_FAILURE() << svo::render::probe_value_name(int(i % svo::render::kProbeValues)) << " = " << values[i]
                      << " at (mu, sigma, x, y) = (" << in.x << ", " << in.y << ", " << in.z << ", " << in.w << ")";
      }
    }
  }
  EXPECT_EQ(bad, 0u);
}

TEST(Sweep, ValuesStayInTheirRanges) {
  auto inputs = svo::render::probe_sweep(300);
  auto v = svo::render::probe_cpu(inputs);
  for (size_t i = 0; i < inputs.size(); ++i) {
    const float* r = &v[i * svo::render::kProbeValues];
    SCOPED_TRACE(::testing::Message() << "input " << inputs[i].x << ", " << inputs[i].y << ", " << inputs[i].z << ", "
                                      << inputs[i].w);
    ASSERT_TRUE(r[0] >= -1.0f && r[0] <= 1.0f);                                // erf
    ASSERT_TRUE(r[1] >= 0.0f && r[1] <= 2.0f);                                 // erfc
    ASSERT_TRUE(r[2] >= 0.0f && r[2] <= 1.0f);                                 // g
    ASSERT_TRUE(r[3] >= -1.0f && r[3] <= 1.0f);                                // s
    ASSERT_TRUE(r[4] >= 0.0f && r[4] <= SVO_LAMBDA_MAX);                       // Lambda
    ASSERT_TRUE(r[5] >= 0.0f && r[5] <= SVO_LAMBDA_MAX);                       // Lambda(a)
    ASSERT_TRUE(r[6] >= 0.0f && r[6] <= 1.0f);                                 // G1
    ASSERT_TRUE(r[7] >= 0.2f - 1e-6f && r[7] <= 1.0f + 1e-6f);                 // 0.6 + 0.4 y * [0, 1]
    ASSERT_TRUE(r[8] >= 0.0f && r[8] <= SVO_LAMBDA_MAX);                       // Lambda(dir)
    ASSERT_TRUE(r[9] >= 0.0f);                                                 // D
    ASSERT_TRUE(r[10] >= 0.0f);                                                // specular
    ASSERT_TRUE(r[11] >= 0.0f && r[11] <= SVO_LAMBDA_MAX);                     // Lambda(cos)
    ASSERT_TRUE(r[12] >= -SVO_PI && r[12] <= SVO_PI);                          // theta
    ASSERT_TRUE(std::abs(r[13]) < 1.0f || std::abs(r[13]) == SVO_MASK_V_ALL);  // v
    ASSERT_TRUE(r[14] >= 0.0f && r[14] <= 1.0f);                               // coverage
    ASSERT_TRUE(r[15] > 0.0f && r[15] <= 1.0f);                                // erfcx
  }
}

}  // namespace
