// svo-render: the renderer alone (issue 23). The commands render,
// flythrough, devices and selftest of svo, the same sources and options,
// linked without the voxelizer (OpenVDB, OpenMesh), the reference tracer
// (Embree) and OpenImageIO: a render node needs a .svo, a Vulkan loader or
// nothing (native), and writes PNG, JPEG or EXR.
#include "cli_hint.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "svo-render: render frames and flythroughs from a .svo file (the renderer of svo alone, for render nodes).\n"
      "Run 'svo-render COMMAND --help' for the options of a command. Octrees are made with 'svo voxelize'; "
      "environment maps are read as .exr or .png.",
      "svo-render"};
  app.require_subcommand(1);
  app.footer("Outputs: -o names the file render writes and the directory flythrough writes (created if missing).\n" +
             std::string(svo::tools::kFilesFooter));
  int exit_code = 0;
  svo::tools::add_devices_command(app, exit_code);
  svo::tools::add_flythrough_command(app, exit_code);
  svo::tools::add_render_command(app, exit_code);
  svo::tools::add_selftest_command(app, exit_code);
  return svo::tools::run_command_line(app, "svo-render 0.1.0", argc, argv, exit_code);
}
