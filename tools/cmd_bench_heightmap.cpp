// svo bench material --heightmap IMAGE: paper Fig. 9, bottom ("a real-world
// texture which is not really Gaussian"): the colour of a height map from an
// image against view angle, lights off, as `svo bench material` does for the
// Gaussian field, with Eq. 17 and MIP from the map's measured statistics.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <glm/common.hpp>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench_util.h"
#include "cmd_bench_figures.h"
#include "progress.h"
#include "svo/octree/files.h"
#include "svo/reference/material.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/heightmap_scene.h"

namespace svo::tools {

namespace fs = std::filesystem;
using bench::fmt;
using bench::sci;

void add_heightmap_material_options(CLI::App& mat, HeightmapMaterialArgs& h) {
  mat.add_option("--heightmap", h.heightmap,
                 "Image file (PNG, JPEG, EXR, ...) whose luminance is the height of a non-Gaussian field, instead of "
                 "the Gaussian one (e.g. /usr/share/glmark2/textures/terrain-grasslight-512.jpg from glmark2-data)")
      ->group("Height map");
  mat.add_option("--map-size", h.map_size, "Samples along the map's longer side after box filtering")
      ->default_val(128)
      ->check(CLI::Range(4, 4096))
      ->group("Height map");
  mat.add_option("--amplitude", h.amplitude,
                 "Scene units of height per unit of luminance (0: the amplitude that gives the map height deviation "
                 "--sigma-h)")
      ->default_val(0)
      ->check(CLI::Range(0.0f, 10.0f))
      ->group("Height map");
  mat.add_flag("--transpose", h.transpose,
               "Swap the map's x and y: the views tilt towards the image's vertical axis instead of its horizontal one")
      ->group("Height map");
}

void run_heightmap_material(const HeightmapMaterialArgs& h, float sigma_h, uint32_t resolution, uint32_t size,
                            uint32_t spp, const std::string& device, const std::string& out) {
  const glm::vec3 abar0(0.45f, 0.4f, 0.3f), a_s0(0.3f, 0.2f, 0.15f);  // as the Gaussian field's
  voxelizer::HeightMap map = voxelizer::read_height_map(h.heightmap, h.map_size);
  if (h.transpose) {
    voxelizer::HeightMap t;
    t.width = map.height;
    t.height = map.width;
    for (int j = 0; j < t.height; ++j) {
      for (int i = 0; i < t.width; ++i) t.values.push_back(map.at(j, i));
    }
    map = std::move(t);
  }
  fs::path dir(out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "material.csv").string());
  float amplitude = h.amplitude;
  if (!(amplitude > 0)) {
    voxelizer::HeightmapScene unit(map, 1.0f, abar0, a_s0);
    if (!(unit.sigma_h() > 0)) throw std::runtime_error(h.heightmap + ": the image is flat (no height variation)");
    amplitude = sigma_h / unit.sigma_h();
  }
  voxelizer::HeightmapScene field(map, amplitude, abar0, a_s0);
  reference::MaterialOptions o;
  o.degrees = {0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 85};
  o.size = size;
  o.spp = spp;
  // Eq. 17 and MIP from the statistics of the patch the images span.
  const glm::vec2 half(0.5f * o.patch);
  const voxelizer::SurfaceStatistics patch = field.statistics(-half, half);
  const voxelizer::SurfaceStatistics whole = field.statistics(glm::vec2(-1), glm::vec2(1));
  reference::MaterialStatistics ms;
  ms.slope_variance = glm::vec2(patch.slope_variance);
  ms.abar = glm::vec3(patch.abar);
  ms.a_s = glm::vec3(patch.a_s);

  ProgressBar bar("bench material");
  o.progress = [&](double f) { bar.update("ground truth", 0.5 * f); };
  std::vector<reference::MaterialPoint> curve = reference::material_curve(field, ms, o);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + stage, 0.5 + 0.4 * f); };
  octree::Octree tree = voxelizer::voxelize(field, vo);
  std::unique_ptr<render::Renderer> renderer = render::make_renderer(tree, {device});
  render::Renderer& gpu = *renderer;

  const auto rel = bench::relative_error;
  bench::TextFile csv(dir / "material.csv");
  csv << "degrees,truth_r,truth_g,truth_b,eq17_r,eq17_g,eq17_b,mip_r,mip_g,mip_b,engine_r,engine_g,engine_b\n";
  std::ostringstream md;
  md << "Height map " << fs::path(h.heightmap).filename().string() << (h.transpose ? " transposed" : "") << " ("
     << map.width << "x" << map.height << " samples, bilinear over [-1, 1]^2), amplitude " << sci(amplitude)
     << "; over the imaged patch: sigma_h " << sci(std::sqrt(patch.height_variance)) << ", height skewness "
     << fmt(patch.skewness, 2) << ", excess kurtosis " << fmt(patch.excess_kurtosis, 2)
     << " (a Gaussian: 0, 0), slope variance " << sci(patch.slope_variance.x) << ", " << sci(patch.slope_variance.y)
     << "; ground truth " << size << " pixels high, " << spp << " spp; engine: octree " << resolution
     << "^3, one prefiltered cone per pixel, 4 pixels high.\n\n"
     << "| degrees | ground truth (R G B) | Eq. 17 | error | MIP | error | engine | error |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  nlohmann::json rows = nlohmann::json::array();
  double worst17 = 0, worst_mip = 0, worst_engine = 0;
  for (size_t i = 0; i < curve.size(); ++i) {
    const auto& p = curve[i];
    glm::vec3 engine = bench::engine_material_colour(gpu, p.degrees, o);
    bar.update("engine", 0.9 + 0.1 * double(i + 1) / double(curve.size()));
    bench::write_material_row(csv, md, p, engine);
    const double e17 = rel(p.eq17, p.truth), emip = rel(p.mip, p.truth), eeng = rel(engine, p.truth);
    worst17 = std::max(worst17, e17), worst_mip = std::max(worst_mip, emip),
    worst_engine = std::max(worst_engine, eeng);
    auto arr = [](glm::vec3 c) { return nlohmann::json::array({c.x, c.y, c.z}); };
    rows.push_back({{"degrees", p.degrees},
                    {"truth", arr(p.truth)},
                    {"eq17", arr(p.eq17)},
                    {"mip", arr(p.mip)},
                    {"engine", arr(engine)},
                    {"eq17_error", e17},
                    {"mip_error", emip},
                    {"engine_error", eeng}});
  }
  bar.finish();
  csv.save();
  md << "\nLargest error over the angles: Eq. 17 " << fmt(100 * worst17, 2) << "%, MIP " << fmt(100 * worst_mip, 2)
     << "%, engine " << fmt(100 * worst_engine, 2) << "%.\n";
  files::write_file((dir / "table.md").string(), md.str());
  auto stats_json = [](const voxelizer::SurfaceStatistics& s) {
    return nlohmann::json{{"area", s.area},
                          {"mean_height", s.mean_height},
                          {"sigma_h", std::sqrt(s.height_variance)},
                          {"skewness", s.skewness},
                          {"excess_kurtosis", s.excess_kurtosis},
                          {"slope_variance", {s.slope_variance.x, s.slope_variance.y}},
                          {"abar", {s.abar.x, s.abar.y, s.abar.z}},
                          {"a_s", {s.a_s.x, s.a_s.y, s.a_s.z}}};
  };
  nlohmann::json j{{"heightmap", h.heightmap},
                   {"transpose", h.transpose},
                   {"map_width", map.width},
                   {"map_height", map.height},
                   {"amplitude", amplitude},
                   {"patch_statistics", stats_json(patch)},
                   {"map_statistics", stats_json(whole)},
                   {"resolution", resolution},
                   {"size", size},
                   {"spp", spp},
                   {"device", gpu.device_name()},
                   {"max_error", {{"eq17", worst17}, {"mip", worst_mip}, {"engine", worst_engine}}},
                   {"rows", rows}};
  files::write_file((dir / "material.json").string(), j.dump(2) + "\n");
  // The map as a grey picture (linear values scaled to [0, 1]), top row first.
  {
    render::Frame img;
    img.width = uint32_t(map.width);
    img.height = uint32_t(map.height);
    auto [lo, hi] = std::minmax_element(map.values.begin(), map.values.end());
    const float scale = *hi > *lo ? 1.0f / (*hi - *lo) : 0.0f;
    for (int y = map.height - 1; y >= 0; --y) {
      for (int x = 0; x < map.width; ++x) {
        float v = (map.at(x, y) - *lo) * scale;
        img.colour.push_back(glm::vec4(v, v, v, 1));
      }
    }
    render::write_colour((dir / "heightmap.png").string(), img);
  }
  bench::write_material_plot(dir, "height map " + fs::path(h.heightmap).filename().string() +
                                       (h.transpose ? " (transposed)" : ""));
  bench::run_gnuplot(dir / "material.gp");
  std::cout << md.str();
}

}  // namespace svo::tools
