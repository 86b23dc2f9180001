// svo bench zoom: the temporal-coherence figure of a camera path (issue 6).
// For every frame of the path (svo flythrough's deep zoom or a path file)
// it renders the octree with the pre-filtered cone tracer and the source
// geometry with the ground truth (svo reference), and reports:
//   - the frame-to-frame change of each (mean |frame f - frame f-1| over
//     all pixels and R, G, B, linear radiance) and their ratio: a zoom
//     changes the picture by itself, so popping shows as change beyond the
//     ground truth's on the same frames;
//   - the mean colour of the zoomed region (the centre window, a quarter of
//     the area) of both and their relative difference (colour shift);
//   - relMSE of each frame against its ground truth (svo compare's figure).
// A bench, not a flythrough option, because it needs the source geometry as
// well as the octree, as svo reference does: the .svo file does not record
// its source.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench_util.h"
#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"
#include "view_options.h"
#include "zoom_path.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;
using bench::fmt;
using bench::sci;

struct ZoomArgs {
  std::string octree;
  SourceOptions source;
  std::string out = "bench-zoom";
  PathOptions path;
  ViewOptions view;
  uint32_t spp = 64;
  uint64_t seed = 1;
  uint32_t strip = 8;
  std::string device;
};

struct ZoomRow {
  uint32_t frame = 0;
  double zoom = 1, view_width = 0;
  double ms = 0;
  double reference_s = 0;
  double change = -1, change_reference = -1;  // -1 on the first frame
  glm::dvec3 centre{0}, centre_reference{0};
  double colour_shift = 0;
  double relmse = 0;
};

std::string numbered(const char* stem, uint32_t f, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04u.%s", stem, f, ext);
  return name;
}

double shift(glm::dvec3 a, glm::dvec3 reference) {
  const double norm = glm::length(reference);
  return norm > 0 ? glm::length(a - reference) / norm : 0.0;
}

void write_plot(const fs::path& dir, const std::string& title) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    std::cerr << "svo bench zoom: gnuplot is not installed; no plot (apt-get install gnuplot-nox)\n";
    return;
  }
  bench::TextFile gp(dir / "coherence.gp");
  const std::string csv = (dir / "coherence.csv").string();
  gp << "set terminal pngcairo size 1100,420 font 'sans,10'\nset output '" << (dir / "coherence.png").string()
     << "'\nset datafile separator ','\nset grid\nset key top right\nset logscale x\n"
     << "set multiplot layout 1,2 title '" << title << "'\n"
     << "set title 'frame-to-frame change (mean |dRGB|)'\nset xlabel 'zoom'\nset logscale y\n"
     << "plot '" << csv << "' every ::2 using 2:5 with linespoints pt 7 title 'prefiltered', '' every ::2 using 2:6 "
     << "with linespoints pt 6 title 'ground truth'\n"
     << "unset logscale y\nset title 'colour shift of the centre window'\nset ylabel 'relative'\n"
     << "plot '" << csv << "' every ::1 using 2:14 with linespoints pt 7 title '|mean - mean_{ref}| / |mean_{ref}|'\n"
     << "unset multiplot\n";
  gp.save();
  if (std::system(("gnuplot '" + (dir / "coherence.gp").string() + "'").c_str()) != 0) {
    std::cerr << "svo bench zoom: gnuplot failed on " << (dir / "coherence.gp").string() << "\n";
  }
}

void run_zoom(const ZoomArgs& a) {
  // --- Everything that can be checked before the files are read.
  check_source_options(a.source, "svo bench zoom");
  check_view_options(a.view);
  std::optional<render::CameraPath> loaded = check_path_options(a.path);
  make_output_directory(a.out);
  const fs::path dir(a.out);
  fs::create_directories(dir / "frames");
  render::check_writable_output((dir / "coherence.csv").string());

  // --- The octree, the source, the path.
  octree::Octree tree = octree::load_svo(a.octree);
  const auto file_bytes = fs::file_size(a.octree);
  std::unique_ptr<voxelizer::AnalyticScene> scene;
  std::unique_ptr<reference::Geometry> geometry;
  if (!a.source.scene.empty()) {
    scene = make_scene_source(a.source);
    if (a.source.roughness < 0) scene->set_sigma_rho2(tree.sigma_rho2);
    geometry = reference::scene_geometry(*scene);
  } else {
    voxelizer::TriangleMesh mesh = read_source_mesh(a.source);
    if (a.source.roughness < 0) mesh.sigma_rho2 = tree.sigma_rho2;
    geometry = reference::mesh_geometry(std::move(mesh));
  }
  const float aspect = float(a.view.width) / float(a.view.height);
  const render::CameraPath path = resolve_path(a.path, loaded, tree, aspect, a.octree);
  const std::vector<render::Camera> cameras = render::path_cameras(path);
  render::save_camera_path((dir / "path.json").string(), path);

  render::RenderSettings settings;
  settings.width = a.view.width;
  settings.height = a.view.height;
  settings.shadows = a.view.shadows;
  settings.lights = make_lights(a.view, tree.origin + glm::vec3(0.5f * tree.size), cameras.front());
  std::unique_ptr<render::Renderer> renderer = render::make_renderer(tree, {a.device});
  render::Renderer& gpu = *renderer;

  // --- Frames: ours, the ground truth, the figures.
  ProgressBar bar("bench zoom");
  const auto n = uint32_t(cameras.size());
  const std::vector<uint32_t> strip_at = strip_indices(n, a.strip);
  std::vector<render::Frame> strip_ours, strip_truth;
  std::vector<ZoomRow> rows;
  render::Frame previous, previous_truth;
  const double first_width = render::view_width(cameras.front());
  for (uint32_t f = 0; f < n; ++f) {
    const std::string stage = "frame " + std::to_string(f + 1) + "/" + std::to_string(n);
    settings.camera = cameras[f];
    render::Frame ours = gpu.render(settings);
    reference::ReferenceSettings rs;
    rs.render = settings;
    rs.spp = a.spp;
    rs.seed = a.seed;
    rs.progress = [&](double x) { bar.update(stage, (double(f) + x) / double(n)); };
    const auto start = std::chrono::steady_clock::now();
    render::Frame truth = reference::render_reference(*geometry, rs);
    ZoomRow row;
    row.frame = f;
    row.view_width = render::view_width(cameras[f]);
    row.zoom = first_width / row.view_width;
    row.ms = render::frame_ms(ours);
    row.reference_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (f > 0) {
      row.change = mean_abs_difference(ours, previous);
      row.change_reference = mean_abs_difference(truth, previous_truth);
    }
    row.centre = centre_mean(ours);
    row.centre_reference = centre_mean(truth);
    row.colour_shift = shift(row.centre, row.centre_reference);
    row.relmse =
        reference::compare_images(render::frame_image(ours), render::frame_image(truth), "prefiltered", "reference")
            .relmse;
    rows.push_back(row);
    render::write_colour((dir / "frames" / numbered("prefiltered", f, "png")).string(), ours);
    render::write_colour((dir / "frames" / numbered("reference", f, "exr")).string(), truth);
    if (std::find(strip_at.begin(), strip_at.end(), f) != strip_at.end()) {
      strip_ours.push_back(ours);
      strip_truth.push_back(truth);
    }
    previous = std::move(ours);
    previous_truth = std::move(truth);
  }
  // The ground truth's own noise: the last frame again with another seed.
  reference::ReferenceSettings rs;
  rs.render = settings;
  rs.spp = a.spp;
  rs.seed = a.seed + 1;
  rs.progress = [&](double x) { bar.update("noise floor", x); };
  const double noise = mean_abs_difference(reference::render_reference(*geometry, rs), previous_truth);
  bar.finish();

  // --- Summary figures.
  double ratio_max = 0, ratio_sum = 0, change_sum = 0, change_truth_sum = 0, shift_max = 0, shift_sum = 0;
  double relmse_sum = 0;
  uint32_t ratio_frame = 0, shift_frame = 0;
  for (const auto& r : rows) {
    shift_sum += r.colour_shift;
    relmse_sum += r.relmse;
    if (r.colour_shift >= shift_max) shift_max = r.colour_shift, shift_frame = r.frame;
    if (r.frame == 0) continue;
    change_sum += r.change;
    change_truth_sum += r.change_reference;
    const double ratio = r.change_reference > 0 ? r.change / r.change_reference : 0.0;
    ratio_sum += ratio;
    if (ratio >= ratio_max) ratio_max = ratio, ratio_frame = r.frame;
  }
  const double steps = double(n - 1);

  // --- CSV, JSON, Markdown, strip, plot.
  std::ostringstream csv;
  csv << std::setprecision(9)
      << "frame,zoom,view_width,ms,change,change_reference,change_ratio,centre_r,centre_g,centre_b,"
         "centre_reference_r,centre_reference_g,centre_reference_b,colour_shift,relmse,reference_s\n";
  for (const auto& r : rows) {
    csv << r.frame << "," << r.zoom << "," << r.view_width << "," << r.ms << ",";
    if (r.frame > 0) {
      csv << r.change << "," << r.change_reference << ","
          << (r.change_reference > 0 ? r.change / r.change_reference : 0.0);
    } else {
      csv << ",,";
    }
    csv << "," << r.centre.r << "," << r.centre.g << "," << r.centre.b << "," << r.centre_reference.r << ","
        << r.centre_reference.g << "," << r.centre_reference.b << "," << r.colour_shift << "," << r.relmse << ","
        << r.reference_s << "\n";
  }
  files::write_file((dir / "coherence.csv").string(), csv.str());

  nlohmann::json j;
  j["octree"] = a.octree;
  j["octree_bytes"] = file_bytes;
  j["source"] = source_name(a.source);
  j["frames"] = n;
  j["width"] = settings.width;
  j["height"] = settings.height;
  j["spp"] = a.spp;
  j["zoom"] = first_width / render::view_width(cameras.back());
  j["device"] = gpu.device_name();
  j["change_mean"] = change_sum / steps;
  j["change_reference_mean"] = change_truth_sum / steps;
  j["change_ratio_of_means"] = change_truth_sum > 0 ? change_sum / change_truth_sum : 0.0;
  j["change_ratio_mean"] = ratio_sum / steps;
  j["change_ratio_max"] = ratio_max;
  j["change_ratio_max_frame"] = ratio_frame;
  j["reference_noise"] = noise;
  j["colour_shift_mean"] = shift_sum / double(n);
  j["colour_shift_max"] = shift_max;
  j["colour_shift_max_frame"] = shift_frame;
  j["relmse_mean"] = relmse_sum / double(n);
  j["rows"] = nlohmann::json::array();
  for (const auto& r : rows) {
    nlohmann::json row{{"frame", r.frame},
                       {"zoom", r.zoom},
                       {"view_width", r.view_width},
                       {"ms", r.ms},
                       {"centre", {r.centre.r, r.centre.g, r.centre.b}},
                       {"centre_reference", {r.centre_reference.r, r.centre_reference.g, r.centre_reference.b}},
                       {"colour_shift", r.colour_shift},
                       {"relmse", r.relmse},
                       {"reference_s", r.reference_s}};
    if (r.frame > 0) {
      row["change"] = r.change;
      row["change_reference"] = r.change_reference;
      row["change_ratio"] = r.change_reference > 0 ? r.change / r.change_reference : 0.0;
    }
    j["rows"].push_back(row);
  }
  files::write_file((dir / "coherence.json").string(), j.dump(2) + "\n");

  std::ostringstream md;
  md << "Octree " << a.octree << " (" << file_bytes << " bytes), ground truth of " << source_name(a.source) << " at "
     << a.spp << " spp; " << n << " frames " << settings.width << "x" << settings.height << ", zoom "
     << fmt(first_width / render::view_width(cameras.back()), 0) << "; device " << gpu.device_name() << ".\n\n"
     << "| frame | zoom | change, prefiltered | change, ground truth | ratio | centre colour, prefiltered | centre "
        "colour, ground truth | colour shift | relMSE |\n|---|---|---|---|---|---|---|---|---|\n";
  auto rgb = [](glm::dvec3 c) { return fmt(c.r, 4) + " " + fmt(c.g, 4) + " " + fmt(c.b, 4); };
  for (const auto& r : rows) {
    md << "| " << r.frame << " | " << sci(r.zoom) << " | " << (r.frame ? sci(r.change) : "") << " | "
       << (r.frame ? sci(r.change_reference) : "") << " | "
       << (r.frame && r.change_reference > 0 ? fmt(r.change / r.change_reference, 2) : "") << " | " << rgb(r.centre)
       << " | " << rgb(r.centre_reference) << " | " << fmt(100 * r.colour_shift, 2) << "% | " << sci(r.relmse)
       << " |\n";
  }
  md << "\nChange ratio (prefiltered over ground truth, frame to frame): mean " << fmt(ratio_sum / steps, 2)
     << ", ratio of the mean changes " << fmt(change_truth_sum > 0 ? change_sum / change_truth_sum : 0.0, 2)
     << ", largest " << fmt(ratio_max, 2) << " (frame " << ratio_frame << "). Ground-truth noise (last frame, two "
     << "seeds): " << sci(noise) << ". Colour shift of the centre window: mean " << fmt(100 * shift_sum / n, 2)
     << "%, largest " << fmt(100 * shift_max, 2) << "% (frame " << shift_frame << ").\n";
  files::write_file((dir / "table.md").string(), md.str());

  if (!strip_ours.empty()) {
    std::vector<const render::Frame*> top, bottom;
    for (const auto& f : strip_ours) top.push_back(&f);
    for (const auto& f : strip_truth) bottom.push_back(&f);
    render::write_colour((dir / "strip.png").string(), make_strip({top, bottom}, 256));
  }
  write_plot(dir, "temporal coherence: " + source_name(a.source));
  std::cout << md.str();
}

}  // namespace

void add_bench_zoom_command(CLI::App& bench, int& exit_code) {
  auto a = std::make_shared<ZoomArgs>();
  CLI::App* cmd = bench.add_subcommand(
      "zoom",
      "Temporal coherence of a camera path: for every frame, prefiltered and the ground truth (svo reference of "
      "the source), their frame-to-frame change (popping shows as change beyond the ground truth's), the mean "
      "colour of the centre window (colour shift) and relMSE; writes table.md, coherence.csv, coherence.json, "
      "strip.png (prefiltered above, ground truth below), coherence.png (gnuplot) and the frames to --out");
  cmd->add_option("FILE", a->octree, "The .svo file made from the source")->required()->group("Input");
  add_source_options(*cmd, a->source);
  cmd->add_option("-o,--out", a->out, "Output directory (created)")->default_val("bench-zoom")->group("Output");
  cmd->add_option("--strip", a->strip, "Frames in strip.png, spread over the path (0: no strip)")
      ->default_val(8)
      ->check(CLI::Range(0u, 64u))
      ->group("Output");
  add_size_options(*cmd, a->view);
  cmd->get_option("--width")->default_val(128);
  cmd->get_option("--height")->default_val(128);
  add_path_options(*cmd, a->path, 12);
  cmd->add_option("--spp", a->spp, "Samples per pixel of the ground truth")
      ->default_val(64)
      ->check(CLI::Range(1u, 65536u))
      ->group("Sampling");
  cmd->add_option("--seed", a->seed, "Seed of the ground truth's jitter (the same for every frame)")
      ->default_val(1)
      ->group("Sampling");
  add_light_options(*cmd, a->view);
  cmd->add_option("--device", a->device, kDeviceHelp)->group("Device");
  cmd->callback([a, &exit_code] {
    run_zoom(*a);
    exit_code = 0;
  });
}

}  // namespace svo::tools
