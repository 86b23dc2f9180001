// svo voxelize: a mesh, a .vdb level set or a built-in scene to a
// pre-filtered .svo octree.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli_hint.h"
#include "commands.h"
#include "memory.h"
#include "output_checks.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo/render/shading.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/vdb.h"

namespace svo::tools {

namespace {

struct VoxelizeArgs {
  SourceOptions source;
  std::string output;
  std::string material;  // a material JSON the octree carries
  uint32_t resolution = 256;
  uint32_t brick = 8;
  std::string grid;  // --grid: the level set of a .vdb input
  double max_memory_mb = 0;
  bool json = false;
};

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

}  // namespace

void add_voxelize_command(CLI::App& app, int& exit_code) {
  auto* cmd =
      app.add_subcommand("voxelize", "Build a pre-filtered sparse voxel octree from a mesh or a built-in scene");
  auto a = std::make_shared<VoxelizeArgs>();
  add_source_options(*cmd, a->source);
  cmd->get_option("input")->description(
      "Mesh file: OBJ, PLY, OFF, STL or glTF 2.0 (.gltf, .glb: triangles of the default scene placed by their "
      "nodes, baseColorFactor, a PNG or JPEG baseColorTexture on TEXCOORD_0, COLOR_0; not Draco or sparse "
      "accessors), or an OpenVDB level set (.vdb: a float grid of class level set, --grid NAME when there are "
      "several; its narrow band is resampled to the lattice). A mesh with holes is drawn as a solid when they are "
      "small (the generalized winding number is within 0.05 of 0 and 1 on 95% of its area), else two-sided, a "
      "thin shell around every triangle, as svo reference shows it (inside the volume where the triangle bounds "
      "one by the winding number, so that the surface does not swell); a warning says which. Refused: polygons of "
      "more than 1000 corners, more than 100 million triangles, face indices that name no vertex, coordinates that "
      "are not finite or beyond 1e15, a bounding box below 1e-12, an mtllib file or texture that is not a regular "
      "file");
  cmd->add_option("-o,--output", a->output,
                  "Output .svo file (written to a temporary name, then renamed; a symbolic link is written through, a "
                  "read-only file refused)")
      ->required()
      ->group("Output");
  cmd->add_option("--material", a->material,
                  "A material (JSON, docs/materials.md) the octree carries: `svo render` and `svo view` shade "
                  "with it when no --material is given (a MERL file is recorded by its absolute path). Scenes with "
                  "materials of their own (--scene material-spheres) carry theirs")
      ->check(CLI::ExistingFile)
      ->group("Output");
  cmd->add_option("--grid", a->grid, "The grid of a .vdb input, by name (default: its only float level set)")
      ->group("Input");
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis: a power of two from 16 to 4096")
      ->default_val(256)
      ->check(resolution_check())
      ->group("Octree");
  cmd->add_option("--brick", a->brick, "Lattice cells per brick edge: 4, 8 or 16")
      ->default_val(8)
      ->check(CLI::IsMember({4u, 8u, 16u}))
      ->group("Octree");
  cmd->add_option("--max-memory", a->max_memory_mb,
                  "Refuse to start above this estimated memory, MiB (default: available memory)")
      ->check(positive_number())
      ->group("Limits");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: seconds, peak_rss_mb, voxels, bytes_per_voxel, ...");
  cmd->callback([a, &exit_code] {
    check_source_options(a->source, "voxelize");
    require_extension("-o", a->output, {".svo"}, "an octree");
    std::unique_ptr<voxelizer::SurfaceSource> source;
    const std::string what = source_name(a->source);
    if (!a->grid.empty() && !voxelizer::is_vdb_path(a->source.input)) {
      throw std::invalid_argument("voxelize: --grid names a grid of a .vdb input (see svo voxelize --help)");
    }
    if (!a->source.scene.empty()) {
      source = make_scene_source(a->source, /*all_octaves=*/false);
    } else if (voxelizer::is_vdb_path(a->source.input)) {
      voxelizer::VdbOptions vdb;
      vdb.grid = a->grid;
      if (a->source.colour.size() == 3)
        vdb.colour = glm::vec3(a->source.colour[0], a->source.colour[1], a->source.colour[2]);
      vdb.sigma_rho = a->source.roughness;
      source = voxelizer::load_vdb(a->source.input, vdb);
    } else {
      // The mesh's repairs and caveats (degenerate triangles dropped, an
      // open surface, whose inside the level set guesses): one line each on
      // stderr, the run goes on. (svo reference ray traces the triangles
      // themselves: neither matters there.)
      source = voxelizer::mesh_source(
          read_source_mesh(a->source, [](const std::string& line) { std::cerr << "svo: warning: " << line << "\n"; }));
    }
    // The source's own materials are checked now, not when rendering.
    render::parse_scene_materials(source->materials(), what);
    std::string material;
    if (!a->material.empty()) {
      if (!source->materials().empty()) {
        throw std::invalid_argument("--material: " + what + " has materials of its own (" +
                                    std::to_string(source->materials().size()) + ")");
      }
      render::Material m = render::load_material(a->material);
      if (!m.file.empty()) m.file = std::filesystem::absolute(m.file);
      material = render::material_json(m);
    }
    // Refuse an output that cannot be written before minutes of work, not after.
    files::resolve_output(a->output);
    double limit = a->max_memory_mb > 0 ? a->max_memory_mb : available_memory_mb();
    double estimate = voxelizer::estimate_memory_bytes(*source, a->resolution, a->brick) / (1024.0 * 1024.0);
    if (limit > 0 && estimate > limit) {
      throw std::runtime_error(what + ": resolution " + std::to_string(a->resolution) + " needs about " +
                               std::to_string(int64_t(estimate)) + " MiB, above the limit of " +
                               std::to_string(int64_t(limit)) + " MiB (--max-memory)");
    }
    ProgressBar bar("voxelize");
    voxelizer::VoxelizeOptions options;
    options.resolution = a->resolution;
    options.brick_size = a->brick;
    options.progress_items = [&bar](const std::string& stage, double f, uint64_t done, uint64_t total) {
      if (total > 0) {
        bar.update(stage, done, total, "bricks", f);
      } else {
        bar.update(stage, f);
      }
    };
    voxelizer::VoxelizeReport report;
    const std::string surface_read = source->surface();
    octree::Octree tree = voxelizer::voxelize(*source, options, &report);
    // The voxelizer may revise what was decided (a flood fill that leaked).
    if (source->surface() != surface_read) {
      bar.finish();
      std::cerr << "svo: warning: " << what << ": " << source->surface() << "\n";
    }
    if (!material.empty()) tree.materials = {material};
    // Where it came from and what was decided about the surface (svo info).
    nlohmann::json provenance{{"input", what}, {"resolution", a->resolution}, {"brick_size", a->brick}};
    if (!a->material.empty()) provenance["material"] = a->material;
    const std::string surface = source->surface();
    if (!surface.empty()) provenance["surface"] = surface;
    if (source->two_sided()) provenance["two_sided"] = true;
    tree.source = provenance.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (tree.source.size() > octree::kMaxSourceBytes) tree.source.clear();  // a path of 64 KiB: not recorded
    bar.update("writing", 1.0);
    auto write_start = std::chrono::steady_clock::now();
    octree::write_svo(a->output, tree);
    double seconds_write = std::chrono::duration<double>(std::chrono::steady_clock::now() - write_start).count();
    bar.finish();
    double bytes = 0;
    {
      std::ifstream f(a->output, std::ios::binary | std::ios::ate);
      bytes = double(f.tellg());
    }
    double voxels = double(tree.voxel_count());
    if (a->json) {
      nlohmann::json channels = nlohmann::json::array();
      for (const auto& c : tree.channels) channels.push_back(octree::channel_name(c.channel));
      nlohmann::json out{{"input", what},
                         {"output", a->output},
                         {"resolution", a->resolution},
                         {"brick_size", a->brick},
                         {"seconds", report.seconds_total + seconds_write},
                         {"seconds_distance_field", report.seconds_source},
                         {"seconds_samples", report.seconds_samples},
                         {"seconds_statistics", report.seconds_statistics},
                         {"seconds_bricks", report.seconds_bricks},
                         {"seconds_write", seconds_write},
                         {"peak_rss_mb", peak_rss_mb()},
                         {"estimated_mb", estimate},
                         {"samples", report.samples},
                         {"nodes", tree.nodes.size()},
                         {"bricks", tree.brick_count},
                         {"voxels", tree.voxel_count()},
                         {"bytes", bytes},
                         {"bytes_per_voxel", voxels > 0 ? bytes / voxels : 0.0},
                         {"channels", channels},
                         {"materials", tree.materials.size()},
                         {"surface", surface.empty() ? nlohmann::json(nullptr) : nlohmann::json(surface)}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << what << " -> " << a->output << ": " << tree.depth_count << " levels, " << tree.brick_count
                << " bricks, " << uint64_t(voxels) << " voxels, " << bytes / voxels << " bytes/voxel, "
                << report.seconds_total << " s, peak " << int(peak_rss_mb()) << " MiB\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
