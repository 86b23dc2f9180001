// svo flythrough: a camera path through a .svo file (issue 6), by default
// the deep zoom from the whole-object view to a surface point; numbered PNG
// frames, a CSV of per-frame cost and levels, the path used, a strip of
// frames, and a video when ffmpeg is installed. Every argument, the path
// file and the outputs are checked before the octree is loaded.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glm/geometric.hpp>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.h"
#include "progress.h"
#include "svo/octree/files.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera_path.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"
#include "view_options.h"
#include "zoom_path.h"

namespace svo::tools {

namespace {

namespace fs = std::filesystem;

struct FlythroughArgs {
  std::string input;
  std::string out;
  PathOptions path;
  ViewOptions view;
  FilmOptions film;
  LightingOptions lighting;
  uint32_t spp = 16;
  std::string mode = "prefiltered";
  uint32_t repeats = 1;
  uint32_t strip = 8;
  std::string video;
  uint32_t fps = 30;
  std::string device;
  bool validate = false;
  bool json = false;
};

// One CSV row.
struct FrameRow {
  uint32_t frame = 0;
  double distance = 0, view_width = 0, zoom = 1;
  double ms = 0, us_per_pixel = 0, us_per_covered_pixel = -1;
  uint64_t covered = 0;
  double steps_per_pixel = 0;
  LevelRange levels;
  double level_target = 0;
};

std::string frame_name(uint32_t f) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04u.png", f);
  return name;
}

// Single quotes for sh.
std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// ffmpeg's container for a video name: the temporary ffmpeg writes has no
// extension to go by.
std::string container_of(const std::string& video) {
  std::string ext = fs::path(video).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".mp4" || ext == ".m4v") return "mp4";
  if (ext == ".mov") return "mov";
  if (ext == ".mkv") return "matroska";
  throw std::invalid_argument("--video " + video + ": unknown video extension '" + ext + "' (use .mp4, .mov or .mkv)");
}

// A frame written by a flythrough: frame_ and digits, .png.
bool is_frame_name(const std::string& name) {
  if (name.size() < 11 || name.rfind("frame_", 0) != 0 || !name.ends_with(".png")) return false;
  return std::all_of(name.begin() + 6, name.end() - 4, [](unsigned char c) { return std::isdigit(c); });
}

// The names of a run's set in DIR: frames, the strip, the CSV and the path.
bool ours(const std::string& name) {
  return is_frame_name(name) || name == "strip.png" || name == "frames.csv" || name == "path.json";
}

bool have_ffmpeg() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

}  // namespace

void add_flythrough_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "flythrough",
      "Render a camera path through a .svo file: the deep zoom from the whole-object view to a surface point "
      "(--path deep-zoom, default) or a JSON path of keyframes (--path-file). Writes DIR/frame_NNNN.png, "
      "DIR/frames.csv (per frame: distance, view width, GPU ms, us per pixel and per covered pixel, levels), "
      "DIR/path.json (the path used, for --path-file) and DIR/strip.png. The run's files replace the earlier "
      "run's together at the end (a killed or failed run leaves them as they were; one killed while it moved "
      "them is completed by the next run into DIR)");
  auto a = std::make_shared<FlythroughArgs>();
  cmd->add_option("FILE", a->input, "The .svo file to fly through")->required()->group("Input");
  cmd->add_option("-o,--out", a->out, "Output directory (created when missing)")->required()->group("Output");
  add_size_options(*cmd, a->view);
  cmd->add_option("--strip", a->strip, "Frames in DIR/strip.png, spread over the path (0: no strip)")
      ->default_val(8)
      ->check(CLI::Range(0u, 64u))
      ->group("Output");
  cmd->add_option("--video", a->video, "Also encode the frames to this video with ffmpeg (H.264 in .mp4)")
      ->group("Output");
  cmd->add_option("--fps", a->fps, "Frame rate of --video")
      ->default_val(30)
      ->check(CLI::Range(1u, 240u))
      ->group("Output");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: frames, ms, us per covered pixel (min, max, ratio), levels, file "
                "size, ...")
      ->group("Output");
  add_path_options(*cmd, a->path, 60);
  cmd->add_option("--mode", a->mode, "prefiltered (ours), nearest, alpha or mip (see svo render)")
      ->default_val("prefiltered")
      ->group("Shading");
  add_light_options(*cmd, a->view);
  add_film_options(*cmd, a->film);
  add_lighting_options(*cmd, a->lighting);
  cmd->add_option("--spp", a->spp, "Samples per pixel of the forward-shading pass (with --env or --material)")
      ->check(CLI::Range(1u, 4096u))
      ->group("Lighting");
  cmd->add_option("--repeats", a->repeats, "Renders per frame; the median GPU time is reported")
      ->default_val(1)
      ->check(CLI::Range(1u, 100u))
      ->group("Timing");
  cmd->add_option("--device", a->device, kDeviceHelp)->group("Device");
  cmd->add_flag(
         "--validate", a->validate,
         "Vulkan: enable the Khronos validation layer; any message fails the command (without --device: the best "
         "Vulkan device, lavapipe on a machine without a GPU)")
      ->group("Device");

  cmd->callback([a, &exit_code] {
    // --- Everything that can be checked without the octree or a device.
    std::optional<render::Mode> mode = render::parse_mode(a->mode);
    if (!mode || *mode == render::Mode::RayMarch) {
      throw std::invalid_argument("unknown mode '" + a->mode +
                                  "' for flythrough (modes: prefiltered, nearest, alpha, mip)");
    }
    check_view_options(a->view);
    const render::Film film = make_film(a->film);
    std::optional<render::CameraPath> loaded = check_path_options(a->path);
    std::string video_format;
    if (!a->video.empty()) {
      video_format = container_of(a->video);
      if (!have_ffmpeg()) {
        throw std::runtime_error("--video " + a->video +
                                 ": ffmpeg is not installed (not on PATH); encode DIR/frame_%04d.png later");
      }
      render::check_writable_output(a->video);
    }
    make_output_directory(a->out);
    const fs::path dir(a->out);
    for (const char* name : {"frames.csv", "path.json", "strip.png"}) files::resolve_output((dir / name).string());
    // The run's files go to a staging directory inside DIR and replace the
    // earlier run's set together at the end: a run that is killed or fails
    // leaves the earlier frames, CSV and path as they were (its staging
    // directory is removed by the next run). A run killed while it moved its
    // set into DIR left the set's manifest in its staging directory: this
    // run completes that publish first.
    files::finish_interrupted_sets(dir, ".flythrough-tmp-", ours);
    files::StagingDirectory staging(dir, ".flythrough-tmp-");
    const fs::path& stage = staging.path();

    // --- The octree, the path, the device.
    octree::Octree tree = octree::load_svo(a->input);
    const auto file_bytes = fs::file_size(a->input);
    const float aspect = float(a->view.width) / float(a->view.height);
    const render::CameraPath path = resolve_path(a->path, loaded, tree, aspect, a->input);
    const std::vector<render::Camera> cameras = render::path_cameras(path);
    render::save_camera_path((stage / "path.json").string(), path);

    render::RenderSettings settings;
    settings.width = a->view.width;
    settings.height = a->view.height;
    settings.mode = *mode;
    settings.shadows = a->view.shadows;
    settings.lights = make_lights(a->view, tree.origin + glm::vec3(0.5f * tree.size), cameras.front());
    settings.gbuffer = true;  // the depths give the levels used
    apply_lighting(a->lighting, settings);
    settings.shading.spp = a->spp;
    std::unique_ptr<render::Renderer> made = render::make_renderer(tree, {a->device, a->validate});
    render::Renderer& renderer = *made;
    if (uses_lighting(a->lighting) || (shades_forward(a->lighting, tree) && *mode == render::Mode::Prefiltered)) {
      if (*mode != render::Mode::Prefiltered)
        throw std::invalid_argument("--env and --material need --mode prefiltered");
      renderer.add_pass(render::make_pass("forward"));
    }

    // --- Frames.
    ProgressBar bar("flythrough");
    std::vector<FrameRow> rows;
    std::vector<render::Frame> strip_frames;
    const std::vector<uint32_t> strip_at = strip_indices(uint32_t(cameras.size()), a->strip);
    const double first_width = render::view_width(cameras.front());
    for (uint32_t f = 0; f < cameras.size(); ++f) {
      bar.update("rendering", f, cameras.size(), "frames");
      settings.camera = cameras[f];
      std::vector<double> times;
      render::Frame frame;
      for (uint32_t r = 0; r < a->repeats; ++r) {
        frame = renderer.render(settings);
        times.push_back(render::frame_ms(frame));
      }
      std::sort(times.begin(), times.end());
      render::write_colour((stage / frame_name(f)).string(), frame, film);
      FrameRow row;
      row.frame = f;
      row.distance = glm::length(glm::dvec3(cameras[f].target) - glm::dvec3(cameras[f].eye));
      row.view_width = render::view_width(cameras[f]);
      row.zoom = first_width / row.view_width;
      row.ms = times[times.size() / 2];
      row.us_per_pixel = row.ms * 1000.0 / double(frame.width * frame.height);
      row.covered = frame.covered_pixels;
      if (row.covered > 0) row.us_per_covered_pixel = row.ms * 1000.0 / double(row.covered);
      row.steps_per_pixel = frame.steps_per_pixel;
      row.levels = frame_levels(tree, settings, frame);
      row.level_target = lod_level(tree, settings, row.distance);
      rows.push_back(row);
      if (std::find(strip_at.begin(), strip_at.end(), f) != strip_at.end()) {
        frame.gbuffer.clear();
        frame.steps.clear();
        strip_frames.push_back(std::move(frame));
      }
    }
    bar.update("rendering", cameras.size(), cameras.size(), "frames");
    bar.finish();

    // --- CSV, strip, video, summary.
    std::ostringstream csv;
    csv << std::setprecision(9);
    csv << "frame,distance,view_width,zoom,ms,us_per_pixel,us_per_covered_pixel,covered_pixels,steps_per_pixel,"
           "level_min,level_max,level_target\n";
    for (const auto& r : rows) {
      csv << r.frame << "," << r.distance << "," << r.view_width << "," << r.zoom << "," << r.ms << ","
          << r.us_per_pixel << ",";
      if (r.covered > 0) csv << r.us_per_covered_pixel;
      csv << "," << r.covered << "," << r.steps_per_pixel << ",";
      if (r.levels.any)
        csv << r.levels.min << "," << r.levels.max;
      else
        csv << ",";
      csv << "," << r.level_target << "\n";
    }
    files::write_file((stage / "frames.csv").string(), csv.str());
    if (!strip_frames.empty()) {
      std::vector<const render::Frame*> row;
      for (const auto& f : strip_frames) row.push_back(&f);
      render::write_colour((stage / "strip.png").string(), make_strip({row}, 256), film);
    }
    if (!a->video.empty()) {
      // ffmpeg writes into our exclusively created temporary (never -y onto
      // a name someone else could have planted), which then replaces the
      // video. It opens it through a descriptor we hold, /dev/fd/N (a
      // duplicate without close-on-exec, inherited through the shell): the
      // same file even if its name were replaced meanwhile, where opening
      // the temporary by name left that window open.
      files::OutputFile video(a->video);
      const int inherited = ::dup(video.fd());
      if (inherited < 0) throw std::runtime_error("--video " + a->video + ": dup: " + std::strerror(errno));
      const std::string command = "ffmpeg -y -loglevel error -framerate " + std::to_string(a->fps) + " -i " +
                                  quoted((stage / "frame_%04d.png").string()) + " -frames:v " +
                                  std::to_string(cameras.size()) + " -c:v libx264 -pix_fmt yuv420p -f " + video_format +
                                  " /dev/fd/" + std::to_string(inherited);
      const int status = std::system(command.c_str());
      ::close(inherited);
      if (status != 0) throw std::runtime_error("--video " + a->video + ": ffmpeg failed: " + command);
      video.commit();
    }
    files::publish_set(stage, dir, ours);

    double lo = 0, hi = 0, total_ms = 0;
    bool any = false;
    for (const auto& r : rows) {
      total_ms += r.ms;
      if (r.covered == 0) continue;
      lo = any ? std::min(lo, r.us_per_covered_pixel) : r.us_per_covered_pixel;
      hi = any ? std::max(hi, r.us_per_covered_pixel) : r.us_per_covered_pixel;
      any = true;
    }
    const std::vector<std::string> messages = renderer.validation_messages();
    if (a->json) {
      nlohmann::json out{
          {"file", a->input},
          {"file_bytes", file_bytes},
          {"out", a->out},
          {"frames", rows.size()},
          {"width", settings.width},
          {"height", settings.height},
          {"mode", render::mode_name(*mode)},
          {"path", a->path.path_file.empty() ? a->path.path : "file"},
          {"zoom", first_width / render::view_width(cameras.back())},
          {"total_ms", total_ms},
          {"us_per_covered_pixel_min", any ? nlohmann::json(lo) : nlohmann::json(nullptr)},
          {"us_per_covered_pixel_max", any ? nlohmann::json(hi) : nlohmann::json(nullptr)},
          {"us_per_covered_pixel_ratio", any && lo > 0 ? nlohmann::json(hi / lo) : nlohmann::json(nullptr)},
          {"finest_level", tree.depth_count - 1},
          {"level_target_last", rows.back().level_target},
          {"device", renderer.device_name()},
          {"device_type", renderer.device_type()},
          {"video", a->video.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->video)},
          {"validation_messages", messages}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << std::fixed << std::setprecision(1) << a->input << " -> " << a->out << ": " << rows.size()
                << " frames " << settings.width << "x" << settings.height << " " << render::mode_name(*mode)
                << ", zoom " << first_width / render::view_width(cameras.back()) << ", " << total_ms << " ms "
                << (renderer.host() == render::Host::Native ? "native" : "GPU") << " in all";
      if (any) {
        std::cout << std::setprecision(3) << ", us per covered pixel " << lo << " to " << hi << " (ratio "
                  << std::setprecision(2) << (lo > 0 ? hi / lo : 0.0) << ")";
      }
      std::cout << ", " << renderer.device_name() << "\n";
    }
    if (!messages.empty()) {
      for (const auto& m : messages) std::cerr << "validation: " << m << "\n";
      throw std::runtime_error("flythrough: " + std::to_string(messages.size()) +
                               " Vulkan validation message(s) (above); the frames were written");
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
