// svo render: one frame of a .svo file by cone tracing (Heitz & Neyret
// Algorithm 1) to PNG or EXR, with an optional G-buffer and timing figures.
// Every argument and both output paths are checked before the octree is
// loaded or a device is opened; bad input is one line and exit code 1.
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"

namespace svo::tools {

namespace {

struct RenderArgs {
  std::string input;
  std::string output;
  std::string gbuffer;
  std::string save_camera;
  uint32_t width = 512;
  uint32_t height = 512;
  std::string view = "far";
  std::string camera;
  std::string camera_file;
  std::vector<float> dof;
  std::string mode = "prefiltered";
  bool shadows = false;
  std::vector<std::string> lights;
  std::string device;
  bool validate = false;
  bool cpu = false;
  bool json = false;
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

// A float as the shortest decimal that reads back as the same float (0.1, not 0.10000000149011612).
double json_float(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

nlohmann::json vec_json(glm::vec3 v) { return {json_float(v.x), json_float(v.y), json_float(v.z)}; }

}  // namespace

void add_render_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "render",
      "Render one frame of a .svo file by cone tracing (one cone per pixel, pre-filtered appearance).\n"
      "The image is written to a temporary name and renamed; outputs are checked before rendering");
  auto a = std::make_shared<RenderArgs>();
  cmd->add_option("FILE", a->input, "The .svo file to render")->required()->group("Input");

  cmd->add_option("-o,--output", a->output,
                  "Image: .png (8-bit sRGB, clamped, background composited) or .exr (float linear RGB, A = coverage)")
      ->required()
      ->group("Output");
  cmd->add_option("--width", a->width, "Image width, pixels")
      ->default_val(512)
      ->check(CLI::Range(1u, 16384u))
      ->group("Output");
  cmd->add_option("--height", a->height, "Image height, pixels")
      ->default_val(512)
      ->check(CLI::Range(1u, 16384u))
      ->group("Output");
  cmd->add_option("--gbuffer", a->gbuffer,
                  "Also write the G-buffer as one float .exr: depth, P.x/y/z, N.x/y/z, slope_variance, abar.R/G/B, "
                  "coverage")
      ->group("Output");
  cmd->add_option("--save-camera", a->save_camera, "Also write the camera used as JSON (the form of --camera-file)")
      ->group("Output");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: width, height, ms, wall_ms, covered_pixels, us_per_pixel, "
                "steps_per_pixel, mode, view, device, ...")
      ->group("Output");

  auto* view = cmd->add_option("--view", a->view,
                               "Camera preset from the octree's bounds: far (whole domain), mid (3x closer), close "
                               "(a few voxels from the surface)")
                   ->default_val("far")
                   ->group("Camera");
  auto* camera = cmd->add_option("--camera", a->camera,
                                 "Camera ex,ey,ez,tx,ty,tz,ux,uy,uz,fov: eye, target, up, vertical fov in (0, 180) "
                                 "degrees")
                     ->group("Camera");
  auto* camera_file = cmd->add_option("--camera-file", a->camera_file,
                                      "Camera from JSON: {\"eye\":[x,y,z],\"target\":[..],\"up\":[..],\"fov\":deg,"
                                      "\"aperture\":r,\"focus\":d} (aperture and focus optional)")
                          ->group("Camera");
  view->excludes(camera)->excludes(camera_file);
  camera->excludes(camera_file);
  cmd->add_option("--dof", a->dof, "Thin lens APERTURE,FOCUS: lens radius >= 0 and focus distance > 0, scene units")
      ->delimiter(',')
      ->expected(2)
      ->group("Camera");

  cmd->add_option("--mode", a->mode,
                  "prefiltered (ours), nearest (binary voxels, nearest level), alpha (coverage as opacity), "
                  "mip (averaged colour and normal)")
      ->default_val("prefiltered")
      ->group("Shading");
  cmd->add_flag("--shadows", a->shadows, "Soft shadows by shadow cones towards each light")->group("Shading");
  cmd->add_option("--light", a->lights,
                  "A light, repeatable up to " + std::to_string(render::kMaxLights) +
                      " (default: dir:0.4,0.8,0.6):\n"
                      "dir:X,Y,Z[,IRRADIANCE[,ANGLE]] towards (X,Y,Z), irradiance default 3, angular radius "
                      "default 0.02 rad;\n"
                      "point:X,Y,Z[,INTENSITY[,RADIUS]] at (X,Y,Z), default intensity gives irradiance 3 at the "
                      "domain centre, radius default 1% of the distance to it")
      ->allow_extra_args(false)  // one light per --light, so that FILE may follow it
      ->group("Shading");

  auto* device = cmd->add_option("--device", a->device,
                                 "Vulkan device: index or name substring (default: discrete > integrated > cpu; see "
                                 "svo devices)")
                     ->group("Device");
  auto* validate =
      cmd->add_flag("--validate", a->validate, "Enable the Khronos validation layer; any message fails the command")
          ->group("Device");
  cmd->add_flag("--cpu", a->cpu, "Trace on the CPU (the reference implementation of the same tracer; slow)")
      ->excludes(device)
      ->excludes(validate)
      ->group("Device");

  cmd->callback([a, &exit_code] {
    // --- Everything that can be checked without the octree or a device.
    std::optional<render::Mode> mode = render::parse_mode(a->mode);
    if (!mode) throw std::invalid_argument("unknown mode '" + a->mode + "' (modes: prefiltered, nearest, alpha, mip)");
    const auto presets = render::view_preset_names();
    if (a->camera.empty() && a->camera_file.empty() &&
        std::find(presets.begin(), presets.end(), a->view) == presets.end()) {
      throw std::invalid_argument("unknown view '" + a->view + "' (views: far, mid, close)");
    }
    if (a->lights.size() > size_t(render::kMaxLights)) {
      throw std::invalid_argument("--light given " + std::to_string(a->lights.size()) + " times, at most " +
                                  std::to_string(render::kMaxLights));
    }
    for (const auto& light : a->lights) render::parse_light(light, glm::vec3(0));  // syntax only
    std::ostringstream dof;
    if (a->dof.size() == 2) {
      dof << "--dof " << a->dof[0] << "," << a->dof[1];
      if (!(a->dof[0] >= 0)) throw std::invalid_argument(dof.str() + ": aperture must be >= 0");
      if (!(a->dof[1] > 0)) throw std::invalid_argument(dof.str() + ": focus must be > 0");
    }
    const std::string dof_where = dof.str();
    std::optional<render::Camera> camera;
    if (!a->camera.empty()) camera = render::parse_camera(a->camera);
    if (!a->camera_file.empty()) camera = render::load_camera_json(a->camera_file);
    render::image_format(a->output);
    render::check_writable_output(a->output);
    if (!a->gbuffer.empty()) {
      if (render::image_format(a->gbuffer) != render::ImageFormat::Exr) {
        throw std::invalid_argument(a->gbuffer + ": the G-buffer is written as OpenEXR only (use .exr)");
      }
      render::check_writable_output(a->gbuffer);
    }
    if (!a->save_camera.empty()) render::check_writable_output(a->save_camera);

    // --- The octree, the camera and the lights.
    auto start = std::chrono::steady_clock::now();
    octree::Octree tree = octree::load_svo(a->input);
    const double load_ms = elapsed_ms(start);
    std::string view_name = camera ? (a->camera.empty() ? "camera-file" : "camera") : a->view;
    if (!camera) camera = render::view_preset(tree, a->view, float(a->width) / float(a->height));
    if (a->dof.size() == 2) {
      camera->aperture = a->dof[0];
      camera->focus = a->dof[1];
      render::validate_camera(*camera, dof_where);
    }
    render::RenderSettings settings;
    settings.width = a->width;
    settings.height = a->height;
    settings.camera = *camera;
    settings.mode = *mode;
    settings.shadows = a->shadows;
    settings.gbuffer = !a->gbuffer.empty();
    if (!a->lights.empty()) {
      const glm::vec3 centre = tree.origin + glm::vec3(0.5f * tree.size);
      settings.lights.clear();
      for (const auto& light : a->lights) settings.lights.push_back(render::parse_light(light, centre));
    }

    // --- Render.
    render::Frame frame;
    std::string device_name = "cpu (render_cpu)", device_type = "cpu";
    std::vector<std::string> messages;
    double setup_ms = 0;
    if (a->cpu) {
      frame = render::render_cpu(tree, settings);
    } else {
      auto setup_start = std::chrono::steady_clock::now();
      vk::Context context({a->device, a->validate});
      render::GpuRenderer renderer(context, tree);
      setup_ms = elapsed_ms(setup_start);
      frame = renderer.render(settings);
      device_name = context.info().name;
      device_type = context.info().type;
      messages = context.validation_messages();
    }

    // --- Outputs (written even when validation complained, so that the frame can be inspected).
    render::write_colour(a->output, frame);
    if (!a->gbuffer.empty()) render::write_gbuffer(a->gbuffer, frame);
    if (!a->save_camera.empty()) render::save_camera_json(a->save_camera, settings.camera);

    const bool gpu_timed = frame.gpu_ms >= 0;
    const double ms = gpu_timed ? frame.gpu_ms : frame.wall_ms;
    // Per covered pixel (DESIGN section 9); -1 when nothing is covered.
    const double us_per_pixel = frame.covered_pixels > 0 ? ms * 1000.0 / double(frame.covered_pixels) : -1.0;
    if (a->json) {
      nlohmann::json lights = nlohmann::json::array();
      for (const auto& l : settings.lights) {
        lights.push_back({{"type", l.point ? "point" : "directional"},
                          {"vector", vec_json(l.vector)},
                          {"radiance", vec_json(l.radiance)},
                          {"size", json_float(l.size)}});
      }
      const render::Camera& c = settings.camera;
      nlohmann::json out{{"file", a->input},
                         {"output", a->output},
                         {"width", frame.width},
                         {"height", frame.height},
                         {"mode", render::mode_name(*mode)},
                         {"view", view_name},
                         {"device", device_name},
                         {"device_type", device_type},
                         {"ms", ms},
                         {"ms_source", gpu_timed ? "gpu timestamps" : "wall clock"},
                         {"gpu_ms", gpu_timed ? nlohmann::json(frame.gpu_ms) : nlohmann::json(nullptr)},
                         {"wall_ms", frame.wall_ms},
                         {"load_ms", load_ms},
                         {"setup_ms", setup_ms},
                         {"covered_pixels", frame.covered_pixels},
                         {"us_per_pixel", us_per_pixel >= 0 ? nlohmann::json(us_per_pixel) : nlohmann::json(nullptr)},
                         {"steps_per_pixel", frame.steps_per_pixel},
                         {"shadows", settings.shadows},
                         {"lights", lights},
                         {"camera",
                          {{"eye", vec_json(c.eye)},
                           {"target", vec_json(c.target)},
                           {"up", vec_json(c.up)},
                           {"fov", json_float(c.fov_deg)},
                           {"aperture", json_float(c.aperture)},
                           {"focus", json_float(c.focus)}}},
                         {"gbuffer", a->gbuffer.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->gbuffer)},
                         {"validation_messages", messages}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << std::fixed << std::setprecision(1) << a->input << " -> " << a->output << ": " << frame.width << "x"
                << frame.height << " " << render::mode_name(*mode) << ", view " << view_name << ", " << ms << " ms "
                << (gpu_timed ? "GPU" : "wall") << " (" << frame.wall_ms << " ms wall), ";
      if (us_per_pixel >= 0) {
        std::cout << std::setprecision(3) << us_per_pixel << " us per covered pixel (" << frame.covered_pixels
                  << " covered)";
      } else {
        std::cout << "no pixel covered";
      }
      std::cout << ", " << std::setprecision(1) << frame.steps_per_pixel << " steps/pixel, " << device_name << "\n";
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
