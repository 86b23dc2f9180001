// The options that name a surface source, shared by svo voxelize and svo
// reference so that the octree and its ground truth are made from the same
// words: a mesh file or --scene NAME, and the appearance a mesh does not
// carry (--colour, --roughness).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/scenes.h"

namespace svo::tools {

struct SourceOptions {
  std::string input;          // mesh file
  std::string scene;          // --scene NAME
  std::string scene_file;     // --scene-file SCENE.json
  std::vector<float> colour;  // --colour R,G,B (empty: the mesh's or the default)
  float roughness = -1;       // --roughness sigma_rho (< 0: the source's own)
  // Procedural detail octaves (--detail-*; scenes only).
  uint32_t detail_octaves = 0;
  float detail_amplitude = 0.002f;
  float detail_wavelength = 0.02f;
  uint32_t detail_seed = 1;
  // Texture budgets, Mi pixels (--max-texture-mpix, --max-texture-mpix-total).
  double max_texture_mpix = voxelizer::kDefaultMaxTexturePixels / 1048576.0;
  double max_texture_mpix_total = voxelizer::kDefaultMaxTotalTexturePixels / 1048576.0;
};

// The positional mesh file and --scene (group Input); --colour and
// --roughness (group Appearance); --detail-octaves, --detail-amplitude,
// --detail-wavelength, --detail-seed (group Detail); --max-texture-mpix,
// --max-texture-mpix-total (group Limits).
void add_source_options(CLI::App& cmd, SourceOptions& o);

// Throws std::invalid_argument "<command>: give a mesh file, --scene NAME or
// --scene-file SCENE.json" unless exactly one is given, and when detail octaves are asked of a mesh
// or their amplitude exceeds their wavelength.
void check_source_options(const SourceOptions& o, const std::string& command);

// The check of a --resolution option: a power of two from 16 to 4096, the
// one limit the voxelizing commands state (the library takes up to 65536).
CLI::Validator resolution_check();

// "scene NAME", "scene file PATH" or the mesh path, for messages and reports.
std::string source_name(const SourceOptions& o);

// The procedural scene of --scene, with --roughness and the detail octaves
// applied. Throws for an unknown name. With `all_octaves` (ground truth)
// every octave is geometry; without (svo voxelize) only those the lattice
// can draw, the rest folded into the statistics (voxelizer::DetailedScene).
std::unique_ptr<voxelizer::AnalyticScene> make_scene_source(const SourceOptions& o, bool all_octaves = true);

// --colour, --roughness and the texture budgets as mesh options.
voxelizer::MeshOptions mesh_options(const SourceOptions& o);

// The mesh file or the scene file's merged meshes (voxelizer::read_mesh,
// read_scene_file), with mesh_options(o) and `warning`.
voxelizer::TriangleMesh read_source_mesh(const SourceOptions& o, std::function<void(const std::string&)> warning = {});

}  // namespace svo::tools
