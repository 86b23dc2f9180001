// svo: pre-filtered sparse voxel octree engine, command line.
#include "cli_hint.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "svo: render detailed surfaces from a pre-filtered sparse voxel octree (Heitz & Neyret 2012).\n"
      "Run 'svo COMMAND --help' for the options of a command.",
      "svo"};
  app.require_subcommand(1);
  app.footer(
      "Outputs: -o names the file a command writes (render, reference, voxelize, export) or, for commands that "
      "write several files (demo, flythrough, bench), their directory, created if missing. Two outputs of one "
      "command may not name one file, and an output's extension must say what it holds (.svo, .vdb, .png, .jpg, "
      ".exr).\n" +
      std::string(svo::tools::kFilesFooter));
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
  return svo::tools::run_command_line(app, "svo 0.1.0", argc, argv, exit_code);
}
