#include "zoom_path.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/common.hpp>
#include <glm/trigonometric.hpp>
#include <sstream>

#include "svo/render/camera.h"

namespace svo::tools {

namespace fs = std::filesystem;

void add_path_options(CLI::App& cmd, PathOptions& o, uint32_t default_frames) {
  o.frames = default_frames;
  auto* path = cmd.add_option("--path", o.path,
                              "Built-in path: deep-zoom (from the far view to a surface point, the view narrowing "
                              "by the same factor every frame)")
                   ->default_val("deep-zoom")
                   ->group("Path");
  auto* file = cmd.add_option("--path-file", o.path_file,
                              "Camera path JSON: {\"frames\":N,\"keys\":[{\"eye\":[x,y,z],\"target\":[..],"
                              "\"up\":[..],\"fov\":deg}, ...]} or a bare list of keys (at least 2); keys are "
                              "interpolated with geometric distance to the target (see camera_path.h)")
                  ->group("Path");
  path->excludes(file);
  o.frames_option = cmd.add_option("--frames", o.frames, "Frames along the path (a path file's own count unless given)")
                        ->default_val(default_frames)
                        ->check(CLI::Range(2u, render::kMaxPathFrames))
                        ->group("Path");
  auto* zoom = cmd.add_option("--zoom", o.zoom, "deep-zoom: the first view's width over the last's, >= 1")
                   ->default_val(1000)
                   ->check(CLI::Range(1.0f, 1.0e6f))
                   ->group("Path");
  auto* target = cmd.add_option("--target", o.target,
                                "deep-zoom: the point X,Y,Z to zoom to (default: where the far view's centre ray "
                                "meets the finest level's surface)")
                     ->delimiter(',')
                     ->expected(3)
                     ->group("Path");
  auto* aim = cmd.add_option("--aim", o.aim,
                             "deep-zoom without --target: centre (the surface point on the far view's centre ray) "
                             "or silhouette (the outermost surface point right of the centre: the silhouette stays "
                             "in the middle of every frame)")
                  ->default_val("centre")
                  ->group("Path");
  file->excludes(zoom)->excludes(target)->excludes(aim);
  target->excludes(aim);
}

std::optional<render::CameraPath> check_path_options(const PathOptions& o) {
  if (!o.path_file.empty()) {
    render::CameraPath p = render::load_camera_path(o.path_file, o.frames);
    if (o.frames_option && o.frames_option->count() > 0) p.frames = o.frames;
    return p;
  }
  if (o.path != "deep-zoom") throw std::invalid_argument("unknown path '" + o.path + "' (paths: deep-zoom)");
  if (o.aim != "centre" && o.aim != "silhouette") {
    throw std::invalid_argument("unknown --aim '" + o.aim + "' (centre, silhouette)");
  }
  for (float v : o.target) {
    if (!std::isfinite(v)) throw std::invalid_argument("--target: values must be finite numbers");
  }
  return std::nullopt;
}

render::CameraPath resolve_path(const PathOptions& o, const std::optional<render::CameraPath>& loaded,
                                const octree::Octree& tree, float aspect, const std::string& svo_name) {
  if (loaded) return *loaded;
  const render::Camera far = render::view_preset(tree, "far", aspect);
  glm::vec3 target;
  if (o.target.size() == 3) {
    target = glm::vec3(o.target[0], o.target[1], o.target[2]);
  } else {
    const bool silhouette = o.aim == "silhouette";
    auto hit = silhouette ? render::silhouette_target(tree, far, aspect) : render::surface_target(tree, far, aspect);
    if (!hit) {
      throw std::runtime_error(svo_name + (silhouette ? ": no silhouette on the far view's horizontal centre line"
                                                      : ": no ray of the far view meets the surface") +
                               "; give --target X,Y,Z");
    }
    target = *hit;
  }
  return render::deep_zoom_path(far, target, o.zoom, o.frames);
}

double lod_level(const octree::Octree& tree, const render::RenderSettings& s, double t) {
  // trace_setup.cpp: k = pixel side at unit distance / sqrt(pi); tracer.glsl
  // svo_step: level = log2(size / (B sqrt(2) r)).
  const double tan_half = std::tan(glm::radians(0.5 * double(s.camera.fov_deg)));
  const double k = 2.0 * tan_half / double(s.height) / std::sqrt(M_PI);
  const double r = std::max(k * t, 1.0e-7 * double(tree.size));
  return std::log2(double(tree.size) / (double(tree.brick_size) * std::sqrt(2.0) * r));
}

LevelRange frame_levels(const octree::Octree& tree, const render::RenderSettings& s, const render::Frame& frame) {
  LevelRange range;
  const double last = double(tree.depth_count - 1);
  range.min = last;
  range.max = 0;
  for (size_t i = 0; i < frame.gbuffer.size(); ++i) {
    const auto& g = frame.gbuffer[i];
    if (!(g.coverage > 0) || !(g.depth > 0)) continue;
    const double level = std::clamp(lod_level(tree, s, g.depth), 0.0, last);
    range.min = std::min(range.min, level);
    range.max = std::max(range.max, level);
    range.any = true;
  }
  if (!range.any) range.min = range.max = 0;
  return range;
}

double mean_abs_difference(const render::Frame& a, const render::Frame& b) {
  if (a.colour.size() != b.colour.size() || a.colour.empty()) {
    throw std::invalid_argument("mean_abs_difference: frames of different sizes");
  }
  double sum = 0;
  for (size_t i = 0; i < a.colour.size(); ++i) {
    const glm::vec4 d = glm::abs(a.colour[i] - b.colour[i]);
    sum += double(d.r) + double(d.g) + double(d.b);
  }
  return sum / (3.0 * double(a.colour.size()));
}

glm::dvec3 centre_mean(const render::Frame& f) {
  const uint32_t x0 = f.width / 4, x1 = std::max(x0 + 1, f.width - f.width / 4);
  const uint32_t y0 = f.height / 4, y1 = std::max(y0 + 1, f.height - f.height / 4);
  glm::dvec3 sum(0);
  for (uint32_t y = y0; y < y1; ++y) {
    for (uint32_t x = x0; x < x1; ++x) sum += glm::dvec3(f.colour[size_t(y) * f.width + x]);
  }
  return sum / double((x1 - x0) * (y1 - y0));
}

render::Frame make_strip(const std::vector<std::vector<const render::Frame*>>& rows, uint32_t max_tile) {
  if (rows.empty() || rows[0].empty()) throw std::invalid_argument("make_strip: no frames");
  const uint32_t w = rows[0][0]->width, h = rows[0][0]->height;
  const uint32_t factor = std::max(1u, (w + max_tile - 1) / std::max(1u, max_tile));
  const uint32_t tw = std::max(1u, w / factor), th = std::max(1u, h / factor), gap = 2;
  size_t columns = 0;
  for (const auto& r : rows) columns = std::max(columns, r.size());
  render::Frame strip;
  strip.width = uint32_t(columns) * (tw + gap) - gap;
  strip.height = uint32_t(rows.size()) * (th + gap) - gap;
  strip.colour.assign(size_t(strip.width) * strip.height, glm::vec4(1, 1, 1, 1));
  for (size_t r = 0; r < rows.size(); ++r) {
    for (size_t c = 0; c < rows[r].size(); ++c) {
      const render::Frame& f = *rows[r][c];
      if (f.width != w || f.height != h) throw std::invalid_argument("make_strip: frames of different sizes");
      for (uint32_t y = 0; y < th; ++y) {
        for (uint32_t x = 0; x < tw; ++x) {
          glm::vec4 sum(0);
          for (uint32_t j = 0; j < factor; ++j) {
            for (uint32_t i = 0; i < factor; ++i) sum += f.colour[size_t(y * factor + j) * w + x * factor + i];
          }
          glm::vec4 v = sum / float(factor * factor);
          v.a = 1;
          strip.colour[size_t(r * (th + gap) + y) * strip.width + c * (tw + gap) + x] = v;
        }
      }
    }
  }
  return strip;
}

std::vector<uint32_t> strip_indices(uint32_t frames, uint32_t count) {
  std::vector<uint32_t> out;
  if (frames == 0 || count == 0) return out;
  count = std::min(count, frames);
  if (count == 1) return {0};
  for (uint32_t i = 0; i < count; ++i) {
    out.push_back(uint32_t(std::llround(double(i) * double(frames - 1) / double(count - 1))));
  }
  return out;
}

void make_output_directory(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw std::invalid_argument(dir + ": is not a directory");
    return;
  }
  fs::create_directories(dir, ec);
  if (ec) throw std::invalid_argument(dir + ": cannot create: " + ec.message());
}

}  // namespace svo::tools
