// The shared math on the GPU path: the compute shader built from the same
// GLSL must agree with the C++ build over the dense sweep, with the Khronos
// validation layer on and silent.
#include <gtest/gtest.h>

#include "svo/render/math_probe.h"
#include "svo/render/vk_compute.h"
#include "svo/render/vk_context.h"

namespace {

std::string join(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

TEST(MathProbeGpu, AgreesWithCppWithin1e5OverTheSweep) {
  svo::vk::Context context({"", true});
  auto inputs = svo::render::probe_sweep(200);
  auto cpu = svo::render::probe_cpu(inputs);
  auto gpu = svo::render::probe_gpu(context, inputs);
  ASSERT_EQ(gpu.values.size(), cpu.size());
  auto cmp = svo::render::compare_probe(inputs, cpu, gpu.values, 1e-5, 1e-20);
  EXPECT_EQ(cmp.mismatches, 0u) << "largest: " << cmp.worst;
  EXPECT_EQ(cmp.non_finite, 0u);
  EXPECT_GT(cmp.above_floor, cmp.values / 2) << "most values must be compared in relative terms";
  EXPECT_TRUE(context.validation_messages().empty()) << join(context.validation_messages());
  std::printf("%s: %zu values, largest relative difference %.3g (%s)\n", context.info().name.c_str(), cmp.values,
              cmp.max_relative, cmp.worst.c_str());
}

// The comparison itself must be able to fail: a perturbed GPU result is caught.
TEST(MathProbeGpu, ComparisonDetectsADifference) {
  auto inputs = svo::render::probe_sweep(10);
  auto cpu = svo::render::probe_cpu(inputs);
  auto other = cpu;
  other[5] = other[5] * (1.0f + 1e-4f) + 1e-3f;
  auto cmp = svo::render::compare_probe(inputs, cpu, other, 1e-5, 1e-20);
  EXPECT_EQ(cmp.mismatches, 1u);
  EXPECT_NE(cmp.worst.find(svo::render::probe_value_name(5)), std::string::npos) << cmp.worst;
  other[7] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(svo::render::compare_probe(inputs, cpu, other, 1e-5, 1e-20).non_finite, 1u);
}

}  // namespace
