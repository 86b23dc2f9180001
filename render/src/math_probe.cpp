#include "svo/render/math_probe.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include "common/shared_math.h"
#include "math_probe.comp.spv.h"
#include "svo/render/vk_compute.h"

namespace svo::render {

const char* probe_value_name(int index) {
  static const char* const names[kProbeValues] = {"erf",
                                                  "erfc",
                                                  "height_cdf",
                                                  "height_sigmoid",  //
                                                  "lambda",
                                                  "lambda_a",
                                                  "g1",
                                                  "attribute_vl",  //
                                                  "lambda_dir",
                                                  "beckmann",
                                                  "specular_brdf",
                                                  "lambda_cos",  //
                                                  "mask_theta",
                                                  "mask_v",
                                                  "mask_coverage",
                                                  "erfcx",  //
                                                  "sg_product_integral",
                                                  "sg_eq11",
                                                  "sg_eq12",
                                                  "sg_iwasaki"};
  return index >= 0 && index < kProbeValues ? names[index] : "?";
}

std::vector<glm::vec4> probe_sweep(int n) {
  std::vector<float> mus = {-1.0f, -1e-3f, -0.0f, 0.0f, 1e-40f, 1e-30f};
  std::vector<float> sigmas = {0.0f, 1e-40f, 1e-30f};
  for (int i = 0; i < n; ++i) {
    double u = n > 1 ? double(i) / (n - 1) : 0.0;
    mus.push_back(float(std::pow(10.0, -6.0 + 10.0 * u)));
    sigmas.push_back(float(std::pow(10.0, -6.0 + 7.0 * u)));
  }
  std::vector<glm::vec4> inputs;
  inputs.reserve(mus.size() * sigmas.size());
  size_t k = 0;
  for (float mu : mus) {
    for (float sigma : sigmas) {
      // Low-discrepancy free arguments (golden-ratio and sqrt(2) sequences).
      double fx = std::fmod(0.6180339887498949 * double(k), 1.0);
      double fy = std::fmod(0.4142135623730950 * double(k), 1.0);
      inputs.emplace_back(mu, sigma, float(-12.0 + 24.0 * fx), float(-1.0 + 2.0 * fy));
      ++k;
    }
  }
  return inputs;
}

std::vector<float> probe_cpu(std::span<const glm::vec4> inputs) {
  std::vector<float> out;
  out.reserve(inputs.size() * kProbeValues);
  for (const glm::vec4& in : inputs) {
    for (int k = 0; k < math::SVO_PROBE_OUTPUTS; ++k) {
      glm::vec4 row = math::svo_probe_row(in, k);
      out.insert(out.end(), {row.x, row.y, row.z, row.w});
    }
  }
  return out;
}

std::vector<float> probe_cpu_flushed(std::span<const glm::vec4> inputs) {
#if defined(__SSE2__)
  struct FlushScope {
    unsigned saved = _mm_getcsr();
    FlushScope() { _mm_setcsr(saved | 0x8040u); }  // FTZ (bit 15) and DAZ (bit 6)
    ~FlushScope() { _mm_setcsr(saved); }
  } scope;
  // The inputs themselves as a flushing device reads them.
  std::vector<glm::vec4> flushed(inputs.begin(), inputs.end());
  for (glm::vec4& in : flushed) {
    for (int c = 0; c < 4; ++c) {
      if (std::fpclassify(in[c]) == FP_SUBNORMAL) in[c] = std::copysign(0.0f, in[c]);
    }
  }
  return probe_cpu(flushed);
#else
  return probe_cpu(inputs);
#endif
}

ProbeRun probe_gpu(vk::Context& context, std::span<const glm::vec4> inputs) {
  static_assert(sizeof(glm::vec4) == 16, "std430 vec4 layout");
  static_assert(math::SVO_PROBE_OUTPUTS * 4 == kProbeValues);
  ProbeRun run;
  if (inputs.empty()) return run;
  vk::Buffer in(context, inputs.size_bytes());
  vk::Buffer out(context, inputs.size() * kProbeValues * sizeof(float));
  std::memcpy(in.data(), inputs.data(), inputs.size_bytes());
  vk::ComputeKernel kernel(context, svo_spv_math_probe_comp, 2, sizeof(uint32_t));
  uint32_t count = uint32_t(inputs.size());
  uint32_t groups = (count + math::SVO_PROBE_WORKGROUP - 1) / math::SVO_PROBE_WORKGROUP;
  const vk::Buffer* buffers[] = {&in, &out};
  run.gpu_ms = kernel.dispatch(buffers, &count, groups);
  auto values = out.as<const float>();
  run.values.assign(values.begin(), values.end());
  return run;
}

ProbeComparison compare_probe(std::span<const glm::vec4> inputs, std::span<const float> cpu, std::span<const float> gpu,
                              double tolerance, double floor, std::span<const float> flushed, double absolute) {
  ProbeComparison result;
  size_t n = std::min({cpu.size(), gpu.size(), inputs.size() * kProbeValues});
  // Relative difference (0 below the floor) and whether it fails.
  auto differ = [&](double a, double b, double& relative) {
    double scale = std::max(std::abs(a), std::abs(b));
    double diff = std::abs(a - b);
    relative = 0;
    if (scale > floor) {
      relative = diff / scale;
      return relative > tolerance;
    }
    return diff > floor;
  };
  for (size_t i = 0; i < n; ++i) {
    const int value = int(i % kProbeValues);
    double a = cpu[i];
    double b = gpu[i];
    ++result.values;
    if (!std::isfinite(a) || !std::isfinite(b)) {
      ++result.non_finite;
      continue;
    }
    if (std::max(std::abs(a), std::abs(b)) > floor) ++result.above_floor;
    double relative;
    bool bad = differ(a, b, relative);
    if (bad && i < flushed.size() && std::isfinite(flushed[i])) {
      double relative_flushed;
      if (!differ(flushed[i], b, relative_flushed)) {
        bad = false;
        relative = relative_flushed;
        ++result.flushed_only;
      }
    }
    if (bad && absolute > 0 &&
        (std::abs(a - b) <= absolute || (i < flushed.size() && std::abs(double(flushed[i]) - b) <= absolute))) {
      bad = false;
      ++result.absolute_only;
    }
    if (bad) {
      ++result.mismatches;
      ++result.mismatches_by_value[size_t(value)];
      if (result.mismatch_indices.size() < 10000) result.mismatch_indices.push_back(i);
    }
    result.max_relative_by_value[size_t(value)] = std::max(result.max_relative_by_value[size_t(value)], relative);
    if (relative > result.max_relative || (bad && result.worst.empty())) {
      result.max_relative = std::max(result.max_relative, relative);
      const glm::vec4& in = inputs[i / kProbeValues];
      std::ostringstream text;
      text.precision(9);
      text << probe_value_name(value) << " at (mu, sigma, x, y) = (" << in.x << ", " << in.y << ", " << in.z << ", "
           << in.w << "): cpu " << a << " vs gpu " << b;
      result.worst = text.str();
    }
  }
  return result;
}

}  // namespace svo::render
