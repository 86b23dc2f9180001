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

// A device may flush fp32 denormals to zero (Vulkan allows it; NVIDIA's
// drivers do, and the H200 failed `svo selftest` on 217 values for that
// alone). The sweep holds denormal inputs, so the flushed reference must
// differ from the IEEE one somewhere, and the comparison must accept either.
TEST(Sweep, FlushedReferenceAcceptsADeviceThatFlushesDenormals) {
  auto inputs = svo::render::probe_sweep(200);
  auto ieee = svo::render::probe_cpu(inputs);
  auto flushed = svo::render::probe_cpu_flushed(inputs);
  auto strict = svo::render::compare_probe(inputs, ieee, flushed, 1e-5, 1e-20);
#if defined(__SSE2__)
  EXPECT_GT(strict.mismatches, 0u) << "the sweep no longer reaches a denormal-sensitive value";
#endif
  auto either = svo::render::compare_probe(inputs, ieee, flushed, 1e-5, 1e-20, flushed);
  EXPECT_EQ(either.mismatches, 0u) << either.worst;
  EXPECT_EQ(either.flushed_only, strict.mismatches);
  // A difference neither reference explains is still a mismatch.
  auto other = flushed;
  other[5] = other[5] * (1.0f + 1e-3f) + 1e-3f;
  auto caught = svo::render::compare_probe(inputs, ieee, other, 1e-5, 1e-20, flushed);
  EXPECT_EQ(caught.mismatches, 1u);
  ASSERT_EQ(caught.mismatch_indices.size(), 1u);
  EXPECT_EQ(caught.mismatch_indices[0], 5u);
  // A relative difference in a tail near zero (the H200's exp there) agrees
  // within an absolute 1e-5; one of 1e-3 on a value of order one does not.
  size_t tiny = 0, unit = 0;
  while (tiny < ieee.size() && !(ieee[tiny] > 1e-20f && ieee[tiny] < 1e-12f)) ++tiny;
  while (unit < ieee.size() && !(ieee[unit] > 0.1f && ieee[unit] < 1.0f)) ++unit;
  ASSERT_LT(tiny, ieee.size());
  ASSERT_LT(unit, ieee.size());
  auto device = ieee;
  device[tiny] *= 1.01f;
  EXPECT_EQ(svo::render::compare_probe(inputs, ieee, device, 1e-5, 1e-20).mismatches, 1u);
  auto loose = svo::render::compare_probe(inputs, ieee, device, 1e-5, 1e-20, {}, 1e-5);
  EXPECT_EQ(loose.mismatches, 0u);
  EXPECT_EQ(loose.absolute_only, 1u);
  device[unit] += 1e-3f;
  EXPECT_EQ(svo::render::compare_probe(inputs, ieee, device, 1e-5, 1e-20, {}, 1e-5).mismatches, 1u);
  // The flushing mode does not leak out of probe_cpu_flushed.
  EXPECT_EQ(svo::render::probe_cpu(inputs), ieee);
}
