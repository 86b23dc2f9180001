// svo selftest: runs the shared math on the Vulkan device and compares it with
// the C++ build of the same source. Exit code 1 when they disagree.
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "svo/octree/files.h"
#include "svo/render/math_probe.h"
#include "svo/render/vk_context.h"

namespace svo::tools {

namespace {
struct SelftestOptions {
  std::string device;
  bool validate = false;
  bool json = false;
  int size = 200;
  double tolerance = 1e-5;
  double floor = 1e-20;
  double absolute = 1e-4;
  bool preserve_denormals = false;
  std::string dump;
};
}  // namespace

void add_selftest_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "selftest",
      "Check that the shaders compute the shared math (erf, Smith Lambda, Eq. 17, Beckmann, cone masks)\n"
      "exactly as the C++ build does, over a dense (mu, sigma) sweep, on the chosen Vulkan device");
  auto opt = std::make_shared<SelftestOptions>();
  cmd->add_option("--device", opt->device,
                  "Vulkan device: index or name substring (default: discrete > integrated > cpu; see svo devices)");
  cmd->add_flag("--validate", opt->validate, "Enable the Khronos validation layer; any message fails the check");
  cmd->add_flag("--json", opt->json, "Print one JSON object on stdout");
  cmd->add_option("--size", opt->size, "Sweep points per axis of the (mu, sigma) grid")
      ->default_val(200)
      ->check(CLI::Range(2, 2000));
  cmd->add_option("--tolerance", opt->tolerance, "Largest relative difference allowed")
      ->default_val(1e-5)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--floor", opt->floor, "Values below this magnitude compare in absolute terms")
      ->default_val(1e-20)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--absolute", opt->absolute,
                  "Values within this of the C++ build's agree whatever their relative difference: Vulkan lets a "
                  "device's exp err by 3 + 2|x| ULPs and contract a * b + c into one rounding, seen as relative "
                  "error in tails near zero and after cancellation (the H200: at most 2.9e-5 absolute); 0: the "
                  "relative test alone, as the lavapipe test in CI runs it")
      ->default_val(1e-4)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("--preserve-denormals", opt->preserve_denormals,
                "Compare with the C++ build's IEEE results alone (default: a device that flushes fp32 denormals to "
                "zero, as Vulkan allows and NVIDIA's drivers do, may agree with the C++ build run with denormals "
                "flushed instead)");
  cmd->add_option("--dump", opt->dump,
                  "Write every mismatching value as CSV (output, mu, sigma, x, y, cpu, cpu with denormals flushed, "
                  "gpu) to this file");
  cmd->callback([opt, &exit_code] {
    vk::Context context({opt->device, opt->validate});
    auto inputs = render::probe_sweep(opt->size);
    auto cpu = render::probe_cpu(inputs);
    auto gpu = render::probe_gpu(context, inputs);
    const std::vector<float> flushed = render::probe_cpu_flushed(inputs);
    auto cmp = render::compare_probe(inputs, cpu, gpu.values, opt->tolerance, opt->floor,
                                     opt->preserve_denormals ? std::span<const float>() : flushed, opt->absolute);
    if (!opt->dump.empty()) {
      std::ostringstream csv;
      csv.precision(9);
      csv << "output,mu,sigma,x,y,cpu,cpu_flushed,gpu\n";
      for (size_t i : cmp.mismatch_indices) {
        const glm::vec4& in = inputs[i / render::kProbeValues];
        csv << render::probe_value_name(int(i % render::kProbeValues)) << "," << in.x << "," << in.y << "," << in.z
            << "," << in.w << "," << cpu[i] << "," << flushed[i] << "," << gpu.values[i] << "\n";
      }
      files::write_file(opt->dump, csv.str());
    }
    auto messages = context.validation_messages();
    bool ok = cmp.mismatches == 0 && cmp.non_finite == 0 && messages.empty();
    if (opt->json) {
      nlohmann::json by_value = nlohmann::json::object();
      for (int v = 0; v < render::kProbeValues; ++v) {
        by_value[render::probe_value_name(v)] = {{"max_relative", cmp.max_relative_by_value[size_t(v)]},
                                                 {"mismatches", cmp.mismatches_by_value[size_t(v)]}};
      }
      nlohmann::json out{{"device", context.info().name},
                         {"inputs", inputs.size()},
                         {"values", cmp.values},
                         {"above_floor", cmp.above_floor},
                         {"mismatches", cmp.mismatches},
                         {"non_finite", cmp.non_finite},
                         {"flushed_only", cmp.flushed_only},
                         {"absolute_only", cmp.absolute_only},
                         {"absolute", opt->absolute},
                         {"max_relative", cmp.max_relative},
                         {"worst", cmp.worst},
                         {"by_value", by_value},
                         {"tolerance", opt->tolerance},
                         {"gpu_ms", gpu.gpu_ms},
                         {"validation_messages", messages},
                         {"ok", ok}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << "device: " << context.info().name << " (" << context.info().type << ")\n"
                << "shared math: " << inputs.size() << " inputs x " << render::kProbeValues << " values";
      if (gpu.gpu_ms >= 0) std::cout << ", GPU " << std::fixed << std::setprecision(3) << gpu.gpu_ms << " ms";
      std::cout << std::defaultfloat << "\n"
                << "largest relative difference " << std::setprecision(3) << cmp.max_relative << " (tolerance "
                << opt->tolerance << "): " << cmp.worst << "\n"
                << "mismatches " << cmp.mismatches << ", non-finite " << cmp.non_finite << ", validation messages "
                << messages.size() << "\n";
      if (cmp.flushed_only > 0) {
        std::cout << "denormals: " << cmp.flushed_only
                  << " values agree with the C++ build run with denormals flushed to zero (the device flushes them)\n";
      }
      if (cmp.absolute_only > 0) {
        std::cout << "precision: " << cmp.absolute_only << " values agree within " << opt->absolute
                  << " but not relatively (--absolute 0 fails them)\n";
      }
      for (int v = 0; v < render::kProbeValues; ++v) {
        std::cout << "  " << std::left << std::setw(15) << render::probe_value_name(v) << std::right
                  << " max relative difference " << std::setw(10) << cmp.max_relative_by_value[size_t(v)]
                  << "  mismatches " << cmp.mismatches_by_value[size_t(v)] << "\n";
      }
      for (const auto& m : messages) std::cout << "  " << m << "\n";
      std::cout << (ok ? "OK: the GPU computes the shared math as the C++ build does\n"
                       : "FAILED: the GPU and the C++ build disagree\n");
    }
    exit_code = ok ? 0 : 1;
  });
}

}  // namespace svo::tools
