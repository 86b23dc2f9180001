// The paper's comparisons as bench cases (issue 5), registered under
// `svo bench` by cmd_bench.cpp: `fig4` (silhouettes under depth of field
// against alpha blending), `fig11` (light- and view-dependent colour at
// grazing angles), `fig12` (a bumpy specular surface turning glossy at
// distance), and `material --heightmap IMAGE` (Fig. 9 on a non-Gaussian
// height map from a real image).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace svo::tools {

// Registers fig4, fig11 and fig12 on `bench`.
void add_bench_figure_commands(CLI::App& bench, int& exit_code);

// `svo bench material --heightmap IMAGE`: the options beside material's own.
struct HeightmapMaterialArgs {
  std::string heightmap;   // image file; empty: the Gaussian field
  int map_size = 128;      // samples along the longer side after box filtering
  float amplitude = 0;     // scene units per map unit; 0: from --sigma-h
  bool transpose = false;  // swap the map's x and y (the views tilt towards the image's y axis)
};
void add_heightmap_material_options(CLI::App& material, HeightmapMaterialArgs& args);

// Fig. 9 on the height map: ground truth, Eq. 17 from the map's measured
// statistics over the imaged patch, MIP and the engine's one-cone colour;
// writes table.md, material.csv, material.json, material.png and
// heightmap.png to `out`. Throws std::runtime_error "<image>: <why>" for an
// unreadable image.
void run_heightmap_material(const HeightmapMaterialArgs& args, float sigma_h, uint32_t resolution, uint32_t size,
                            uint32_t spp, const std::string& device, const std::string& out);

}  // namespace svo::tools
