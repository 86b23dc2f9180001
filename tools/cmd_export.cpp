// svo export: an octree's finest level as an OpenVDB level set (.vdb), so
// that OpenVDB's tools (vdb_print, vdb_view, vdb_tool, Houdini, Blender)
// open what we voxelized.
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo/voxelizer/vdb.h"

namespace svo::tools {

namespace {

struct ExportArgs {
  std::string input, output, level = "finest", grid = "surface";
};

}  // namespace

void add_export_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "export", "Write an octree's finest level as an OpenVDB level set (.vdb) that OpenVDB's tools open");
  auto a = std::make_shared<ExportArgs>();
  cmd->add_option("input", a->input, "The .svo octree (svo voxelize)")->required()->group("Input");
  cmd->add_option("-o,--output", a->output,
                  "Output .vdb file: one FloatGrid of class level set, the finest voxels' mean signed distance "
                  "(scene units) within 3 voxels of the surface, background 3 voxels, inside negative; its "
                  "transform places index (i, j, k) at the octree's lattice point (scene units). Written to a "
                  "temporary name, then renamed")
      ->required()
      ->group("Output");
  cmd->add_option("--level", a->level, "Which level: finest (the only one for now)")
      ->default_val("finest")
      ->check(CLI::IsMember({"finest"}))
      ->group("Output");
  cmd->add_option("--grid", a->grid, "Name of the grid in the .vdb file")->default_val("surface")->group("Output");
  cmd->callback([a, &exit_code] {
    std::string ext = std::filesystem::path(a->output).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".vdb") {
      throw std::invalid_argument("export: -o " + a->output + ": expected a .vdb file name (see svo export --help)");
    }
    files::resolve_output(a->output);
    const octree::Octree tree = octree::load_svo(a->input);
    const voxelizer::VdbExport report = voxelizer::export_vdb(tree, a->output, a->grid);
    std::cout << a->input << " -> " << a->output << ": grid \"" << a->grid << "\", level set of "
              << report.active_voxels << " active voxels of " << report.voxel_size << " (resolution "
              << tree.finest_resolution() << "), background " << report.background << "\n";
    exit_code = 0;
  });
}

}  // namespace svo::tools
