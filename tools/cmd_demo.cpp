// svo demo: the main job on an embedded default. Voxelizes the built-in
// bumpy sphere (paper Fig. 11), renders a far and a close view on the GPU
// tracer and writes svo-demo.png and svo-demo-close.png, with the times.
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "progress.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"

namespace svo::tools {

namespace {

struct DemoArgs {
  std::string directory = ".";
  uint32_t resolution = 256;
  uint32_t size = 512;
  std::string device;
  bool json = false;
};

}  // namespace

void add_demo_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "demo",
      "Build the bumpy-sphere scene, render a far and a close view by cone tracing on the GPU and write\n"
      "svo-demo.png (far) and svo-demo-close.png; prints the voxelize and render times");
  auto a = std::make_shared<DemoArgs>();
  cmd->add_option("-o,--output", a->directory, "Directory for the images (must exist)")->default_val(".");
  cmd->add_option("--resolution", a->resolution, "Finest lattice cells per axis: a power of two")
      ->default_val(256)
      ->check(CLI::IsMember({32u, 64u, 128u, 256u, 512u, 1024u}));
  cmd->add_option("--size", a->size, "Image width and height, pixels")->default_val(512)->check(CLI::Range(16u, 4096u));
  cmd->add_option("--device", a->device, kDeviceHelp);
  cmd->add_flag("--json", a->json, "Print one JSON object on stdout instead of text");
  cmd->callback([a, &exit_code] {
    const std::string far_path = (std::filesystem::path(a->directory) / "svo-demo.png").string();
    const std::string close_path = (std::filesystem::path(a->directory) / "svo-demo-close.png").string();
    render::check_writable_output(far_path);

    auto scene = voxelizer::make_scene("bumpy-sphere");
    voxelizer::VoxelizeOptions options;
    options.resolution = a->resolution;
    voxelizer::VoxelizeReport report;
    octree::Octree tree;
    {
      ProgressBar bar("voxelize");
      options.progress = [&bar](const std::string& stage, double f) { bar.update(stage, f); };
      tree = voxelizer::voxelize(*scene, options, &report);
    }
    if (!a->json) {
      std::cout << std::fixed << std::setprecision(2) << "voxelized bumpy-sphere at " << a->resolution << "^3 in "
                << report.seconds_total << " s: " << tree.depth_count << " levels, " << tree.brick_count << " bricks\n";
    }

    auto setup_start = std::chrono::steady_clock::now();
    std::unique_ptr<render::Renderer> made = render::make_renderer(tree, {a->device});
    render::Renderer& renderer = *made;
    const double setup_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - setup_start).count();
    nlohmann::json views = nlohmann::json::array();
    for (const auto& [name, path] : {std::pair{"far", far_path}, std::pair{"close", close_path}}) {
      render::RenderSettings settings;
      settings.width = settings.height = a->size;
      settings.camera = render::view_preset(tree, name);
      render::Frame frame = renderer.render(settings);
      render::write_colour(path, frame);
      const bool gpu_timed = frame.gpu_ms >= 0;
      const double ms = render::frame_ms(frame);
      const double us = frame.covered_pixels > 0 ? ms * 1000.0 / double(frame.covered_pixels) : 0.0;
      views.push_back({{"view", name},
                       {"output", path},
                       {"ms", ms},
                       {"gpu_ms", gpu_timed ? nlohmann::json(frame.gpu_ms) : nlohmann::json(nullptr)},
                       {"wall_ms", frame.wall_ms},
                       {"covered_pixels", frame.covered_pixels},
                       {"us_per_pixel", frame.covered_pixels > 0 ? nlohmann::json(us) : nlohmann::json(nullptr)},
                       {"steps_per_pixel", frame.steps_per_pixel}});
      if (!a->json) {
        std::cout << std::setprecision(1) << name << ": " << a->size << "x" << a->size << " in " << ms << " ms "
                  << render::frame_clock(frame, renderer.host()) << " (" << frame.wall_ms << " ms wall), "
                  << std::setprecision(3) << us << " us per covered pixel, " << std::setprecision(1)
                  << frame.steps_per_pixel << " steps/pixel -> " << path << "\n";
      }
    }
    if (a->json) {
      nlohmann::json out{{"scene", "bumpy-sphere"},
                         {"resolution", a->resolution},
                         {"size", a->size},
                         {"voxelize_seconds", report.seconds_total},
                         {"bricks", tree.brick_count},
                         {"device", renderer.device_name()},
                         {"device_type", renderer.device_type()},
                         {"setup_ms", setup_ms},
                         {"views", views}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << "device: " << renderer.device_name() << " (" << renderer.device_type() << "), setup "
                << std::setprecision(1) << setup_ms << " ms\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
