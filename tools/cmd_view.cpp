// svo view: an interactive window on a .svo file. Each frame the cone tracer
// renders the view (GpuRenderer, with its display pass: 8-bit sRGB) and the
// swapchain shows it stretched to the window. Frames are drawn when something
// changed, not continuously, so an idle viewer costs nothing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <span>
#include <sstream>

#include "commands.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"
#include "svo/render/vk_swapchain.h"
#include "view_options.h"
#include "view_orbit.h"
#include "view_window.h"

namespace svo::tools {

namespace {

struct ViewerOptions {
  std::string path;
  int width = 800, height = 600;
  double scale = 0;  // 0: automatic
  std::string device;
  std::string view = "far";
  std::string mode = "prefiltered";
  bool shadows = false;
  int frames = 0;
  std::string screenshot;
  bool validate = false;
  LightingOptions lighting;
  uint32_t spp = 4;
};

const char* kControls =
    "Controls: left-drag orbit, right- or middle-drag pan, wheel or +/- zoom (by factors: deep zoom works),\n"
    "F orbit around the surface under the cursor, 1-4 mode (prefiltered, nearest, alpha, mip),\n"
    "S shadows on/off, R back to the far view, Esc or Q quit.\n"
    "The title shows the mode, the time of the passes (GPU timestamps, or the native host's) and the wall time\n"
    "of the frame. Without a GPU, frames are rendered natively on the CPU and presented through lavapipe.";

std::string format_ms(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, ms >= 100 ? "%.0f" : "%.1f", ms);
  return text;
}

}  // namespace

void add_view_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("view", "Look at a .svo file in a window (GLFW, Vulkan swapchain)");
  cmd->footer(kControls);
  auto opt = std::make_shared<ViewerOptions>();
  cmd->add_option("FILE", opt->path, "The octree (.svo)")->required();
  auto* window = cmd->add_option_group("Window");
  window->add_option("--width", opt->width, "Window width in pixels")->default_val(800)->check(CLI::Range(16, 8192));
  window->add_option("--height", opt->height, "Window height in pixels")->default_val(600)->check(CLI::Range(16, 8192));
  window
      ->add_option("--scale", opt->scale,
                   "Render at this fraction of the window size and stretch it (default: 1 on a GPU, 0.5 on the "
                   "native host or a Vulkan CPU device such as lavapipe)")
      ->check(CLI::Range(0.05, 1.0));
  auto* view = cmd->add_option_group("View");
  view->add_option("--view", opt->view, "Starting camera preset: far, mid or close")
      ->default_val("far")
      ->check(CLI::IsMember({"far", "mid", "close"}));
  view->add_option("--mode", opt->mode, "Starting mode: prefiltered, nearest, alpha or mip")
      ->default_val("prefiltered")
      ->check(CLI::IsMember({"prefiltered", "nearest", "alpha", "mip"}));
  view->add_flag("--shadows", opt->shadows, "Start with shadow cones on");
  auto* run = cmd->add_option_group("Run");
  run->add_option("--device", opt->device,
                  std::string(kDeviceHelp) +
                      ". Frames rendered natively are shown through the Vulkan device that "
                      "can present (lavapipe on a machine without a GPU)");
  run->add_flag("--validate", opt->validate,
                "Enable the Khronos validation layer; any message ends the viewer with exit 1");
  run->add_option("--frames", opt->frames, "Render this many frames, then exit 0 (for tests; default 0: until closed)")
      ->check(CLI::Range(0, 1000000));
  run->add_option("--screenshot", opt->screenshot, "On exit, write the last rendered frame here (.png or .exr)");
  add_lighting_options(*cmd, opt->lighting);
  cmd->add_option("--spp", opt->spp, "Samples per pixel of the forward-shading pass (with --env or --material)")
      ->check(CLI::Range(1u, 4096u))
      ->group("Lighting");

  cmd->callback([opt, &exit_code] {
    if (!opt->screenshot.empty()) {
      render::image_format(opt->screenshot);
      render::check_writable_output(opt->screenshot);
    }
    octree::Octree tree = octree::load_svo(opt->path);
    auto fail = [](const std::string& what) { throw std::runtime_error("view: " + what); };

    std::unique_ptr<Window> win;
    try {
      win = std::make_unique<Window>("svo view " + opt->path, opt->width, opt->height);
    } catch (const std::exception& e) {
      fail(e.what());
    }
    // The host that renders; the window presents through a Vulkan device
    // either way (the one rendering, or the default one that can present).
    const std::string device = render::resolve_device(opt->device);
    const bool native = device == "native";
    vk::ContextOptions options{native ? "" : device, opt->validate};
    win->prepare(options);
    vk::Context context(options);
    auto check_validation = [&] {
      auto messages = context.validation_messages();
      if (!messages.empty()) {
        fail("validation: " + messages.front() +
             (messages.size() > 1 ? " (and " + std::to_string(messages.size() - 1) + " more)" : ""));
      }
    };
    uint32_t fb_width = 0, fb_height = 0;
    win->framebuffer_size(fb_width, fb_height);
    vk::Swapchain swapchain(context, fb_width, fb_height);
    std::unique_ptr<render::Renderer> made;
    if (native) {
      made = std::make_unique<render::NativeRenderer>(tree);
    } else {
      made = std::make_unique<render::GpuRenderer>(context, tree);
    }
    render::Renderer& renderer = *made;
    if (shades_forward(opt->lighting, tree)) renderer.add_pass(render::make_pass("forward"));
    double scale = opt->scale > 0 ? opt->scale : native || context.info().type == "cpu" ? 0.5 : 1.0;

    render::RenderSettings settings;
    settings.mode = *render::parse_mode(opt->mode);
    settings.shadows = opt->shadows;
    apply_lighting(opt->lighting, settings);
    settings.shading.spp = opt->spp;
    float aspect = float(fb_width) / float(std::max(fb_height, 1u));
    Orbit orbit(render::view_preset(tree, opt->view, aspect), tree.size);

    render::Frame frame;
    settings.display = true;
    auto pixels = [&frame] {  // the display pass's RGBA words as bytes (little-endian: R first)
      return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(frame.display.data()), frame.display.size() * 4);
    };
    bool dirty = true, shown = false, focus = false, minimised = false;
    int frames = 0;
    while (true) {
      // Block for events while there is nothing new to draw (or nowhere to draw it).
      Input in = win->poll(/*wait=*/minimised || (!dirty && shown && opt->frames == 0));
      uint32_t win_width = 0, win_height = 0;
      win->window_size(win_width, win_height);
      bool quit = false;
      for (uint32_t key : in.keys) {
        switch (key) {
          case Window::kQuit:
            quit = true;
            break;
          case Window::kZoomIn:
            orbit.zoom(0.8);
            break;
          case Window::kZoomOut:
            orbit.zoom(1.25);
            break;
          case Window::kMode1:
          case Window::kMode2:
          case Window::kMode3:
          case Window::kMode4:
            settings.mode = render::Mode(key - Window::kMode1);
            break;
          case Window::kShadows:
            settings.shadows = !settings.shadows;
            break;
          case Window::kReset:
            win->framebuffer_size(fb_width, fb_height);
            orbit =
                Orbit(render::view_preset(tree, "far", float(fb_width) / float(std::max(fb_height, 1u))), tree.size);
            break;
          case Window::kFocus:
            focus = true;
            break;
        }
        dirty = true;
      }
      if (quit || win->closing()) break;
      if (in.rotate_x != 0 || in.rotate_y != 0) orbit.rotate(in.rotate_x, in.rotate_y, win_height), dirty = true;
      if (in.pan_x != 0 || in.pan_y != 0) orbit.pan(in.pan_x, in.pan_y, win_height), dirty = true;
      if (in.scroll != 0) orbit.zoom(std::pow(0.85, in.scroll)), dirty = true;

      win->framebuffer_size(fb_width, fb_height);
      minimised = fb_width == 0 || fb_height == 0;
      if (minimised) {
        dirty = true;  // redraw when the window comes back
        continue;
      }
      VkExtent2D extent = swapchain.extent();
      if (in.resized || extent.width != fb_width || extent.height != fb_height) {
        swapchain.resize(fb_width, fb_height);
        dirty = true;
      }
      if (opt->frames > 0) dirty = true;

      if (dirty) {
        auto start = std::chrono::steady_clock::now();
        settings.width = std::max(1u, uint32_t(std::lround(fb_width * scale)));
        settings.height = std::max(1u, uint32_t(std::lround(fb_height * scale)));
        settings.camera = orbit.camera();
        settings.gbuffer = focus;
        frame = renderer.render(settings);
        check_validation();
        if (focus && !frame.gbuffer.empty()) {
          // Orbit around the surface point under the cursor, if there is one.
          uint32_t x = uint32_t(std::clamp(in.cursor_x / std::max(win_width, 1u), 0.0, 0.999) * frame.width);
          uint32_t y = uint32_t(std::clamp(in.cursor_y / std::max(win_height, 1u), 0.0, 0.999) * frame.height);
          const render::GBufferTexel& t = frame.gbuffer[size_t(y) * frame.width + x];
          if (t.coverage > 0) {
            orbit.look_at(settings.camera.eye, t.position);
            settings.camera = orbit.camera();
            settings.gbuffer = false;
            frame = renderer.render(settings);
            check_validation();
          }
        }
        focus = false;
        bool ok = swapchain.present(pixels(), frame.width, frame.height);
        if (!ok) {
          win->framebuffer_size(fb_width, fb_height);
          swapchain.resize(fb_width, fb_height);
          if (fb_width > 0 && fb_height > 0) swapchain.present(pixels(), frame.width, frame.height);
        }
        check_validation();
        double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        std::ostringstream title;
        title << "svo view " << opt->path << " | " << render::mode_name(settings.mode)
              << (settings.shadows ? " + shadows" : "") << " | " << (native ? "native " : "GPU ")
              << (frame.ms >= 0 ? format_ms(frame.ms) + " ms" : "n/a") << ", frame " << format_ms(wall_ms) << " ms | "
              << frame.width << "x" << frame.height;
        win->set_title(title.str());
        dirty = false;
        shown = true;
        ++frames;
        if (opt->frames > 0 && frames >= opt->frames) break;
      } else if (in.exposed) {
        if (!swapchain.present(pixels(), frame.width, frame.height)) dirty = true;
        check_validation();
      }
    }
    if (!opt->screenshot.empty() && frames > 0) render::write_colour(opt->screenshot, frame);
    check_validation();
    exit_code = 0;
  });
}

}  // namespace svo::tools
