// svo: pre-filtered sparse voxel octree engine, command line.
#include <exception>
#include <iostream>
#include <new>

#include "cli_hint.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "svo: render detailed surfaces from a pre-filtered sparse voxel octree (Heitz & Neyret 2012).\n"
      "Run 'svo COMMAND --help' for the options of a command."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "svo 0.1.0");
  app.footer(
      "Outputs: -o names the file a command writes (render, reference, voxelize, export) or, for commands that "
      "write several files (demo, flythrough, bench), their directory, created if missing. Two outputs of one "
      "command may not name one file, and an output's extension must say what it holds (.svo, .vdb, .png, .jpg, "
      ".exr).\n"
      "Files: inputs must be regular files (a FIFO or a device is refused before it is read). Every output is "
      "written to a temporary name beside it (NAME.tmp-PID-N, created exclusively) and renamed over NAME when "
      "complete, so a failure or a kill leaves the earlier file as it was; temporaries of killed runs are removed "
      "by the next write of NAME. A symbolic link at NAME is written through to its target, which keeps its mode; "
      "a read-only file, a directory or a device at NAME is refused before any work.");
  int exit_code = 0;
  svo::tools::add_bench_command(app, exit_code);
  svo::tools::add_compare_command(app, exit_code);
  svo::tools::add_demo_command(app, exit_code);
  svo::tools::add_devices_command(app, exit_code);
  svo::tools::add_export_command(app, exit_code);
  svo::tools::add_flythrough_command(app, exit_code);
  svo::tools::add_info_command(app, exit_code);
  svo::tools::add_luminaire_command(app, exit_code);
  svo::tools::add_material_command(app, exit_code);
  svo::tools::add_reference_command(app, exit_code);
  svo::tools::add_render_command(app, exit_code);
  svo::tools::add_selftest_command(app, exit_code);
  svo::tools::add_view_command(app, exit_code);
  svo::tools::add_voxelize_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    std::cout << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion&) {
    std::cout << "svo 0.1.0\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    const svo::tools::CommandLineHint hint = svo::tools::command_line_hint(app, argc, argv);
    std::cerr << hint.command << ": " << (hint.message.empty() ? std::string(e.what()) : hint.message) << " (see "
              << hint.command << " --help)\n";
    return 1;
  } catch (const std::bad_alloc&) {
    std::cerr << "svo: out of host memory (an allocation failed); try a smaller --resolution or image size\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "svo: " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}
