// Runs the shared math of shaders/common/ on the GPU (math_probe.comp) and on
// the CPU (the C++ build of the same source) over the same inputs, and
// compares the two: the proof that the shaders compute what the C++ tests check.
#pragma once

#include <array>
#include <cstddef>
#include <glm/vec4.hpp>
#include <span>
#include <string>
#include <vector>

#include "svo/render/vk_context.h"

namespace svo::render {

// Number of scalar outputs per input (4 rows of vec4) and their names.
constexpr int kProbeValues = 20;
const char* probe_value_name(int index);

// A dense deterministic sweep: every (mu, sigma) of a grid of `n` x `n`
// log-spaced values (mu in [1e-6, 1e4], sigma in [1e-6, 10]) plus the edge
// values 0, -0, negatives and denormals; the free arguments x and y run over
// [-12, 12] and [-1, 1].
std::vector<glm::vec4> probe_sweep(int n);

// The 16 outputs of each input, in order, from the C++ build.
std::vector<float> probe_cpu(std::span<const glm::vec4> inputs);

// The same with denormals flushed to zero, inputs and results (x86's FTZ and
// DAZ modes): the other answer Vulkan allows a device, whose float controls
// may flush fp32 denormals (NVIDIA's do; lavapipe preserves them). On other
// processors it equals probe_cpu.
std::vector<float> probe_cpu_flushed(std::span<const glm::vec4> inputs);

struct ProbeRun {
  std::vector<float> values;  // as probe_cpu
  double gpu_ms = -1;         // timestamp-query time of the dispatch; < 0 if unsupported
};

// The same on the device of `context`. Throws svo::vk::Error on Vulkan failures.
ProbeRun probe_gpu(vk::Context& context, std::span<const glm::vec4> inputs);

struct ProbeComparison {
  std::size_t values = 0;       // scalars compared
  std::size_t above_floor = 0;  // of which one side exceeds `floor` in magnitude
  std::size_t mismatches = 0;   // relative difference above the tolerance
  std::size_t non_finite = 0;   // NaN or Inf on either side
  double max_relative = 0;      // largest relative difference among those above the floor
  std::string worst;            // "name at (mu, sigma, x, y): cpu vs gpu" of the largest difference
  std::array<double, kProbeValues> max_relative_by_value{};  // per output, indexed as probe_value_name
  std::array<std::size_t, kProbeValues> mismatches_by_value{};
  std::size_t flushed_only = 0;   // agree with the flushed reference alone (the device flushes denormals)
  std::size_t absolute_only = 0;  // agree within `absolute` alone (relatively they differ by more than the tolerance)
  std::vector<std::size_t> mismatch_indices;  // into the values, in order (at most 10,000)
};

// Relative difference |a - b| / max(|a|, |b|) for every value where either
// side exceeds `floor` in magnitude; below it both must be within `floor`.
// With `flushed` (probe_cpu_flushed of the same inputs), a GPU value that
// agrees with it instead agrees too, counted in flushed_only; the relative
// differences reported are then against the closer reference. A value
// within `absolute` of a reference agrees too, counted in absolute_only: the
// outputs are quantities of order one that shading combines additively or
// through 1 / (1 + Lambda), where a difference of 1e-4 cannot show, while
// Vulkan lets a device's exp err by 3 + 2|x| ULPs and contract a * b + c
// into one rounding, which shows as relative error in tails near zero and
// after cancellation (the H200, 2026-12-04: 281 values, at most 2.9e-5 off).
ProbeComparison compare_probe(std::span<const glm::vec4> inputs, std::span<const float> cpu, std::span<const float> gpu,
                              double tolerance, double floor, std::span<const float> flushed = {}, double absolute = 0);

}  // namespace svo::render
