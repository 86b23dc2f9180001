// svo view: an interactive window on an octree, or on a mesh or built-in
// scene voxelized first. Each frame the cone tracer renders the view (with
// its display pass: 8-bit sRGB) and the swapchain shows it stretched to the
// window. Frames are drawn when something changed, not continuously, so an
// idle viewer costs nothing; while the camera moves they are drawn smaller,
// sized to a frame-time budget, and the view is drawn again at full size
// once it stops.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <span>
#include <sstream>

#include "commands.h"
#include "memory.h"
#include "progress.h"
#include "source_options.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/text.h"
#include "svo/render/vk_context.h"
#include "svo/render/vk_swapchain.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/vdb.h"
#include "view_options.h"
#include "view_orbit.h"
#include "view_window.h"

namespace svo::tools {

namespace {

struct ViewerOptions {
  SourceOptions source;  // the positional FILE (an octree or a mesh), --scene, --scene-file
  uint32_t resolution = 256;
  int width = 800, height = 600;
  double scale = 0;  // 0: automatic
  std::string device;
  std::string view = "far";
  std::string mode = "prefiltered";
  bool shadows = false;
  int frames = 0;
  std::string screenshot;
  std::string screenshot_dir = ".";
  std::string grid;  // --grid: the level set of a .vdb input
  double budget_ms = 50;
  bool validate = false;
  LightingOptions lighting;
  uint32_t spp = 4;
};

// The mesh formats voxelizer::read_mesh reads, by extension.
// (voxelizer::load_vdb reads .vdb level sets.)
constexpr const char* kMeshExtensions[] = {".obj", ".ply", ".off", ".stl", ".gltf", ".glb", ".vdb"};

const char* kKeys =
    "Keys: left-drag orbit, right- or middle-drag pan, wheel or +/- zoom (by factors: deep zoom works),\n"
    "F orbit around the surface under the cursor, 1-4 mode (prefiltered, nearest, alpha, mip),\n"
    "S shadows on/off, R back to the far view, P or F12 screenshot at the window's size\n"
    "(svo-view-NNNN.png, never overwritten; its name is printed), H or F1 these keys over the view (and on\n"
    "stdout), Esc or Q quit.";

const char* kTitleKeys = "H keys, P screenshot, Q quit";

// The overlay H shows, one key a line (render/text.h draws capitals).
constexpr const char* kOverlay[] = {"DRAG    ORBIT",
                                    "R-DRAG  PAN (OR MIDDLE)",
                                    "WHEEL   ZOOM (OR + -)",
                                    "F       ORBIT CURSOR POINT",
                                    "1 2 3 4 PREFILT NEAR ALPHA MIP",
                                    "S       SHADOWS ON/OFF",
                                    "R       RESET THE VIEW",
                                    "P F12   SCREENSHOT",
                                    "H F1    HIDE THE KEYS",
                                    "ESC Q   QUIT"};

// Draws kOverlay over frame.display (8-bit sRGB RGBA words, R in the low
// byte) at the top left: a box darkened to 30% and the lines in white,
// `scale` pixels a font cell. Parts beyond the frame are left out.
void draw_overlay(render::Frame& frame, int scale) {
  const int pad = 4 * scale, line = (render::kGlyphHeight + 4) * scale;
  int width = 0;
  for (const char* text : kOverlay) width = std::max(width, render::text_width(text, scale));
  const int lines = int(std::size(kOverlay));
  render::Frame text;
  text.width = uint32_t(std::min(int(frame.width), width + 2 * pad));
  text.height = uint32_t(std::min(int(frame.height), lines * line - 4 * scale + 2 * pad));
  text.colour.assign(size_t(text.width) * text.height, glm::vec4(0));
  for (int i = 0; i < lines; ++i) render::draw_text(text, pad, pad + i * line, kOverlay[i], glm::vec3(1), scale);
  for (uint32_t y = 0; y < text.height; ++y) {
    for (uint32_t x = 0; x < text.width; ++x) {
      uint32_t& p = frame.display[size_t(y) * frame.width + x];
      if (text.colour[size_t(y) * text.width + x].r > 0.5f) {
        p = 0xffffffffu;
      } else {
        uint32_t out = p & 0xff000000u;
        for (int c = 0; c < 3; ++c) out |= (((p >> (8 * c)) & 0xffu) * 3 / 10) << (8 * c);
        p = out;
      }
    }
  }
}

std::string format_ms(double ms) {
  char text[32];
  std::snprintf(text, sizeof text, ms >= 100 ? "%.0f" : "%.1f", ms);
  return text;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Refuses what svo view cannot open before any work: a file that is neither
// an octree (.svo) nor a mesh it can voxelize, mesh options given with an
// octree, not exactly one of FILE, --scene and --scene-file.
// @throw std::invalid_argument, one line naming the accepted types.
void check_input(const ViewerOptions& o, bool resolution_given) {
  const SourceOptions& s = o.source;
  check_source_options(s, "view");
  if ((o.resolution & (o.resolution - 1)) != 0) {
    throw std::invalid_argument("view: --resolution " + std::to_string(o.resolution) + " is not a power of two");
  }
  if (!o.grid.empty() && !voxelizer::is_vdb_path(s.input)) {
    throw std::invalid_argument("view: --grid names a grid of a .vdb input");
  }
  if (s.input.empty()) return;
  const std::string ext = lower_extension(s.input);
  if (ext == ".svo") {
    if (resolution_given || !s.colour.empty() || s.roughness >= 0) {
      throw std::invalid_argument("view: " + s.input +
                                  " is an octree: --resolution, --colour and --roughness apply to a mesh");
    }
  } else if (std::find(std::begin(kMeshExtensions), std::end(kMeshExtensions), ext) == std::end(kMeshExtensions)) {
    throw std::invalid_argument("view: " + s.input +
                                ": not a file svo view opens (an octree: .svo; voxelized first: a mesh, .obj, .ply, "
                                ".off, .stl, .gltf, .glb, or an OpenVDB level set, .vdb)");
  }
}

// The octree to look at (check_input first): the .svo file itself, or the
// mesh or scene voxelized at --resolution with a progress bar (on a
// terminal) and a one-line summary on stdout.
// @throw what load_svo, read_mesh and voxelize throw; std::runtime_error
//        when the voxelizer's estimate exceeds the memory available.
octree::Octree load_octree(const ViewerOptions& o) {
  const SourceOptions& s = o.source;
  if (!s.input.empty() && lower_extension(s.input) == ".svo") return octree::load_svo(s.input);
  const std::string what = source_name(s);
  std::unique_ptr<voxelizer::SurfaceSource> source;
  if (!s.scene.empty()) {
    source = make_scene_source(s, /*all_octaves=*/false);
  } else if (voxelizer::is_vdb_path(s.input)) {
    voxelizer::VdbOptions vdb;
    vdb.grid = o.grid;
    if (s.colour.size() == 3) vdb.colour = glm::vec3(s.colour[0], s.colour[1], s.colour[2]);
    vdb.sigma_rho = s.roughness;
    source = voxelizer::load_vdb(s.input, vdb);
  } else {
    source = voxelizer::mesh_source(
        read_source_mesh(s, [](const std::string& line) { std::cerr << "svo: warning: " << line << "\n"; }));
  }
  const double limit = available_memory_mb();
  const double estimate = voxelizer::estimate_memory_bytes(*source, o.resolution, 8) / (1024.0 * 1024.0);
  if (limit > 0 && estimate > limit) {
    throw std::runtime_error("view: " + what + ": resolution " + std::to_string(o.resolution) + " needs about " +
                             std::to_string(int64_t(estimate)) + " MiB, above the " + std::to_string(int64_t(limit)) +
                             " MiB available (try a smaller --resolution)");
  }
  ProgressBar bar("voxelize");
  voxelizer::VoxelizeOptions options;
  options.resolution = o.resolution;
  options.progress = [&bar](const std::string& stage, double f) { bar.update(stage, f); };
  voxelizer::VoxelizeReport report;
  octree::Octree tree = voxelizer::voxelize(*source, options, &report);
  bar.finish();
  const std::string input = !s.scene.empty()        ? "--scene " + s.scene
                            : !s.scene_file.empty() ? "--scene-file " + s.scene_file
                                                    : s.input;
  const std::string stem =
      !s.scene.empty() ? s.scene : std::filesystem::path(s.input.empty() ? s.scene_file : s.input).stem().string();
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f", report.seconds_total);
  std::cout << what << ": voxelized at " << o.resolution << "^3 in " << seconds << " s, " << tree.voxel_count()
            << " voxels (to keep them: svo voxelize " << input << (o.grid.empty() ? "" : " --grid " + o.grid)
            << " --resolution " << o.resolution << " -o " << stem << ".svo)" << std::endl;
  return tree;
}

// Reserves the first free DIR/svo-view-NNNN.png from `next` on, by creating
// it empty and exclusively: an existing file is never replaced, and two
// viewers never take the same name.
// @throw std::runtime_error naming the file when it cannot be created.
std::string reserve_screenshot(const std::string& dir, int& next) {
  for (; next <= 9999; ++next) {
    char name[32];
    std::snprintf(name, sizeof name, "svo-view-%04d.png", next);
    const std::string path = dir == "." ? std::string(name) : (std::filesystem::path(dir) / name).string();
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      ++next;
      return path;
    }
    if (errno != EEXIST) throw std::runtime_error("screenshot " + path + ": " + std::strerror(errno));
  }
  throw std::runtime_error("screenshot: " + dir + " holds svo-view-0001.png to svo-view-9999.png already");
}

}  // namespace

void add_view_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "view", "Look at an octree (.svo), or a mesh or built-in scene voxelized first, in a window (GLFW, Vulkan)");
  cmd->footer(kKeys);
  auto opt = std::make_shared<ViewerOptions>();
  add_source_options(*cmd, opt->source);
  cmd->get_option("input")->description(
      "An octree (.svo), or a mesh (OBJ, PLY, OFF, STL, glTF) or OpenVDB level set (.vdb) voxelized first at "
      "--resolution, with a progress bar");
  cmd->add_option("--resolution", opt->resolution,
                  "A mesh or --scene is voxelized at this many finest cells per axis: a power of two")
      ->default_val(256)
      ->check(CLI::Range(16u, 4096u))
      ->group("Input");
  cmd->add_option("--grid", opt->grid, "The grid of a .vdb input, by name (default: its only float level set)")
      ->group("Input");
  auto* window = cmd->add_option_group("Window");
  window->add_option("--width", opt->width, "Window width in pixels")->default_val(800)->check(CLI::Range(16, 8192));
  window->add_option("--height", opt->height, "Window height in pixels")->default_val(600)->check(CLI::Range(16, 8192));
  window
      ->add_option("--scale", opt->scale,
                   "Render the still view at this fraction of the window size and stretch it (default: 1 on a GPU, "
                   "0.5 on the native host or a Vulkan CPU device such as lavapipe)")
      ->check(CLI::Range(0.05, 1.0));
  window
      ->add_option("--frame-budget", opt->budget_ms,
                   "While the camera moves, frames are drawn smaller so that one takes about this many ms; the "
                   "still view is drawn again at --scale (0: always at --scale)")
      ->default_val(50)
      ->check(CLI::Range(0.0, 10000.0));
  auto* view = cmd->add_option_group("View");
  view->add_option("--view", opt->view,
                   "Starting camera preset: far (the object framed), mid (2x closer), close (a surface point, "
                   "the finest voxel 1/64 of the window; 8 voxels away with detail octaves)")
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
  run->add_option("--screenshot", opt->screenshot,
                  "On exit, write the view at the window's size here (.png or .exr; replaced if it exists)");
  run->add_option("--screenshot-dir", opt->screenshot_dir,
                  "Where the P key writes svo-view-NNNN.png (the first free number; default: the current directory)")
      ->check(CLI::ExistingDirectory);
  add_lighting_options(*cmd, opt->lighting);
  cmd->add_option("--spp", opt->spp, "Samples per pixel of the forward-shading pass (with --env or --material)")
      ->check(CLI::Range(1u, 4096u))
      ->group("Lighting");

  cmd->callback([opt, cmd, &exit_code] {
    if (!opt->screenshot.empty()) {
      render::image_format(opt->screenshot);
      render::check_writable_output(opt->screenshot);
    }
    if (::access(opt->screenshot_dir.c_str(), W_OK) != 0) {
      throw std::invalid_argument("view: --screenshot-dir " + opt->screenshot_dir + " is not writable");
    }
    check_input(*opt, cmd->count("--resolution") > 0);
    auto fail = [](const std::string& what) { throw std::runtime_error("view: " + what); };
    // No display: one line now, not after voxelizing.
    try {
      Window::check_display();
    } catch (const std::exception& e) {
      fail(e.what());
    }
    octree::Octree tree = load_octree(*opt);
    const std::string name = opt->source.scene.empty() ? source_name(opt->source) : opt->source.scene;

    std::unique_ptr<Window> win;
    try {
      win = std::make_unique<Window>("svo view " + name, opt->width, opt->height);
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
    const double scale = opt->scale > 0 ? opt->scale : native || context.info().type == "cpu" ? 0.5 : 1.0;

    render::RenderSettings settings;
    settings.mode = *render::parse_mode(opt->mode);
    settings.shadows = opt->shadows;
    apply_lighting(opt->lighting, settings);
    settings.shading.spp = opt->spp;
    float aspect = float(fb_width) / float(std::max(fb_height, 1u));
    Orbit orbit(render::view_preset(tree, opt->view, aspect), tree.size);

    // A frame of the current view at `width` x `height` (for the screen
    // with the display pass, for files without).
    auto render_view = [&](uint32_t width, uint32_t height, bool display) {
      render::RenderSettings s = settings;
      s.width = std::max(1u, width);
      s.height = std::max(1u, height);
      s.camera = orbit.camera();
      s.lights = render::default_lights(s.camera);  // the key and fill follow the camera
      s.display = display;
      s.gbuffer = false;
      render::Frame f = renderer.render(s);
      check_validation();
      return f;
    };
    int next_shot = 1;
    auto screenshot = [&](uint32_t width, uint32_t height) {
      std::string path;
      try {
        path = reserve_screenshot(opt->screenshot_dir, next_shot);
        render::write_colour(path, render_view(width, height, false));
        std::cout << "screenshot " << path << " (" << width << " x " << height << ")" << std::endl;
      } catch (const std::exception& e) {
        std::error_code ignored;
        if (!path.empty()) std::filesystem::remove(path, ignored);
        std::cerr << "svo: view: screenshot not written: " << e.what() << std::endl;
      }
    };

    render::Frame frame;
    settings.display = true;
    auto pixels = [&frame] {  // the display pass's RGBA words as bytes (little-endian: R first)
      return std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(frame.display.data()), frame.display.size() * 4);
    };
    using Clock = std::chrono::steady_clock;
    // While the camera moves (and for kSettle after) frames are drawn at
    // `moving_scale`, chosen from the measured cost of a pixel so that a
    // frame takes about the budget; then the still view at `scale`.
    const auto kSettle = std::chrono::milliseconds(200);
    Clock::time_point last_motion{};
    double moving_scale = scale, ms_per_pixel = -1, present_ms = 0;
    bool dirty = true, shown = false, focus = false, minimised = false, refine = false, help = false;
    uint32_t shot_width = fb_width, shot_height = fb_height;  // the window's last size not minimised
    int frames = 0;
    while (true) {
      // Block for events while there is nothing new to draw (or nowhere to
      // draw it); with a reduced frame on screen, only until it is time to
      // draw the still view.
      Input in;
      if (minimised || (!dirty && shown && opt->frames == 0)) {
        auto left = std::chrono::duration<double>(last_motion + kSettle - Clock::now()).count();
        in = refine && !minimised ? (left > 0 ? win->poll_for(left) : win->poll(false)) : win->poll(true);
      } else {
        in = win->poll(false);
      }
      uint32_t win_width = 0, win_height = 0;
      win->window_size(win_width, win_height);
      bool quit = false, shot = false, motion = false;
      for (uint32_t key : in.keys) {
        switch (key) {
          case Window::kQuit:
            quit = true;
            break;
          case Window::kZoomIn:
            orbit.zoom(0.8);
            motion = true;
            break;
          case Window::kZoomOut:
            orbit.zoom(1.25);
            motion = true;
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
          case Window::kScreenshot:
            shot = true;
            break;
          case Window::kHelp:
            help = !help;
            if (help) std::cout << kKeys << std::endl;
            break;
        }
        if (key != Window::kScreenshot) dirty = true;
      }
      if (quit || win->closing()) break;
      if (in.rotate_x != 0 || in.rotate_y != 0) orbit.rotate(in.rotate_x, in.rotate_y, win_height), motion = true;
      if (in.pan_x != 0 || in.pan_y != 0) orbit.pan(in.pan_x, in.pan_y, win_height), motion = true;
      if (in.scroll != 0) orbit.zoom(std::pow(0.85, in.scroll)), motion = true;
      const auto now = Clock::now();
      if (motion) last_motion = now, dirty = true;
      const bool moving = opt->budget_ms > 0 && now - last_motion < kSettle;
      if (refine && !moving) dirty = true;  // the still view, at full size

      win->framebuffer_size(fb_width, fb_height);
      minimised = fb_width == 0 || fb_height == 0;
      if (minimised) {
        dirty = true;  // redraw when the window comes back
        continue;
      }
      shot_width = fb_width, shot_height = fb_height;
      if (shot) screenshot(fb_width, fb_height);
      VkExtent2D extent = swapchain.extent();
      if (in.resized || extent.width != fb_width || extent.height != fb_height) {
        swapchain.resize(fb_width, fb_height);
        dirty = true;
      }
      if (opt->frames > 0) dirty = true;

      if (dirty) {
        auto start = Clock::now();
        const double frame_scale = moving ? moving_scale : scale;
        settings.width = std::max(1u, uint32_t(std::lround(fb_width * frame_scale)));
        settings.height = std::max(1u, uint32_t(std::lround(fb_height * frame_scale)));
        settings.camera = orbit.camera();
        settings.lights = render::default_lights(settings.camera);
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
        const double render_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        // The keys over the still view (a moving frame is too coarse for text).
        if (help && !moving && !frame.display.empty()) {
          draw_overlay(frame, std::max(1, int(std::lround(2.0 * frame.width / fb_width))));
        }
        bool ok = swapchain.present(pixels(), frame.width, frame.height);
        if (!ok) {
          win->framebuffer_size(fb_width, fb_height);
          swapchain.resize(fb_width, fb_height);
          if (fb_width > 0 && fb_height > 0) swapchain.present(pixels(), frame.width, frame.height);
        }
        check_validation();
        const double wall_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
        // The cost of a pixel and of presenting, smoothed, size the next moving frame.
        const double pixel_ms = render_ms / (double(frame.width) * frame.height);
        ms_per_pixel = ms_per_pixel < 0 ? pixel_ms : 0.5 * (ms_per_pixel + pixel_ms);
        present_ms = frames == 0 ? wall_ms - render_ms : 0.5 * (present_ms + wall_ms - render_ms);
        if (opt->budget_ms > 0 && fb_width > 0 && fb_height > 0) {
          const double budget = std::max(opt->budget_ms - present_ms, 0.3 * opt->budget_ms);
          const double fit = std::sqrt(budget / ms_per_pixel / (double(fb_width) * fb_height));
          moving_scale = std::clamp(fit, std::min(scale, 64.0 / std::min(fb_width, fb_height)), scale);
        }
        std::ostringstream title;
        title << "svo view " << name << " | " << render::mode_name(settings.mode)
              << (settings.shadows ? " + shadows" : "") << " | " << (native ? "native " : "GPU ")
              << (frame.ms >= 0 ? format_ms(frame.ms) + " ms" : "n/a") << ", " << frame.width << "x" << frame.height
              << ", " << format_ms(1000.0 / std::max(wall_ms, 1e-3)) << " fps | " << kTitleKeys;
        win->set_title(title.str());
        refine = moving && frame.width < uint32_t(std::lround(fb_width * scale));
        dirty = false;
        shown = true;
        ++frames;
        if (opt->frames > 0 && frames >= opt->frames) break;
      } else if (in.exposed) {
        if (!swapchain.present(pixels(), frame.width, frame.height)) dirty = true;
        check_validation();
      }
    }
    if (!opt->screenshot.empty() && frames > 0) {
      render::write_colour(opt->screenshot, render_view(shot_width, shot_height, false));
    }
    check_validation();
    exit_code = 0;
  });
}

}  // namespace svo::tools
