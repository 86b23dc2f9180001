// svo demo: the main job on an embedded default, showing what pre-filtering
// is for in under a minute on 2 cores. It voxelizes the built-in bumpy
// sphere with procedural detail octaves (paper Fig. 11), renders a far, a
// mid and a close view with one cone per pixel, pre-filtered (ours) and with
// the nearest-voxel baseline, ray traces the supersampled ground truth of
// each view (svo reference's), and writes:
//   DIR/svo-demo.png          the contact sheet: one row per view, ground
//                             truth | pre-filtered | nearest voxel, each
//                             captioned with its time and relMSE;
//   DIR/svo-demo/VIEW-KIND.exr the nine frames (KIND: reference,
//                             prefiltered, nearest), so that every printed
//                             error can be checked by hand with svo compare.
// The errors are computed from the EXR files as written, so `svo compare
// DIR/svo-demo/far-prefiltered.exr DIR/svo-demo/far-reference.exr` prints
// the same relMSE.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/render/text.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"
#include "view_options.h"
#include "zoom_path.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;

struct DemoArgs {
  std::string directory = ".";
  uint32_t resolution = 128;
  uint32_t size = 128;
  uint32_t spp = 4;
  uint32_t octaves = 3;
  std::string device;
  bool json = false;
  FilmOptions film;
};

// One frame of the demo: what it shows, its time, its error against the ground truth.
struct Shot {
  std::string kind;  // "reference", "prefiltered", "nearest"
  std::string path;
  render::Frame frame;
  double ms = 0;
  std::optional<reference::ImageErrors> errors;  // none for the ground truth itself
};

constexpr const char* kKinds[] = {"reference", "prefiltered", "nearest"};
constexpr const char* kColumnTitles[] = {"GROUND TRUTH", "PRE-FILTERED (OURS)", "NEAREST VOXEL"};

std::string fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

// relMSE as svo compare prints it (4 significant digits).
std::string relmse_text(double v) {
  std::ostringstream s;
  s << std::setprecision(4) << v;
  return s.str();
}

std::string time_text(double ms) { return ms >= 1000 ? fixed(ms / 1000, 1) + " S" : fixed(ms, 0) + " MS"; }

// Rows of views, columns of kinds, two title lines above and a two-line
// caption under each tile; each frame pixel drawn as zoom x zoom pixels, so
// that small frames show their pixels. Linear RGB for write_colour.
render::Frame contact_sheet(const std::vector<std::pair<std::string, std::vector<Shot>>>& views, uint32_t size,
                            uint32_t zoom, uint32_t spp, const std::vector<std::string>& title) {
  const int tile = int(size * zoom);
  const int scale = tile >= 256 ? 2 : 1;
  const int line = (render::kGlyphHeight + 4) * scale;
  const int label = render::text_width("CLOSE", scale) + 8 * scale;
  const int gap = 4;
  const int header = int(title.size() + 1) * line + gap;
  const int row_height = tile + 2 * line + gap;
  const glm::vec3 background(0.015f, 0.015f, 0.02f);
  render::Frame sheet;
  sheet.width = uint32_t(label + 3 * (tile + gap));
  sheet.height = uint32_t(header + int(views.size()) * row_height);
  sheet.colour.assign(size_t(sheet.width) * sheet.height, glm::vec4(background, 1));
  const glm::vec3 white(0.9f), grey(0.45f), good(0.35f, 0.8f, 0.3f), bad(0.9f, 0.35f, 0.25f);
  for (size_t t = 0; t < title.size(); ++t) render::draw_text(sheet, 4, 2 + int(t) * line, title[t], white, scale);
  for (int c = 0; c < 3; ++c) {
    render::draw_text(sheet, label + c * (tile + gap) + 2, int(title.size()) * line + 2, kColumnTitles[c], white,
                      scale);
  }
  for (size_t r = 0; r < views.size(); ++r) {
    const int y0 = header + int(r) * row_height;
    std::string name = views[r].first;
    std::transform(name.begin(), name.end(), name.begin(), ::toupper);
    render::draw_text(sheet, 4, y0 + tile / 2, name, white, scale);
    const auto& shots = views[r].second;
    const double best = std::min(shots[1].errors->relmse, shots[2].errors->relmse);
    for (size_t c = 0; c < shots.size(); ++c) {
      const int x0 = label + int(c) * (tile + gap);
      const render::Frame& f = shots[c].frame;
      for (int y = 0; y < tile; ++y) {
        for (int x = 0; x < tile; ++x) {
          // Over the sheet's background, as the PNG of a frame shows it.
          const glm::vec4 p = f.colour[size_t(y / int(zoom)) * f.width + size_t(x / int(zoom))];
          sheet.colour[size_t(y0 + y) * sheet.width + size_t(x0 + x)] =
              glm::vec4(glm::vec3(p) + (1.0f - p.a) * background, 1.0f);
        }
      }
      if (shots[c].errors) {
        render::draw_text(sheet, x0 + 2, y0 + tile + 3, "RELMSE " + relmse_text(shots[c].errors->relmse),
                          shots[c].errors->relmse <= best ? good : bad, scale);
      } else {
        render::draw_text(sheet, x0 + 2, y0 + tile + 3, std::to_string(spp) + " RAYS PER PIXEL", grey, scale);
      }
      render::draw_text(sheet, x0 + 2, y0 + tile + 3 + line, time_text(shots[c].ms), grey, scale);
    }
  }
  return sheet;
}

void run_demo(const DemoArgs& a) {
  // --- Outputs checked before any work.
  make_output_directory(a.directory);
  const fs::path dir(a.directory), frames = dir / "svo-demo";
  fs::create_directories(frames);
  const std::string sheet_path = (dir / "svo-demo.png").string();
  render::check_writable_output(sheet_path);

  // --- The scene: the bumpy sphere with detail octaves; the voxelizer's
  // folds the octaves finer than a voxel into its statistics, the ground
  // truth's keeps every octave.
  SourceOptions source;
  source.scene = "bumpy-sphere";
  source.detail_octaves = a.octaves;
  auto scene = make_scene_source(source, /*all_octaves=*/false);
  auto truth_scene = make_scene_source(source, true);
  voxelizer::VoxelizeOptions options;
  options.resolution = a.resolution;
  voxelizer::VoxelizeReport report;
  octree::Octree tree;
  {
    ProgressBar bar("voxelize");
    options.progress = [&bar](const std::string& stage, double f) { bar.update(stage, f); };
    tree = voxelizer::voxelize(*scene, options, &report);
  }
  truth_scene->set_sigma_rho2(tree.sigma_rho2);
  const std::unique_ptr<reference::Geometry> geometry = reference::scene_geometry(*truth_scene);
  std::unique_ptr<render::Renderer> renderer = render::make_renderer(tree, {a.device});

  // --- Three views, three kinds each.
  std::vector<std::pair<std::string, std::vector<Shot>>> views;
  ProgressBar bar("demo");
  const std::vector<std::string> names{"far", "mid", "close"};
  for (size_t v = 0; v < names.size(); ++v) {
    const std::string& name = names[v];
    render::RenderSettings settings;
    settings.width = settings.height = a.size;
    settings.camera = render::view_preset(tree, name);
    settings.lights = render::default_lights(settings.camera);
    std::vector<Shot> shots(3);
    for (size_t k = 0; k < 3; ++k) {
      Shot& s = shots[k];
      s.kind = kKinds[k];
      s.path = (frames / (name + "-" + s.kind + ".exr")).string();
      const double done = (double(v) + (k == 0 ? 0.0 : 0.9)) / double(names.size());
      if (k == 0) {
        reference::ReferenceSettings rs;
        rs.render = settings;
        rs.spp = a.spp;
        rs.progress = [&](double x) { bar.update(name + " ground truth", done + 0.9 * x / double(names.size())); };
        const auto start = std::chrono::steady_clock::now();
        s.frame = reference::render_reference(*geometry, rs);
        s.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      } else {
        bar.update(name + " " + s.kind, done);
        settings.mode = k == 1 ? render::Mode::Prefiltered : render::Mode::Nearest;
        s.frame = renderer->render(settings);
        s.ms = render::frame_ms(s.frame);
      }
      render::write_colour(s.path, s.frame);
    }
    // The errors of the files as written: what svo compare reads.
    const render::Image truth = render::read_image(shots[0].path);
    for (size_t k = 1; k < 3; ++k) {
      shots[k].errors =
          reference::compare_images(render::read_image(shots[k].path), truth, shots[k].path, shots[0].path);
    }
    views.emplace_back(name, std::move(shots));
  }
  bar.finish();
  const uint32_t zoom = std::max(1u, 256u / a.size);
  const std::vector<std::string> title{"SVO DEMO: BUMPY SPHERE, " + std::to_string(a.octaves) + " DETAIL OCTAVES, " +
                                           std::to_string(a.resolution) + " VOXELS PER AXIS",
                                       "ONE CONE PER PIXEL; GROUND TRUTH " + std::to_string(a.spp) + " RAYS PER PIXEL" +
                                           (zoom > 1 ? "; PIXELS SHOWN " + std::to_string(zoom) + "X" : "")};
  render::write_colour(sheet_path, contact_sheet(views, a.size, zoom, a.spp, title), make_film(a.film));

  // --- The report.
  if (a.json) {
    nlohmann::json out{{"scene", "bumpy-sphere"},
                       {"detail_octaves", a.octaves},
                       {"resolution", a.resolution},
                       {"size", a.size},
                       {"spp", a.spp},
                       {"voxelize_seconds", report.seconds_total},
                       {"bricks", tree.brick_count},
                       {"device", renderer->device_name()},
                       {"device_type", renderer->device_type()},
                       {"contact_sheet", sheet_path},
                       {"views", nlohmann::json::array()}};
    for (const auto& [name, shots] : views) {
      nlohmann::json view{{"view", name}};
      for (const auto& s : shots) {
        nlohmann::json shot{{"file", s.path}, {"ms", s.ms}};
        if (s.errors) shot["relmse"] = s.errors->relmse, shot["psnr"] = s.errors->psnr;
        view[s.kind] = shot;
      }
      out["views"].push_back(view);
    }
    std::cout << out.dump() << "\n";
    return;
  }
  std::cout << "svo demo: the bumpy sphere with " << a.octaves << " detail octaves, voxelized at " << a.resolution
            << "^3 in " << fixed(report.seconds_total, 1) << " s (" << tree.brick_count << " bricks); " << a.size << "x"
            << a.size << " frames, one cone per pixel, on " << renderer->device_name() << " ("
            << renderer->device_type() << ")\n\n"
            << "view    ground truth (" << std::setw(2) << a.spp
            << " rays/pixel)  pre-filtered (ours)          nearest voxel\n";
  for (const auto& [name, shots] : views) {
    std::cout << std::left << std::setw(8) << name << std::setw(29) << (fixed(shots[0].ms / 1000, 1) + " s");
    for (size_t k = 1; k < 3; ++k) {
      std::cout << std::setw(k == 1 ? 29 : 0)
                << (fixed(shots[k].ms, 0) + " ms, relMSE " + relmse_text(shots[k].errors->relmse));
    }
    std::cout << "\n";
  }
  std::cout << std::right << "\nrelMSE: mean squared error over the ground truth's squared radiance (lower is "
            << "better).\ncontact sheet: " << sheet_path << "\ncheck a figure: svo compare " << views[0].second[1].path
            << " " << views[0].second[0].path << "\n";
}

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "demo",
      "The point of the engine in under a minute: voxelize the bumpy sphere with detail octaves, render a far, a mid\n"
      "and a close view with one cone per pixel, pre-filtered and with the nearest-voxel baseline, ray trace the\n"
      "ground truth of each, print times and errors, and write the contact sheet DIR/svo-demo.png (and the frames\n"
      "as EXR under DIR/svo-demo/, for svo compare)");
  auto a = std::make_shared<DemoArgs>();
  cmd->add_option("-o,--output", a->directory, "Directory for the contact sheet and frames (created if missing)")
      ->default_val(".")
      ->group("Output");
  cmd->add_option("--size", a->size, "Width and height of each frame, pixels")
      ->default_val(128)
      ->check(CLI::Range(32u, 1024u))
      ->group("Output");
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis: a power of two")
      ->default_val(128)
      ->check(CLI::IsMember({32u, 64u, 128u, 256u, 512u, 1024u}))
      ->group("Scene");
  cmd->add_option("--octaves", a->octaves, "Detail octaves of noise on the sphere (0: the smooth bumps alone)")
      ->default_val(3)
      ->check(CLI::Range(0u, 8u))
      ->group("Scene");
  cmd->add_option("--spp", a->spp, "Rays per pixel of the ground truth")
      ->default_val(4)
      ->check(CLI::Range(1u, 4096u))
      ->group("Scene");
  add_film_options(*cmd, a->film);
  cmd->add_option("--device", a->device, kDeviceHelp)->group("Output");
  cmd->add_flag("--json", a->json, "Print one JSON object on stdout instead of text")->group("Output");
  cmd->callback([a, &exit_code] {
    run_demo(*a);
    exit_code = 0;
  });
}

}  // namespace svo::tools
