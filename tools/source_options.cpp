#include "source_options.h"

#include <stdexcept>

namespace svo::tools {

void add_source_options(CLI::App& cmd, SourceOptions& o) {
  auto* input = cmd.add_option("input", o.input, "Mesh file: OBJ, PLY, OFF or STL")->group("Input");
  auto* scene =
      cmd.add_option("--scene", o.scene,
                     "Built-in procedural scene instead of a mesh: bumpy-sphere, heightfield, grooved-cylinder")
          ->group("Input");
  input->excludes(scene);
  cmd.add_option("--colour", o.colour, "Constant colour R,G,B in [0, 1] for meshes without colours")
      ->delimiter(',')
      ->expected(3)
      ->check(CLI::Range(0.0f, 1.0f))
      ->group("Appearance");
  cmd.add_option("--roughness", o.roughness,
                 "Micro-BRDF slope deviation sigma_rho (default: the OBJ material's Pr or Ns, else 0.1)")
      ->check(CLI::Range(0.0f, 4.0f))
      ->group("Appearance");
}

void check_source_options(const SourceOptions& o, const std::string& command) {
  if (o.input.empty() == o.scene.empty()) throw std::invalid_argument(command + ": give a mesh file or --scene NAME");
}

std::string source_name(const SourceOptions& o) { return o.input.empty() ? "scene " + o.scene : o.input; }

std::unique_ptr<voxelizer::AnalyticScene> make_scene_source(const SourceOptions& o) {
  auto scene = voxelizer::make_scene(o.scene);
  if (o.roughness >= 0) scene->set_sigma_rho2(o.roughness * o.roughness);
  return scene;
}

voxelizer::MeshOptions mesh_options(const SourceOptions& o) {
  voxelizer::MeshOptions options;
  if (o.colour.size() == 3) options.colour = glm::vec3(o.colour[0], o.colour[1], o.colour[2]);
  if (o.roughness >= 0) options.sigma_rho = o.roughness;
  return options;
}

}  // namespace svo::tools
