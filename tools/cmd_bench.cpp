// svo bench speed-error: for each view, the time and the error against the
// ground truth of every way the engine can draw a frame: one pre-filtered
// cone per pixel, the three baselines, and supersampled ray marching of the
// finest level at 1, 4, 16 and 64 rays per pixel (DESIGN section 9).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/common.hpp>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "bench_tie.h"
#include "bench_util.h"
#include "cmd_bench_figures.h"
#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/material.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "view_options.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::fmt;
using bench::run_gnuplot;
using bench::sci;

struct SpeedErrorArgs {
  SourceOptions source;
  uint32_t resolution = 256;
  std::string views = "far,mid,close";
  uint32_t size = 256;
  uint32_t reference_spp = 256;
  uint32_t repeats = 3;
  bool shadows = false;
  LightingOptions lighting;  // --env, --material: the forward pass at several spp instead of the tracer's modes
  std::string device;
  std::string out = "bench-speed-error";
  double tie_tolerance = bench::kErrorTieTolerance;
};

// One way of drawing a frame.
struct Method {
  std::string name;  // as in the tables: "prefiltered", ..., "raymarch-16"
  render::Mode mode;
  uint32_t spp;
};

struct Row {
  std::string view, method;
  uint32_t spp = 1;
  double ms = 0;  // median GPU time
  double us_per_pixel = 0;
  double relmse = 0, rmse = 0, psnr = 0, coverage_error = 0, coverage_error_silhouette = 0;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  for (std::string p; std::getline(in, p, ',');) parts.push_back(p);
  return parts;
}

// One panel per view, time against relMSE: ray marching as a line through
// its 1-64 rays per pixel, each one-cone method as its own point style named
// in the key (the one-cone methods often lie within a few percent of each
// other: labels beside the points overprinted).
void write_plot(const fs::path& dir, const std::vector<std::string>& views, const std::vector<std::string>& singles,
                const std::string& title) {
  bench::TextFile gp(dir / "plot.gp");
  gp << "set terminal pngcairo size " << std::max<size_t>(480, 440 * views.size()) << ",480 font 'sans,10'\n"
     << "set output '" << (dir / "speed-error.png").string()
     << "'\nset datafile separator ','\nset logscale xy\nset grid\nset key outside bottom center horizontal\n"
     << "set xlabel 'ms per frame (GPU)'\nset ylabel 'relMSE'\nset offsets graph 0.05, graph 0.05, graph 0.05, "
        "graph 0.05\n"
     << "set multiplot layout 1," << views.size() << " title '" << title << "'\n";
  const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2"};
  const int points[] = {7, 5, 9, 11, 13, 3};
  for (const auto& v : views) {
    gp << "set title '" << v << "'\nplot '" << (dir / "results.csv").string()
       << "' every ::1 using (stringcolumn(1) eq '" << v
       << "' && strstrt(stringcolumn(2),'raymarch') ? $4 : 1/0):6 with linespoints lc '#777777' pt 6 "
       << "title 'ray marching 1-64 rays'";
    for (size_t i = 0; i < singles.size(); ++i) {
      gp << ", '' every ::1 using (stringcolumn(1) eq '" << v << "' && stringcolumn(2) eq '" << singles[i]
         << "' ? $4 : 1/0):6 with points pt " << points[i % 6] << " ps 1.6 lc '" << colours[i % 6] << "' title '"
         << singles[i] << "'";
    }
    gp << "\n";
  }
  gp << "unset multiplot\n";
  gp.save();
  run_gnuplot(dir / "plot.gp");
}

void run_speed_error(const SpeedErrorArgs& a) {
  check_source_options(a.source, "svo bench speed-error");
  const std::vector<std::string> views = split(a.views);
  for (const auto& v : views) {
    const auto names = render::view_preset_names();
    if (std::find(names.begin(), names.end(), v) == names.end()) {
      throw std::invalid_argument("svo bench speed-error: unknown view '" + v + "' (views: far, mid, close)");
    }
  }
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "results.csv").string());

  // The octree and the ground truth's geometry, from the same source.
  ProgressBar bar("bench");
  voxelizer::VoxelizeOptions vo;
  vo.resolution = a.resolution;
  // The bar's fraction runs once over the whole bench (voxelize 10%, then
  // each view: its ground truth half, its methods half), so that the time
  // left is extrapolated from the time so far.
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + stage, 0.1 * f); };
  std::unique_ptr<voxelizer::AnalyticScene> scene;
  std::unique_ptr<reference::Geometry> geometry;
  octree::Octree tree;
  if (!a.source.scene.empty()) {
    scene = make_scene_source(a.source);
    tree = voxelizer::voxelize(*scene, vo);
    geometry = reference::scene_geometry(*scene);
  } else {
    voxelizer::TriangleMesh mesh = read_source_mesh(a.source);
    tree = voxelizer::voxelize(*voxelizer::mesh_source(mesh), vo);
    geometry = reference::mesh_geometry(std::move(mesh));
  }

  std::unique_ptr<render::Renderer> renderer = render::make_renderer(tree, {a.device});
  render::Renderer& gpu = *renderer;
  // Image-based lighting (an environment, a material, or the scene's own
  // materials): the forward pass's speed against error as its samples grow,
  // the baseline curve of the shading modules.
  const bool lit = shades_forward(a.lighting, tree);
  const std::vector<Method> methods = lit ? std::vector<Method>{{"forward-16", render::Mode::Prefiltered, 16},
                                                                {"forward-64", render::Mode::Prefiltered, 64},
                                                                {"forward-256", render::Mode::Prefiltered, 256}}
                                          : std::vector<Method>{{"prefiltered", render::Mode::Prefiltered, 1},
                                                                {"nearest", render::Mode::Nearest, 1},
                                                                {"alpha", render::Mode::Alpha, 1},
                                                                {"mip", render::Mode::Mip, 1},
                                                                {"raymarch-1", render::Mode::RayMarch, 1},
                                                                {"raymarch-4", render::Mode::RayMarch, 4},
                                                                {"raymarch-16", render::Mode::RayMarch, 16},
                                                                {"raymarch-64", render::Mode::RayMarch, 64}};
  if (lit) gpu.add_pass(render::make_pass("forward"));

  std::vector<Row> rows;
  nlohmann::json headline = nlohmann::json::object();
  for (size_t vi = 0; vi < views.size(); ++vi) {
    const std::string& view = views[vi];
    render::RenderSettings s;
    s.width = s.height = a.size;
    s.camera = render::view_preset(tree, view);
    s.shadows = a.shadows;
    apply_lighting(a.lighting, s);
    reference::ReferenceSettings rs;
    rs.render = s;
    rs.spp = a.reference_spp;
    const double view_start = 0.1 + 0.9 * double(vi) / double(views.size()), view_share = 0.9 / double(views.size());
    rs.progress = [&](double f) {
      bar.update(view + ": reference", uint64_t(f * a.size + 0.5), a.size, "rows", view_start + 0.5 * view_share * f);
    };
    render::Frame truth = reference::render_reference(*geometry, rs);
    render::write_colour((dir / (view + "-reference.exr")).string(), truth);
    const render::Image truth_image = render::frame_image(truth);
    for (size_t mi = 0; mi < methods.size(); ++mi) {
      const Method& m = methods[mi];
      bar.update(view + ": " + m.name, view_start + view_share * (0.5 + 0.5 * double(mi) / double(methods.size())));
      s.mode = m.mode;
      s.spp = lit ? 1 : m.spp;
      s.shading.spp = m.spp;
      std::vector<double> ms;
      render::Frame f;
      for (uint32_t r = 0; r < std::max(1u, a.repeats); ++r) {
        f = gpu.render(s);
        ms.push_back(render::frame_ms(f));
      }
      std::sort(ms.begin(), ms.end());
      render::write_colour((dir / (view + "-" + m.name + ".png")).string(), f);
      reference::ImageErrors e = reference::compare_images(render::frame_image(f), truth_image, m.name, "reference");
      Row row;
      row.view = view;
      row.method = m.name;
      row.spp = m.spp;
      row.ms = ms[ms.size() / 2];
      row.us_per_pixel = f.covered_pixels ? row.ms * 1000.0 / double(f.covered_pixels) : 0.0;
      row.relmse = e.relmse;
      row.rmse = e.rmse;
      row.psnr = e.psnr;
      row.coverage_error = e.coverage_error.value_or(0.0);
      row.coverage_error_silhouette = e.coverage_error_silhouette.value_or(0.0);
      rows.push_back(row);
    }
    if (lit) continue;  // the rows are the curve; the modules' benches weigh it
    // Headline: speed-up of one pre-filtered cone over supersampled marching
    // at equal error, or a tie when the errors are within their noise.
    std::vector<bench::CostErrorPoint> march;
    const Row* ours = nullptr;
    for (const auto& r : rows) {
      if (r.view != view) continue;
      if (r.method.rfind("raymarch", 0) == 0) march.push_back({r.method, r.ms, r.relmse});
      if (r.method == "prefiltered") ours = &r;
    }
    nlohmann::json h = {{"prefiltered_ms", ours->ms}, {"prefiltered_relmse", ours->relmse}};
    const bench::EqualErrorClaim claim = bench::claim_at_equal_error(ours->ms, ours->relmse, march, a.tie_tolerance);
    using Kind = bench::EqualErrorClaim::Kind;
    if (claim.kind == Kind::Speedup) {
      h["raymarch_ms_at_equal_error"] = claim.factor * ours->ms;
      h["speedup"] = claim.factor;
    } else if (claim.kind == Kind::AtLeast) {
      h["speedup_at_least"] = claim.factor;
      h["compared_with"] = claim.against;
    } else if (claim.kind == Kind::Tie) {
      h["tie"] = true;
      h["tied_with"] = claim.against;
      h["tied_relmse"] = claim.against_error;
      h["tied_ms"] = claim.factor * ours->ms;
    }
    // The spread of every method's relMSE in this view, for the summary.
    double lo = ours->relmse, hi = ours->relmse;
    for (const auto& r : rows) {
      if (r.view == view) lo = std::min(lo, r.relmse), hi = std::max(hi, r.relmse);
    }
    h["relmse_min"] = lo;
    h["relmse_max"] = hi;
    headline[view] = h;
  }
  bar.finish();

  // CSV, JSON, Markdown, plot.
  {
    bench::TextFile csv(dir / "results.csv");
    csv << "view,method,spp,ms,us_per_covered_pixel,relmse,rmse,psnr,coverage_error,coverage_error_silhouette\n";
    for (const auto& r : rows) {
      csv << r.view << "," << r.method << "," << r.spp << "," << r.ms << "," << r.us_per_pixel << "," << r.relmse << ","
          << r.rmse << "," << r.psnr << "," << r.coverage_error << "," << r.coverage_error_silhouette << "\n";
    }
    csv.save();
  }
  nlohmann::json j;
  j["source"] = source_name(a.source);
  j["resolution"] = a.resolution;
  j["size"] = a.size;
  j["reference_spp"] = a.reference_spp;
  j["device"] = gpu.device_name();
  j["headline"] = headline;
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows) {
    j["rows"].push_back({{"view", r.view},
                         {"method", r.method},
                         {"spp", r.spp},
                         {"ms", r.ms},
                         {"us_per_covered_pixel", r.us_per_pixel},
                         {"relmse", r.relmse},
                         {"rmse", r.rmse},
                         {"psnr", r.psnr},
                         {"coverage_error", r.coverage_error},
                         {"coverage_error_silhouette", r.coverage_error_silhouette}});
  }
  files::write_file((dir / "results.json").string(), j.dump(2) + "\n");
  std::ostringstream md;
  md << "Source " << source_name(a.source) << " at " << a.resolution << "^3, " << a.size << "x" << a.size
     << ", reference " << a.reference_spp << " spp, device " << gpu.device_name() << ", median of " << a.repeats
     << " frames" << (lit ? ", image-based lighting (forward pass)" : "")
     << ".\n\n| view | method | ms | us per covered pixel | relMSE | RMSE | coverage error (silhouette) |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    md << "| " << r.view << " | " << r.method << " | " << fmt(r.ms, 1) << " | " << fmt(r.us_per_pixel, 2) << " | "
       << sci(r.relmse) << " | " << sci(r.rmse) << " | " << fmt(r.coverage_error_silhouette, 3) << " |\n";
  }
  if (!lit) {
    md << "\n| view | prefiltered against ray marching at equal relMSE |\n|---|---|\n";
  }
  for (const auto& v : lit ? std::vector<std::string>{} : views) {
    const auto& h = headline[v];
    const double ours_ms = h["prefiltered_ms"].get<double>();
    std::string says;
    // "12.3x faster", or for a ratio below one "4.2x slower".
    auto ratio = [](double f) { return f >= 1 ? fmt(f, 1) + "x faster" : fmt(1 / f, 1) + "x slower"; };
    if (h.contains("speedup")) {
      says = ratio(h["speedup"].get<double>());
    } else if (h.contains("speedup_at_least")) {
      says = "at least " + ratio(h["speedup_at_least"].get<double>()) + " (more accurate than " +
             h["compared_with"].get<std::string>() + " beyond the noise)";
    } else if (h.contains("tie")) {
      says = "tie: relMSE " + sci(h["prefiltered_relmse"].get<double>()) + " against " +
             sci(h["tied_relmse"].get<double>()) + " for " + h["tied_with"].get<std::string>() + ", within the " +
             fmt(100 * a.tie_tolerance, 0) + "% noise; prefiltered " + fmt(ours_ms, 2) + " ms, " +
             h["tied_with"].get<std::string>() + " " + fmt(h["tied_ms"].get<double>(), 2) + " ms";
    } else {
      says = "none: less accurate than 1 ray per pixel";
    }
    md << "| " << v << " | " << says << " |\n";
  }
  if (!lit) {
    md << "\nErrors within " << fmt(100 * a.tie_tolerance, 0)
       << "% of each other (relative, --tie-tolerance) are a tie: the ground truth's own noise and the octree's "
          "resolution move relMSE by that much, so no speed-up is claimed from them.";
    for (const auto& v : views) {
      const auto& h = headline[v];
      const double lo = h["relmse_min"].get<double>(), hi = h["relmse_max"].get<double>();
      if (bench::errors_tie(lo, hi, a.tie_tolerance)) {
        md << " In the " << v << " view every method's relMSE lies within " << fmt(100 * (hi - lo) / hi, 1) << "% ("
           << sci(lo) << " to " << sci(hi) << "): the error there does not tell the methods apart.";
      }
    }
    md << "\n";
  }
  files::write_file((dir / "table.md").string(), md.str());
  std::vector<std::string> singles;
  for (const auto& m : methods) {
    if (m.name.rfind("raymarch", 0) != 0) singles.push_back(m.name);
  }
  write_plot(dir, views, singles, "speed against error: " + source_name(a.source));
  std::cout << md.str();
}

struct MaterialArgs {
  float sigma_h = 0.0075f;
  uint32_t resolution = 256;
  uint32_t size = 64;
  uint32_t spp = 4;
  std::string device;
  std::string out = "bench-material";
};

// Paper Fig. 9: colour against view angle on a Gaussian height field (the
// built-in scene's waves and colours at height deviation --sigma-h), lights
// off: ground truth, Eq. 17 from the field's statistics, MIP, and what the
// engine draws with one prefiltered cone per pixel of a 4-pixel-high image
// (coarse levels) of the voxelized field.
void run_material(const MaterialArgs& a) {
  fs::path dir(a.out);
  fs::create_directories(dir);
  render::check_writable_output((dir / "material.csv").string());
  voxelizer::HeightfieldScene field(64, 0.08f, 0.25f, a.sigma_h, 5, glm::vec3(0.45f, 0.4f, 0.3f),
                                    glm::vec3(0.3f, 0.2f, 0.15f));
  ProgressBar bar("bench material");
  reference::MaterialOptions o;
  o.degrees = {0, 10, 20, 30, 40, 50, 60, 70, 75, 80, 85};
  o.size = a.size;
  o.spp = a.spp;
  o.progress = [&](double f) { bar.update("ground truth", 0.5 * f); };
  std::vector<reference::MaterialPoint> curve = reference::material_curve(field, o);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = a.resolution;
  vo.progress = [&](const std::string& stage, double f) { bar.update("voxelize " + stage, 0.5 + 0.4 * f); };
  octree::Octree tree = voxelizer::voxelize(field, vo);
  std::unique_ptr<render::Renderer> renderer = render::make_renderer(tree, {a.device});
  render::Renderer& gpu = *renderer;
  bench::TextFile csv(dir / "material.csv");
  csv << "degrees,truth_r,truth_g,truth_b,eq17_r,eq17_g,eq17_b,mip_r,mip_g,mip_b,engine_r,engine_g,engine_b\n";
  std::ostringstream md;
  md << "Gaussian height field, sigma_h " << a.sigma_h << ", slope variance " << sci(field.slope_variance().x) << ", "
     << sci(field.slope_variance().y) << "; ground truth " << a.size << " pixels high, " << a.spp
     << " spp; engine: octree " << a.resolution << "^3, one prefiltered cone per pixel, 4 pixels high.\n\n"
     << "| degrees | ground truth (R G B) | Eq. 17 | error | MIP | error | engine | error "
        "|\n|---|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < curve.size(); ++i) {
    glm::vec3 engine = bench::engine_material_colour(gpu, curve[i].degrees, o);
    bar.update("engine", 0.9 + 0.1 * double(i + 1) / double(curve.size()));
    bench::write_material_row(csv, md, curve[i], engine);
  }
  bar.finish();
  csv.save();
  files::write_file((dir / "table.md").string(), md.str());
  bench::write_material_plot(dir, "");
  run_gnuplot(dir / "material.gp");
  std::cout << md.str();
}

}  // namespace

void add_bench_command(CLI::App& app, int& exit_code) {
  CLI::App* bench = app.add_subcommand("bench", "Speed against error: tables, CSV, JSON and plots (DESIGN section 9)");
  bench->require_subcommand(1);

  auto a = std::make_shared<SpeedErrorArgs>();
  CLI::App* se = bench->add_subcommand(
      "speed-error",
      "For each view: GPU time and error against the ground truth (svo reference) of prefiltered, nearest, alpha, "
      "mip and ray marching of the finest level at 1, 4, 16 and 64 rays per pixel; with --env or --material (or a "
      "source with materials of its own), the forward pass at 16, 64 and 256 samples per pixel instead, the ground "
      "truth under the same lighting; writes table.md, results.csv, results.json, speed-error.png (gnuplot) and the "
      "images to --out");
  add_source_options(*se, a->source);
  se->add_option("--resolution", a->resolution, "Finest lattice cells per axis of the octree")
      ->default_val(256)
      ->check(CLI::Range(16u, 2048u));
  se->add_option("--views", a->views, "Comma-separated view presets")->default_val("far,mid,close");
  se->add_option("--size", a->size, "Image width and height, pixels")->default_val(256)->check(CLI::Range(8u, 4096u));
  se->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the ground truth")
      ->default_val(256)
      ->check(CLI::Range(1u, 65536u));
  se->add_option("--repeats", a->repeats, "Frames per method; the median time is reported")
      ->default_val(3)
      ->check(CLI::Range(1u, 100u));
  se->add_flag("--shadows", a->shadows, "Soft shadows in every method and in the ground truth");
  se->add_option("--tie-tolerance", a->tie_tolerance,
                 "Relative difference of relMSE below which two methods tie (no speed-up is claimed)")
      ->default_val(bench::kErrorTieTolerance)
      ->check(CLI::Range(0.0, 1.0));
  add_lighting_options(*se, a->lighting);
  se->add_option("--device", a->device, kDeviceHelp);
  se->add_option("-o,--out", a->out, "Output directory (created)")->default_val("bench-speed-error");
  se->callback([a, &exit_code] {
    run_speed_error(*a);
    exit_code = 0;
  });

  auto m = std::make_shared<MaterialArgs>();
  CLI::App* mat = bench->add_subcommand(
      "material",
      "Paper Fig. 9: colour against view angle (0-85 degrees) on a Gaussian height field coloured by height, lights "
      "off: ground truth (svo reference averaged over the field), Eq. 17 from the field's statistics, MIP, and the "
      "engine's prefiltered cone; with --heightmap IMAGE the same on a non-Gaussian height map from an image, with "
      "Eq. 17 from its measured statistics (also material.json and heightmap.png); writes table.md, material.csv and "
      "material.png (gnuplot) to --out");
  mat->add_option("--sigma-h", m->sigma_h, "Height deviation of the field (the built-in heightfield scene uses 0.02)")
      ->default_val(0.0075f)
      ->check(CLI::Range(0.001f, 0.05f));
  mat->add_option("--resolution", m->resolution, "Octree resolution for the engine's curve")
      ->default_val(256)
      ->check(CLI::Range(16u, 2048u));
  mat->add_option("--size", m->size, "Ground-truth image height, pixels")
      ->default_val(64)
      ->check(CLI::Range(4u, 1024u));
  mat->add_option("--spp", m->spp, "Ground-truth samples per pixel")->default_val(4)->check(CLI::Range(1u, 4096u));
  mat->add_option("--device", m->device, kDeviceHelp);
  mat->add_option("-o,--out", m->out, "Output directory (created)")->default_val("bench-material");
  auto hm = std::make_shared<HeightmapMaterialArgs>();
  add_heightmap_material_options(*mat, *hm);
  mat->callback([m, hm, &exit_code] {
    if (hm->heightmap.empty()) {
      run_material(*m);
    } else {
      run_heightmap_material(*hm, m->sigma_h, m->resolution, m->size, m->spp, m->device, m->out);
    }
    exit_code = 0;
  });

  add_bench_figure_commands(*bench, exit_code);

  add_bench_zoom_command(*bench, exit_code);

  add_bench_lobe_command(*bench, exit_code);
  add_bench_luminaire_command(*bench, exit_code);
  add_bench_bandwidth_command(*bench, exit_code);
}

}  // namespace svo::tools
