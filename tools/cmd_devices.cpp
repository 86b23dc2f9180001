// svo devices: the Vulkan devices of this machine and the limits we plan with.
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "svo/render/vk_context.h"

namespace svo::tools {

void add_devices_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("devices", "List the Vulkan devices; '*' marks the one used by default");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print one JSON object on stdout");
  cmd->callback([json, &exit_code] {
    auto devices = vk::list_devices();
    uint32_t chosen = vk::select_device(devices, "");
    if (*json) {
      nlohmann::json out;
      out["default"] = chosen;
      out["devices"] = nlohmann::json::array();
      for (const auto& d : devices) {
        out["devices"].push_back({{"index", d.index},
                                  {"name", d.name},
                                  {"type", d.type},
                                  {"api_version", d.api_version},
                                  {"max_storage_buffer_range", d.max_storage_buffer_range},
                                  {"max_image_dimension_3d", d.max_image_dimension_3d},
                                  {"max_compute_workgroup_invocations", d.max_compute_workgroup_invocations},
                                  {"subgroup_size", d.subgroup_size},
                                  {"device_local_bytes", d.device_local_bytes},
                                  {"timestamps", d.timestamps}});
      }
      std::cout << out.dump() << "\n";
    } else {
      for (const auto& d : devices) {
        std::cout << (d.index == chosen ? "* " : "  ") << d.index << ": " << d.name << " (" << d.type << ", Vulkan "
                  << d.api_version << ")\n"
                  << "     storage buffer range " << (d.max_storage_buffer_range >> 20) << " MiB, 3D image side "
                  << d.max_image_dimension_3d << ", subgroup " << d.subgroup_size << ", device memory "
                  << (d.device_local_bytes >> 20) << " MiB, timestamps " << (d.timestamps ? "yes" : "no") << "\n";
      }
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
