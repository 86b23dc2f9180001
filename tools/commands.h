// The subcommands of `svo`. Each add_* registers one on the app; its callback
// runs the command and stores the process exit code in `exit_code`. Errors
// reach main() as exceptions and become one line on stderr with exit code 1.
#pragma once

#include <CLI/CLI.hpp>

namespace svo::tools {

// The help of every --device option.
inline constexpr const char* kDeviceHelp =
    "Where to render: native (the CPU, the tracer compiled as C++), or a Vulkan device by index or name substring "
    "(e.g. llvmpipe, Vulkan on the CPU, for tests). Default: a discrete GPU, then an integrated one, then native; "
    "see svo devices";

// The help's footer on files, for svo and svo-render.
inline constexpr const char* kFilesFooter =
    "Files: inputs must be regular files (a FIFO or a device is refused before it is read). Every output is "
    "written to a temporary name beside it (NAME.tmp-PID-N, created exclusively) and renamed over NAME when "
    "complete, so a failure or a kill leaves the earlier file as it was; temporaries of killed runs are removed "
    "by the next write of NAME. A symbolic link at NAME is written through to its target, which keeps its mode; "
    "a read-only file, a directory or a device at NAME is refused before any work.";

void add_bench_command(CLI::App& app, int& exit_code);
// svo bench zoom, registered on the bench subcommand by add_bench_command.
void add_bench_zoom_command(CLI::App& bench, int& exit_code);
// svo bench lobe-filter (cmd_bench_lobe.cpp): Tokuyoshi 2015's figures.
void add_bench_lobe_command(CLI::App& bench, int& exit_code);
// svo bench bandwidth (cmd_bench_bandwidth.cpp): Bagher et al. 2013's figures.
void add_bench_bandwidth_command(CLI::App& bench, int& exit_code);
// svo bench luminaire (cmd_bench_luminaire.cpp): Lu et al. 2015's figures.
void add_bench_luminaire_command(CLI::App& bench, int& exit_code);
void add_compare_command(CLI::App& app, int& exit_code);
void add_demo_command(CLI::App& app, int& exit_code);
void add_devices_command(CLI::App& app, int& exit_code);
// svo export (cmd_export.cpp): an octree's finest level as a .vdb level set.
void add_export_command(CLI::App& app, int& exit_code);
void add_flythrough_command(CLI::App& app, int& exit_code);
void add_info_command(CLI::App& app, int& exit_code);
// svo luminaire make|info|sheet|import (cmd_luminaire.cpp): light-field luminaires.
void add_luminaire_command(CLI::App& app, int& exit_code);
void add_material_command(CLI::App& app, int& exit_code);
void add_reference_command(CLI::App& app, int& exit_code);
void add_render_command(CLI::App& app, int& exit_code);
void add_selftest_command(CLI::App& app, int& exit_code);
void add_view_command(CLI::App& app, int& exit_code);
void add_voxelize_command(CLI::App& app, int& exit_code);

}  // namespace svo::tools
