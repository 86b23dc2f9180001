// svo render: one frame of a .svo file by cone tracing (Heitz & Neyret
// Algorithm 1) to PNG or EXR, with an optional G-buffer and timing figures.
// Every argument and both output paths are checked before the octree is
// loaded or a device is opened; bad input is one line and exit code 1.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli_hint.h"
#include "commands.h"
#include "memory.h"
#include "output_checks.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"
#include "view_options.h"

namespace svo::tools {

namespace {

struct RenderArgs {
  std::string input;
  std::string output;
  std::string gbuffer;
  std::string steps;
  std::string save_camera;
  std::vector<std::string> aovs;    // NAME=FILE.exr
  std::vector<std::string> passes;  // added after the tracer, in order
  ViewOptions view;
  FilmOptions film;
  std::string mode = "prefiltered";
  uint32_t spp = 0;  // 0: the default of the mode (1 ray) or of forward shading (16 samples)
  std::string
      shading;  // tracer or forward; empty: forward with --env, --material or the octree's materials, else tracer
  LightingOptions lighting;
  FilterArgs filter;
  render::AdaptiveOptions adaptive;
  LuminaireArgs luminaires;
  uint32_t seed = 1;
  uint32_t msaa = 1;
  float footprint_spread = render::RenderSettings{}.footprint_spread;
  bool flat_masks = false;
  bool keep_back_facing = false;
  bool shared_normal = false;
  bool shade_at_axis = false;
  bool unsplit_creases = false;
  float shading_voxel = 1.0f;
  uint32_t lens_parts = 0;
  std::string device;
  bool validate = false;
  bool cpu = false;
  bool json = false;
  uint32_t repeats = 1;
  double max_memory_mb = 0;
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// What the adaptive pass did in the last frame, for --json.
nlohmann::json adaptive_json(const render::AdaptivePass::Stats& st, const render::AdaptiveOptions& o) {
  return {{"shaded_texels", st.shaded},
          {"samples", st.samples},
          {"covered_pixels", st.covered},
          {"pixels_at_level", st.pixels_at_level},
          {"shaded_at_level", st.shaded_at_level},
          {"tables_ms", st.tables_ms},
          {"bandwidth_ms", st.bandwidth_ms},
          {"shading_ms", st.shading_ms},
          {"tau", o.tau},
          {"variance", o.measured_variance ? "measured" : "bound"},
          {"directions", o.directions}};
}

}  // namespace

// The switches of the far-view research (docs/RESULTS.md), kept so that each
// addition to the paper's cone can be weighed or turned off.
constexpr const char* kAdvanced = "Advanced: research switches of the far-view work (docs/RESULTS.md)";

void add_render_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "render",
      "Render one frame of a .svo file by cone tracing (one cone per pixel, pre-filtered appearance).\n"
      "The image is written to a temporary name and renamed; outputs are checked before rendering");
  auto a = std::make_shared<RenderArgs>();
  cmd->add_option("FILE", a->input, "The .svo file to render")->required()->group("Input");

  cmd->add_option("-o,--output", a->output,
                  "Image: .png or .jpg (8-bit sRGB through --exposure and --tonemap, background composited) or "
                  ".exr (float linear RGB as rendered, A = coverage)")
      ->required()
      ->group("Output");
  add_size_options(*cmd, a->view);
  cmd->add_option("--gbuffer", a->gbuffer,
                  "Also write the G-buffer as one float .exr: depth, P (position), N (filtered normal), T (tangent), "
                  "slope_cov (xx, yy, xy in the frame T, N x T: the voxels' and the footprint's, without sigma_rho2), "
                  "sigma_rho2, abar, a_s, coverage (shaders/common/gbuffer.glsl)")
      ->group("Output");
  cmd->add_option("--steps", a->steps,
                  "Also write the cone elements visited per pixel (shadow cones included) as a one-channel float "
                  ".exr: where the frame's time goes")
      ->group("Output");
  cmd->add_option("--save-camera", a->save_camera, "Also write the camera used as JSON (the form of --camera-file)")
      ->group("Output");
  cmd->add_option("--aov", a->aovs,
                  "Also write the frame's image NAME as a float .exr, NAME=FILE.exr (repeatable): colour, background "
                  "(the background's share of colour), gbuffer (every G-buffer field), steps, display")
      ->group("Output");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: width, height, ms, wall_ms (the first frame's host time), "
                "warm_wall_ms (the median of the --repeats after it), covered_pixels, us_per_pixel, "
                "steps_per_pixel, mode, view, device, device_type, passes (name and ms of each), ...")
      ->group("Output");

  add_camera_options(*cmd, a->view);

  cmd->add_option("--mode", a->mode,
                  "prefiltered (ours), nearest (binary voxels, nearest level), alpha (coverage as opacity), "
                  "mip (averaged colour and normal), raymarch (the supersampling baseline: --spp rays per pixel "
                  "marching the finest level)")
      ->default_val("prefiltered")
      ->group("Shading");
  cmd->add_option("--spp", a->spp,
                  "Samples per pixel of --shading forward (default 16), or rays per pixel of --mode raymarch "
                  "(a square, default 1); 1 to 4096")
      ->check(CLI::Range(1u, 4096u))
      ->group("Shading");
  cmd->add_option("--shading", a->shading,
                  "tracer: each cone element shaded by the lights as it is marched (paper Eq. 13); forward: the "
                  "G-buffer shaded afterwards with --env, --material and --spp samples per pixel (multiple "
                  "importance sampling); adaptive: as forward, but each pixel shaded at the pyramid level and with the "
                  "samples its predicted bandwidth and variance ask for (Bagher et al. 2013; --adaptive-*). Default: "
                  "forward with --env or --material or an octree that carries materials "
                  "(svo voxelize --material, "
                  "--scene material-spheres), else tracer")
      ->check(CLI::IsMember({"tracer", "forward", "adaptive"}))
      ->group("Shading");
  cmd->add_option("--seed", a->seed, "Seed of the forward pass's sample sequence")->group("Shading");
  cmd->add_option("--msaa", a->msaa,
                  "Multisample anti-aliasing: trace and shade N x N samples per pixel (a cone each) and average them. "
                  "--shading forward shades every sample; --shading adaptive only those whose predicted bandwidth asks "
                  "for more than a pixel (Bagher et al. 2013, Fig. 19). --aov images are at the samples' size; not "
                  "with --gbuffer")
      ->check(CLI::IsMember({1u, 2u, 4u}))
      ->capture_default_str()
      ->group("Shading");
  add_lighting_options(*cmd, a->lighting);
  add_area_light_options(*cmd, a->lighting);
  add_light_options(*cmd, a->view);
  add_film_options(*cmd, a->film);
  add_filter_options(*cmd, a->filter);
  add_adaptive_options(*cmd, a->adaptive);
  add_luminaire_options(*cmd, a->luminaires);
  cmd->add_option("--footprint-spread", a->footprint_spread,
                  "Weight in [0, 4] of the normals' spread over each cone's footprint, added to the voxels' slope "
                  "variance (prefiltered and alpha modes); 0: the voxels' statistics alone, as in the paper")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 4.0f))
      ->group(kAdvanced);
  cmd->add_flag("--flat-masks", a->flat_masks,
                "Occlusion masks from the voxels' mean planes alone, as in the paper (default: they bend with the "
                "surface's curvature along the cone, which keeps convex silhouettes from spreading)")
      ->group(kAdvanced);
  cmd->add_flag("--keep-back-facing", a->keep_back_facing,
                "Shade with mean normals that face away from the eye as they are (default: they are laid into the "
                "silhouette plane, where a limb's visible normals lie)")
      ->group(kAdvanced);
  cmd->add_flag("--shared-normal", a->shared_normal,
                "Shade every element of a cone with the normal where its axis meets the element's mean plane "
                "(default: cones at least about a finest voxel wide take half of it from each element's centre)")
      ->group(kAdvanced);
  cmd->add_flag("--shade-at-axis", a->shade_at_axis,
                "Prefiltered: shade every element where the cone's axis meets its mean plane, with the whole "
                "footprint's spread (default: at the centre of the part of the footprint it covers first, with that "
                "part's spread)")
      ->group(kAdvanced);
  cmd->add_flag("--unsplit-creases", a->unsplit_creases,
                "Prefiltered: shade a part of the footprint across which the normal turns fast (a crease) at one "
                "point, with one lobe about the mean normal (default: as its two halves across the turn, weighted by "
                "where its own normal lies between theirs; one lobe draws a glint along creases that neither face has)")
      ->group(kAdvanced);
  cmd->add_option("--lens-parts", a->lens_parts,
                  "With --dof: split the lens into N x N parts, a cone each, averaged, at about N^2 the cost (0: "
                  "from the blur's width in the object, 1 to 4: one cone for a gentle blur, more as it widens; one "
                  "cone draws thin parts as wide as the blur, and a blur wider than the coarsest voxels as boxes)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 8u))
      ->group("Camera");
  cmd->add_option("--shading-voxel", a->shading_voxel,
                  "Prefiltered: voxel size of the level shading reads, in cone radii (default 1: its voxels' box and "
                  "trilinear tent spread as the footprint does; occlusion reads 1.414)")
      ->capture_default_str()
      ->check(CLI::Range(0.25f, 4.0f))
      ->group(kAdvanced);
  cmd->add_option("--pass", a->passes,
                  "Add a pass after the tracer (repeatable, run in order): visibility (the visible fraction of each "
                  "light from every surface point, a cone through the octree; write it with --aov visibility=F.exr), "
                  "forward (image-based lighting of the G-buffer, as --shading forward)")
      ->group("Passes");

  auto* device = cmd->add_option("--device", a->device, kDeviceHelp)->group("Device");
  auto* validate =
      cmd->add_flag(
             "--validate", a->validate,
             "Vulkan: enable the Khronos validation layer; any message fails the command (without --device: the best "
             "Vulkan device, lavapipe on a machine without a GPU)")
          ->group("Device");
  cmd->add_flag("--cpu", a->cpu, "The same as --device native")->excludes(device)->excludes(validate)->group("Device");

  cmd->add_option("--repeats", a->repeats,
                  "Render the frame this many times on the same renderer and report the median time (the first "
                  "frame also pays for allocating the frame's images)")
      ->default_val(1)
      ->check(CLI::Range(1u, 100u))
      ->group("Timing");
  cmd->add_option("--max-memory", a->max_memory_mb,
                  "Refuse a frame whose host memory estimate is above this, MiB (default: available memory)")
      ->check(positive_number())
      ->group("Limits");

  cmd->callback([a, &exit_code] {
    // --- Everything that can be checked without the octree or a device.
    std::optional<render::Mode> mode = render::parse_mode(a->mode);
    if (!mode)
      throw std::invalid_argument("unknown mode '" + a->mode + "' (modes: prefiltered, nearest, alpha, mip, raymarch)");
    const bool adaptive = a->shading == "adaptive";
    bool forward =
        a->shading.empty() ? uses_lighting(a->lighting) || uses_filter(a->filter) : a->shading == "forward" || adaptive;
    if (uses_filter(a->filter) && (!forward || adaptive)) {
      throw std::invalid_argument("--filter and --upsample filter the forward pass: they need --shading forward");
    }
    if (forward && *mode != render::Mode::Prefiltered) {
      throw std::invalid_argument("--shading forward shades the prefiltered G-buffer: it needs --mode prefiltered");
    }
    const uint32_t rays = forward || a->spp == 0 ? 1 : a->spp;
    const uint32_t root = uint32_t(std::lround(std::sqrt(double(rays))));
    if (root * root != rays) throw std::invalid_argument("--spp " + std::to_string(rays) + " is not a square");
    if (rays != 1 && *mode != render::Mode::RayMarch) {
      throw std::invalid_argument("--spp needs --mode raymarch or --shading forward");
    }
    check_luminaire_args(a->luminaires);
    if (!a->luminaires.files.empty() && *mode != render::Mode::Prefiltered) {
      throw std::invalid_argument("--luminaire shades the prefiltered G-buffer: it needs --mode prefiltered");
    }
    std::optional<render::Camera> camera = check_view_options(a->view);
    render::image_format(a->output);
    render::check_writable_output(a->output);
    const render::Film film = make_film(a->film);
    if (const std::string note = film_note(a->film, a->output); !note.empty()) std::cerr << note << "\n";
    for (const auto& [path, what] : {std::pair{a->gbuffer, "the G-buffer"}, std::pair{a->steps, "the steps image"}}) {
      if (path.empty()) continue;
      if (render::image_format(path) != render::ImageFormat::Exr) {
        throw std::invalid_argument(path + ": " + what + " is written as OpenEXR only (use .exr)");
      }
      render::check_writable_output(path);
    }
    if (!a->save_camera.empty()) render::check_writable_output(a->save_camera);
    for (const std::string& name : a->passes) render::make_pass(name);  // an unknown name fails here
    std::vector<std::pair<std::string, std::string>> aovs;              // (image, path)
    for (const std::string& aov : a->aovs) {
      const size_t eq = aov.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == aov.size()) {
        throw std::invalid_argument("--aov '" + aov + "': expected NAME=FILE.exr");
      }
      aovs.emplace_back(aov.substr(0, eq), aov.substr(eq + 1));
      if (render::image_format(aovs.back().second) != render::ImageFormat::Exr) {
        throw std::invalid_argument(aovs.back().second + ": --aov images are written as OpenEXR only (use .exr)");
      }
      render::check_writable_output(aovs.back().second);
    }
    {
      std::vector<std::pair<std::string, std::string>> outputs{
          {"-o", a->output}, {"--gbuffer", a->gbuffer}, {"--steps", a->steps}, {"--save-camera", a->save_camera}};
      for (const auto& [name, path] : aovs) outputs.emplace_back("--aov " + name, path);
      check_distinct_outputs(outputs);
    }
    // The frame on the host: colour (16 bytes a pixel), steps (4), the
    // file's copy (up to 16), the G-buffer and its file's copy (2 x 48), the
    // steps image's copy (4), the adaptive pass's images.
    {
      const double pixels = double(a->view.width) * double(a->view.height) * double(a->msaa) * double(a->msaa);
      const bool gbuffer = !a->gbuffer.empty() ||
                           std::any_of(aovs.begin(), aovs.end(), [](const auto& x) { return x.first == "gbuffer"; });
      const double mib =
          pixels *
          (16 + 16 + 4 + 16 + (gbuffer ? 2 * 4 * 21 : 0) + (a->steps.empty() ? 0 : 4) + 16.0 * double(aovs.size()) +
           (adaptive ? 2 * 16 * 4 / 3 + 16 : 0)) /  // the adaptive pass's two pyramids and its mask
          (1024.0 * 1024.0);
      const double limit = a->max_memory_mb > 0 ? a->max_memory_mb : available_memory_mb();
      if (limit > 0 && mib > limit) {
        throw std::runtime_error("a " + std::to_string(a->view.width) + "x" + std::to_string(a->view.height) +
                                 " frame needs about " + std::to_string(int64_t(mib)) + " MiB, above the limit of " +
                                 std::to_string(int64_t(limit)) + " MiB (--max-memory)");
      }
    }

    // --- The octree, the camera and the lights.
    auto start = std::chrono::steady_clock::now();
    octree::Octree tree = octree::load_svo(a->input);
    const double load_ms = elapsed_ms(start);
    // A scene with materials of its own shades them: forward by default.
    if (a->shading.empty() && shades_forward(a->lighting, tree) && *mode == render::Mode::Prefiltered && a->spp <= 1) {
      forward = true;
    }
    // Luminaires light the G-buffer themselves: the forward pass (and its
    // lights) only with an environment, or when asked for.
    if (a->shading.empty() && !a->luminaires.files.empty() && a->lighting.env.empty() && !uses_filter(a->filter)) {
      forward = false;
    }
    const std::string view_name = tools::view_name(a->view);
    const glm::vec3 centre = tree.origin + glm::vec3(0.5f * tree.size);
    render::RenderSettings settings;
    settings.width = a->view.width;
    settings.height = a->view.height;
    settings.camera = resolve_camera(a->view, camera, &tree);
    settings.mode = *mode;
    settings.spp = rays;
    settings.shading.spp = forward ? (a->spp == 0 ? 16 : a->spp) : 1;
    settings.shading.seed = a->seed;
    apply_lighting(a->lighting, settings);
    apply_filter(a->filter, settings);
    settings.adaptive = a->adaptive;
    settings.msaa = a->msaa;
    apply_luminaires(a->luminaires, &tree, settings);
    apply_area_light(a->lighting, tree.origin + glm::vec3(0.5f * tree.size), tree.size, settings);
    settings.footprint_spread = a->footprint_spread;
    settings.curved_masks = !a->flat_masks;
    settings.front_facing = !a->keep_back_facing;
    settings.element_normals = !a->shared_normal;
    settings.covered_part = !a->shade_at_axis;
    settings.crease_split = !a->unsplit_creases;
    settings.shading_voxel = a->shading_voxel;
    settings.lens_parts = a->lens_parts;
    settings.shadows = a->view.shadows;
    settings.gbuffer = !a->gbuffer.empty();
    for (const auto& [name, path] : aovs) {
      settings.gbuffer = settings.gbuffer || name == "gbuffer";
      settings.display = settings.display || name == "display";
    }
    settings.lights = make_lights(a->view, centre, settings.camera);
    // The area light (and --ambient) light the frame alone, unless --light is given.
    if (settings.shading.area_light && a->view.lights.empty()) settings.lights.clear();

    // --- Render.
    auto setup_start = std::chrono::steady_clock::now();
    std::unique_ptr<render::Renderer> renderer =
        render::make_renderer(tree, {a->cpu ? "native" : a->device, a->validate});
    render::AdaptivePass* adaptive_pass = nullptr;
    if (adaptive) {
      auto pass = std::make_unique<render::AdaptivePass>();
      adaptive_pass = pass.get();
      renderer->add_pass(std::move(pass));
    } else if (forward && uses_filter(a->filter)) {
      add_filter_passes(a->filter, *renderer);
    } else if (forward) {
      renderer->add_pass(render::make_pass("forward"));
    }
    if (!settings.luminaire.luminaires.empty()) renderer->add_pass(std::make_unique<render::LuminairePass>(forward));
    for (const std::string& name : a->passes) renderer->add_pass(render::make_pass(name));
    const double setup_ms = elapsed_ms(setup_start);
    {
      const std::vector<std::string> names = renderer->image_names();
      for (const auto& [name, path] : aovs) {
        if (std::find(names.begin(), names.end(), name) == names.end()) {
          std::string list;
          for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
          throw std::invalid_argument("--aov: the frame has no image '" + name + "' (images: " + list + ")");
        }
      }
    }
    render::Frame frame = renderer->render(settings);
    std::vector<double> times{render::frame_ms(frame)};
    std::vector<double> walls;  // warm frames' host time, read-back included (the first also allocates)
    for (uint32_t r = 1; r < a->repeats; ++r) {
      render::Frame again = renderer->render(settings);
      times.push_back(render::frame_ms(again));
      walls.push_back(again.wall_ms);
      frame.passes = again.passes;  // the passes' times of a warm frame
    }
    std::sort(times.begin(), times.end());
    std::sort(walls.begin(), walls.end());
    const std::vector<std::string> messages = renderer->validation_messages();

    // --- Outputs (written even when validation complained, so that the frame can be inspected).
    render::write_colour(a->output, frame, film);
    if (!a->gbuffer.empty()) render::write_gbuffer(a->gbuffer, frame);
    if (!a->steps.empty()) render::write_steps(a->steps, frame);
    if (!a->save_camera.empty()) render::save_camera_json(a->save_camera, settings.camera);
    for (const auto& [name, path] : aovs) render::write_aov(path, *renderer, name);

    const bool gpu_timed = frame.gpu_ms >= 0;
    const double ms = times[times.size() / 2];
    // Per covered pixel (DESIGN section 9); -1 when nothing is covered.
    const double us_per_pixel = frame.covered_pixels > 0 ? ms * 1000.0 / double(frame.covered_pixels) : -1.0;
    nlohmann::json passes = nlohmann::json::array();
    for (const auto& p : frame.passes)
      passes.push_back({{"name", p.name}, {"ms", p.ms >= 0 ? nlohmann::json(p.ms) : nlohmann::json(nullptr)}});
    if (a->json) {
      nlohmann::json out{
          {"file", a->input},
          {"output", a->output},
          {"width", frame.width},
          {"height", frame.height},
          {"mode", render::mode_name(*mode)},
          {"spp", forward ? settings.shading.spp : rays},
          {"msaa", settings.msaa},
          {"shading", adaptive  ? "adaptive"
                      : forward ? "forward"
                                : "tracer"},
          {"adaptive",
           adaptive_pass ? adaptive_json(adaptive_pass->stats(), settings.adaptive) : nlohmann::json(nullptr)},
          {"filter", uses_filter(a->filter) ? nlohmann::json{{"weight", a->filter.weight},
                                                             {"beta", settings.filter.beta},
                                                             {"sigma_n2", settings.filter.sigma_n2},
                                                             {"radius", settings.filter.radius},
                                                             {"upsample", a->filter.upsample}}
                                            : nlohmann::json(nullptr)},
          {"luminaires", settings.luminaire.luminaires.empty()
                             ? nlohmann::json(nullptr)
                             : nlohmann::json{{"files", a->luminaires.files},
                                              {"sampler", a->luminaires.sampler},
                                              {"spp", settings.luminaire.spp},
                                              {"kmax", settings.luminaire.kmax},
                                              {"visibility", a->luminaires.visibility},
                                              {"search", a->luminaires.search},
                                              {"sequence", a->luminaires.sequence}}},
          {"env", a->lighting.env.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->lighting.env)},
          {"area_light",
           a->lighting.area_light.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->lighting.area_light)},
          {"material", settings.shading.material
                           ? nlohmann::json::parse(render::material_json(*settings.shading.material))
                           : nlohmann::json(nullptr)},
          {"view", view_name},
          {"device", renderer->device_name()},
          {"device_type", renderer->device_type()},
          {"host", render::host_name(renderer->host())},
          {"ms", ms},
          {"ms_source", gpu_timed ? "gpu timestamps" : "wall clock"},
          {"repeats", a->repeats},
          {"ms_each", times},
          {"passes", passes},
          {"gpu_ms", gpu_timed ? nlohmann::json(frame.gpu_ms) : nlohmann::json(nullptr)},
          {"wall_ms", frame.wall_ms},
          {"warm_wall_ms", walls.empty() ? nlohmann::json(nullptr) : nlohmann::json(walls[walls.size() / 2])},
          {"load_ms", load_ms},
          {"setup_ms", setup_ms},
          {"covered_pixels", frame.covered_pixels},
          {"us_per_pixel", us_per_pixel >= 0 ? nlohmann::json(us_per_pixel) : nlohmann::json(nullptr)},
          {"steps_per_pixel", frame.steps_per_pixel},
          {"shadows", settings.shadows},
          {"footprint_spread", settings.footprint_spread},
          {"curved_masks", settings.curved_masks},
          {"front_facing", settings.front_facing},
          {"element_normals", settings.element_normals},
          {"covered_part", settings.covered_part},
          {"crease_split", settings.crease_split},
          {"shading_voxel", settings.shading_voxel},
          {"lens_parts", render::lens_parts(tree, settings)},
          {"lights", lights_json(settings.lights)},
          {"camera", camera_json(settings.camera)},
          {"gbuffer", a->gbuffer.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->gbuffer)},
          {"validation_messages", messages}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << std::fixed << std::setprecision(1) << a->input << " -> " << a->output << ": " << frame.width << "x"
                << frame.height << " " << render::mode_name(*mode) << ", view " << view_name << ", " << ms << " ms "
                << render::frame_clock(frame, renderer->host()) << " (" << frame.wall_ms << " ms wall), ";
      if (us_per_pixel >= 0) {
        std::cout << std::setprecision(3) << us_per_pixel << " us per covered pixel (" << frame.covered_pixels
                  << " covered)";
      } else {
        std::cout << "no pixel covered";
      }
      std::cout << ", " << std::setprecision(1) << frame.steps_per_pixel << " steps/pixel, " << renderer->device_name()
                << "\n";
    }
    if (!messages.empty()) {
      for (const auto& m : messages) std::cerr << "validation: " << m << "\n";
      throw std::runtime_error("render: " + std::to_string(messages.size()) +
                               " Vulkan validation message(s) (above); the image was written");
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
