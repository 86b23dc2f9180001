// svo devices: where svo can render: the native host (the CPU) and the Vulkan
// devices of this machine, with the limits we plan with.
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "commands.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"

namespace svo::tools {

void add_devices_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "devices",
      "List where svo can render: native (the CPU, the tracer compiled as C++) and the Vulkan devices; '*' marks the "
      "default (a discrete GPU, then an integrated one, then native)");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print one JSON object on stdout");
  cmd->callback([json, &exit_code] {
    std::vector<vk::DeviceInfo> devices;
    std::string vulkan_error;
    try {
      devices = vk::list_devices();
    } catch (const vk::Error& e) {
      vulkan_error = e.what();
    }
    const std::string chosen = render::resolve_device("");
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    if (*json) {
      nlohmann::json out;
      out["default"] = chosen;
      out["devices"] = nlohmann::json::array();
      out["devices"].push_back({{"selector", "native"},
                                {"name", "native"},
                                {"type", "native"},
                                {"threads", threads},
                                {"default", chosen == "native"}});
      for (const auto& d : devices) {
        out["devices"].push_back({{"selector", std::to_string(d.index)},
                                  {"index", d.index},
                                  {"name", d.name},
                                  {"type", d.type},
                                  {"default", chosen == std::to_string(d.index)},
                                  {"api_version", d.api_version},
                                  {"max_storage_buffer_range", d.max_storage_buffer_range},
                                  {"max_image_dimension_3d", d.max_image_dimension_3d},
                                  {"max_compute_workgroup_invocations", d.max_compute_workgroup_invocations},
                                  {"subgroup_size", d.subgroup_size},
                                  {"device_local_bytes", d.device_local_bytes},
                                  {"mapped_device_local_bytes", d.mapped_device_local_bytes},
                                  {"host_cached", d.host_cached},
                                  {"timestamps", d.timestamps}});
      }
      out["vulkan_error"] = vulkan_error.empty() ? nlohmann::json(nullptr) : nlohmann::json(vulkan_error);
      std::cout << out.dump() << "\n";
    } else {
      std::cout << (chosen == "native" ? "* " : "  ") << "native: the CPU, " << threads
                << " threads (the tracer compiled as C++; --device native)\n";
      for (const auto& d : devices) {
        std::cout << (std::to_string(d.index) == chosen ? "* " : "  ") << d.index << ": " << d.name << " (" << d.type
                  << ", Vulkan " << d.api_version << ")\n"
                  << "     storage buffer range " << (d.max_storage_buffer_range >> 20) << " MiB, 3D image side "
                  << d.max_image_dimension_3d << ", subgroup " << d.subgroup_size << ", device memory "
                  << (d.device_local_bytes >> 20) << " MiB, timestamps " << (d.timestamps ? "yes" : "no") << "\n"
                  << "     memory the CPU maps: device-local " << (d.mapped_device_local_bytes >> 20)
                  << " MiB (the octree's home when it fits), host-cached " << (d.host_cached ? "yes" : "no")
                  << " (frames read back)\n";
      }
      if (!vulkan_error.empty()) std::cout << "  " << vulkan_error << "\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
