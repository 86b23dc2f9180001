#include "source_options.h"

#include <stdexcept>

#include "cli_hint.h"
#include "svo/render/image_io.h"

namespace svo::tools {

void add_source_options(CLI::App& cmd, SourceOptions& o) {
  auto* input =
      cmd.add_option("input", o.input, "Mesh file: OBJ, PLY, OFF, STL or glTF 2.0 (.gltf, .glb)")->group("Input");
  auto* scene = cmd.add_option("--scene", o.scene,
                               "Built-in procedural scene instead of a mesh: bumpy-sphere, heightfield, "
                               "grooved-cylinder, material-spheres (five materials)")
                    ->group("Input");
  auto* scene_file = cmd.add_option("--scene-file", o.scene_file,
                                    "A scene of several meshes, each with a transform and a material (JSON; "
                                    "docs/materials.md, \"Scene files\")")
                         ->group("Input");
  input->excludes(scene);
  input->excludes(scene_file);
  scene->excludes(scene_file);
  cmd.add_option_function<std::string>(
         "--colour",
         [&o](const std::string& text) {
           try {
             const glm::vec3 c = render::parse_colour(text);
             o.colour = {c.r, c.g, c.b};
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError("--colour", e.what());  // one line, naming the command's --help
           }
         },
         "Constant albedo for meshes without colours: R,G,B as linear reflectance, each in [0, 1] (0.5,0.5,0.5 "
         "is mid-grey in radiance, shown as sRGB 188), or #rrggbb as a colour picker gives it (sRGB, converted "
         "to linear: #808080 is 0.216)")
      ->type_name("R,G,B|#rrggbb")
      ->group("Appearance");
  cmd.add_option("--roughness", o.roughness,
                 "Micro-BRDF slope deviation sigma_rho (default: the OBJ material's Pr or Ns, else 0.1)")
      ->check(CLI::Range(0.0f, 4.0f))
      ->group("Appearance");
  cmd.add_option("--detail-octaves", o.detail_octaves,
                 "Procedural detail: octaves of gradient noise displacing a --scene surface, each half the "
                 "wavelength and amplitude of the one before; drawn by the renderer below the stored "
                 "resolution, folded into the statistics above it (0: none)")
      ->check(CLI::Range(0, 32))
      ->default_val(0)
      ->group("Detail");
  cmd.add_option("--detail-amplitude", o.detail_amplitude, "Amplitude of the first detail octave, scene units")
      ->check(positive_number())
      ->default_val(0.002f)
      ->group("Detail");
  cmd.add_option("--detail-wavelength", o.detail_wavelength, "Wavelength of the first detail octave, scene units")
      ->check(positive_number())
      ->default_val(0.02f)
      ->group("Detail");
  cmd.add_option("--detail-seed", o.detail_seed, "Seed of the detail noise")->default_val(1)->group("Detail");
  cmd.add_option("--max-texture-mpix", o.max_texture_mpix,
                 "Largest texture a mesh may name, Mi pixels (2^20; 64 is 8192 x 8192), checked from its header "
                 "before it is decoded")
      ->default_val(o.max_texture_mpix)
      ->check(CLI::Range(1.0, 4096.0))
      ->group("Limits");
  cmd.add_option("--max-texture-mpix-total", o.max_texture_mpix_total,
                 "All textures of the mesh (or scene file) together, Mi pixels; 12 bytes each once read")
      ->default_val(o.max_texture_mpix_total)
      ->check(CLI::Range(1.0, 65536.0))
      ->group("Limits");
}

void check_source_options(const SourceOptions& o, const std::string& command) {
  if (int(!o.input.empty()) + int(!o.scene.empty()) + int(!o.scene_file.empty()) != 1) {
    throw std::invalid_argument(command + ": give a mesh file, --scene NAME or --scene-file SCENE.json");
  }
  if (o.detail_octaves > 0 && o.scene.empty()) {
    throw std::invalid_argument(command +
                                ": --detail-octaves needs --scene (detail octaves displace the built-in scenes)");
  }
  if (o.detail_octaves > 0 && !(o.detail_amplitude <= o.detail_wavelength)) {
    throw std::invalid_argument(command + ": --detail-amplitude " + std::to_string(o.detail_amplitude) +
                                " exceeds --detail-wavelength " + std::to_string(o.detail_wavelength));
  }
}

CLI::Validator resolution_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        unsigned long v = 0;
        const bool number = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos &&
                            text.size() < 10 && (v = std::stoul(text), true);
        if (number && v >= 16 && v <= 4096 && (v & (v - 1)) == 0) return "";
        return "resolution " + text + " is not a power of two from 16 to 4096";
      },
      "POWER OF TWO 16..4096");
}

std::string source_name(const SourceOptions& o) {
  return !o.scene.empty() ? "scene " + o.scene : !o.scene_file.empty() ? "scene file " + o.scene_file : o.input;
}

voxelizer::TriangleMesh read_source_mesh(const SourceOptions& o, std::function<void(const std::string&)> warning) {
  voxelizer::MeshOptions options = mesh_options(o);
  options.warning = std::move(warning);
  return o.scene_file.empty() ? voxelizer::read_mesh(o.input, options)
                              : voxelizer::read_scene_file(o.scene_file, options);
}

std::unique_ptr<voxelizer::AnalyticScene> make_scene_source(const SourceOptions& o, bool all_octaves) {
  auto scene = voxelizer::make_scene(o.scene);
  if (o.roughness >= 0) scene->set_sigma_rho2(o.roughness * o.roughness);
  if (o.detail_octaves == 0) return scene;
  octree::Detail detail =
      voxelizer::make_detail(*scene, o.detail_octaves, o.detail_amplitude, o.detail_wavelength, o.detail_seed);
  return std::make_unique<voxelizer::DetailedScene>(std::move(scene), detail, all_octaves);
}

voxelizer::MeshOptions mesh_options(const SourceOptions& o) {
  voxelizer::MeshOptions options;
  if (o.colour.size() == 3) options.colour = glm::vec3(o.colour[0], o.colour[1], o.colour[2]);
  if (o.roughness >= 0) options.sigma_rho = o.roughness;
  options.max_texture_pixels = o.max_texture_mpix * 1048576.0;
  options.max_total_texture_pixels = o.max_texture_mpix_total * 1048576.0;
  return options;
}

}  // namespace svo::tools
