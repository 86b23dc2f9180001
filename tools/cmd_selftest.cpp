// svo selftest: runs the shared math on the Vulkan device and compares it with
// the C++ build of the same source. Exit code 1 when they disagree.
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
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
  cmd->callback([opt, &exit_code] {
    vk::Context context({opt->device, opt->validate});
    auto inputs = render::probe_sweep(opt->size);
    auto cpu = render::probe_cpu(inputs);
    auto gpu = render::probe_gpu(context, inputs);
    auto cmp = render::compare_probe(inputs, cpu, gpu.values, opt->tolerance, opt->floor);
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
