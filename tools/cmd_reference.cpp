// svo reference: ground truth from the source geometry (never the octree),
// DESIGN section 9. The .svo file records nothing about its source, so the
// source is named again (mesh file or --scene, with the same --colour and
// --roughness as svo voxelize); --octree only supplies what svo render took
// from the file: the view presets, the micro-BRDF roughness it was built
// with and the centre the point-light defaults refer to (and the domain the
// luminaires' default placement refers to; without --octree, the source's
// bounds).
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/svo_file.h"
#include "svo/reference/reference.h"
#include "svo/render/image_io.h"
#include "view_options.h"

namespace svo::tools {

namespace {

struct ReferenceArgs {
  SourceOptions source;
  std::string output;
  std::string octree;
  ViewOptions view;
  FilmOptions film;
  LightingOptions lighting;
  LuminaireArgs luminaires;
  uint32_t luminaire_quadrature = 1;
  uint32_t spp = 64;
  uint64_t seed = 1;
  bool json = false;
};

}  // namespace

void add_reference_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "reference",
      "Ground truth: ray trace the source geometry (procedural scenes by sphere tracing their distance functions, "
      "meshes with Embree) with N stratified samples over each pixel's cone footprint, the micro-BRDF alone, and "
      "the lights, shadows and camera of svo render; light-field luminaires (--luminaire) by dense quadrature "
      "with exact shadow rays");
  auto a = std::make_shared<ReferenceArgs>();
  add_source_options(*cmd, a->source);
  cmd->add_option("--octree", a->octree,
                  "The .svo file svo render used: its domain gives --view presets, its micro-BRDF roughness is "
                  "used unless --roughness is given, its centre anchors point-light defaults")
      ->group("Input");

  cmd->add_option("-o,--output", a->output,
                  "Image: .exr (float linear RGB, A = covered fraction; what svo compare needs) or .png or .jpg "
                  "(8-bit sRGB through --exposure and --tonemap, no coverage)")
      ->required()
      ->group("Output");
  add_size_options(*cmd, a->view);
  cmd->add_option("--spp", a->spp,
                  "Samples per pixel: a stratified grid over the footprint disk (a square grid for 4, 16, 64, 256, "
                  "...)")
      ->default_val(64)
      ->check(CLI::Range(1u, 65536u))
      ->group("Sampling");
  cmd->add_option("--seed", a->seed, "Seed of the jitter; the same seed gives the same image")
      ->default_val(1)
      ->group("Sampling");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: seconds, spp, width, height, covered_pixels, sigma_rho2, camera, "
                "lights, ...")
      ->group("Output");
  add_camera_options(*cmd, a->view);
  add_light_options(*cmd, a->view);
  add_film_options(*cmd, a->film);
  add_lighting_options(*cmd, a->lighting);
  add_area_light_options(*cmd, a->lighting);
  add_luminaire_options(*cmd, a->luminaires);
  cmd->add_option("--luminaire-quadrature", a->luminaire_quadrature,
                  "K: each hit is lit by the luminaires through dense quadrature of the light-field integral, K x K "
                  "points per texel of the emitting plane (of the region each basis function lets reach the hit), "
                  "each with an exact shadow ray; the luminaires replace the lights unless --env is given, as in "
                  "svo render. The sampling options (--sampler, --luminaire-spp, --kmax, --luminaire-visibility, "
                  "--search, --search-depth, --sequence) are accepted so that svo render's words can be given, and "
                  "ignored")
      ->default_val(1)
      ->check(CLI::Range(1u, 8u))
      ->group("Luminaires");

  cmd->callback([a, &exit_code] {
    // --- Everything that can be checked before the source is read.
    check_source_options(a->source, "reference");
    std::optional<render::Camera> camera = check_view_options(a->view);
    if (!camera && a->octree.empty()) {
      throw std::invalid_argument("reference: --view " + a->view.preset +
                                  " needs --octree FILE.svo (the presets come from an octree's domain), or give "
                                  "--camera or --camera-file");
    }
    check_luminaire_args(a->luminaires);
    render::image_format(a->output);
    render::check_writable_output(a->output);
    const render::Film film = make_film(a->film);
    if (const std::string note = film_note(a->film, a->output); !note.empty()) std::cerr << note << "\n";

    // --- The source, the octree's view and the settings.
    auto start = std::chrono::steady_clock::now();
    std::optional<octree::Octree> tree;
    if (!a->octree.empty()) tree = octree::load_svo(a->octree);
    std::unique_ptr<voxelizer::AnalyticScene> scene;
    std::unique_ptr<reference::Geometry> geometry;
    if (!a->source.scene.empty()) {
      scene = make_scene_source(a->source);
      if (tree && a->source.roughness < 0) scene->set_sigma_rho2(tree->sigma_rho2);
      geometry = reference::scene_geometry(*scene);
    } else {
      voxelizer::TriangleMesh mesh = read_source_mesh(a->source);
      if (tree && a->source.roughness < 0) mesh.sigma_rho2 = tree->sigma_rho2;
      geometry = reference::mesh_geometry(std::move(mesh));
    }
    const voxelizer::Box bounds = geometry->bounds();
    // The domain's centre, as svo voxelize centres the domain on the bounds.
    const glm::vec3 centre = tree ? tree->origin + glm::vec3(0.5f * tree->size) : 0.5f * (bounds.lo + bounds.hi);
    reference::ReferenceSettings settings;
    settings.render.width = a->view.width;
    settings.render.height = a->view.height;
    settings.render.camera =
        resolve_camera(a->view, camera, tree ? &*tree : nullptr, glm::length(bounds.hi - bounds.lo));
    settings.render.shadows = a->view.shadows;
    settings.render.lights = make_lights(a->view, centre, settings.render.camera);
    if (a->lighting.env_preconvolved)
      throw std::invalid_argument(
          "--env-preconvolved is an approximation for svo render; the reference samples the map");
    if (a->lighting.env_sampling != "mis")
      throw std::invalid_argument("--env-sampling is svo render's; the reference samples the map its own way");
    apply_lighting(a->lighting, settings.render);
    // The luminaires about the octree's domain, else the source's bounds.
    if (tree) {
      apply_luminaires(a->luminaires, &*tree, settings.render);
      apply_area_light(a->lighting, centre, tree->size, settings.render);
    } else {
      const glm::vec3 extent = bounds.hi - bounds.lo;
      const float size = std::max({extent.x, extent.y, extent.z, 1e-6f});
      apply_luminaires(a->luminaires, centre, size, settings.render);
      apply_area_light(a->lighting, centre, size, settings.render);
    }
    // As svo render: the luminaires (and the ambient term) light the frame
    // alone, unless an environment makes it forward shade with its lights.
    if (!settings.render.luminaire.luminaires.empty() && a->lighting.env.empty()) settings.render.lights.clear();
    if (settings.render.shading.area_light && a->view.lights.empty()) settings.render.lights.clear();
    settings.luminaire_quadrature = a->luminaire_quadrature;
    settings.spp = a->spp;
    settings.seed = a->seed;
    tree.reset();  // only its view and roughness were needed

    // --- Trace.
    ProgressBar bar("reference");
    settings.progress = [&bar, rows = uint64_t(settings.render.height)](double f) {
      bar.update("tracing", uint64_t(f * double(rows) + 0.5), rows, "rows");
    };
    render::Frame frame = reference::render_reference(*geometry, settings);
    bar.finish();
    render::write_colour(a->output, frame, film);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string source = source_name(a->source);
    if (a->json) {
      nlohmann::json out{{"source", source},
                         {"output", a->output},
                         {"octree", a->octree.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->octree)},
                         {"width", frame.width},
                         {"height", frame.height},
                         {"spp", settings.spp},
                         {"seed", settings.seed},
                         {"seconds", seconds},
                         {"trace_seconds", frame.wall_ms / 1000.0},
                         {"covered_pixels", frame.covered_pixels},
                         {"view", view_name(a->view)},
                         {"sigma_rho2", json_float(geometry->sigma_rho2())},
                         {"shadows", settings.render.shadows},
                         {"lights", lights_json(settings.render.lights)},
                         {"luminaires", settings.render.luminaire.luminaires.empty()
                                            ? nlohmann::json(nullptr)
                                            : nlohmann::json{{"files", a->luminaires.files},
                                                             {"quadrature", settings.luminaire_quadrature}}},
                         {"camera", camera_json(settings.render.camera)}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << std::fixed << std::setprecision(1) << source << " -> " << a->output << ": " << frame.width << "x"
                << frame.height << ", " << settings.spp << " spp, view " << view_name(a->view) << ", " << seconds
                << " s, " << frame.covered_pixels << " covered pixels";
      const size_t lums = settings.render.luminaire.luminaires.size();
      if (lums > 0) {
        std::cout << ", " << lums << (lums == 1 ? " luminaire" : " luminaires") << " (quadrature "
                  << settings.luminaire_quadrature << "x" << settings.luminaire_quadrature << " per texel)";
      }
      std::cout << "\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
