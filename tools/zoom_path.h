// What svo flythrough and svo bench zoom share (issue 6): the options that
// choose a camera path (the deep zoom or a path file), the level of detail
// the tracer reaches, per-frame image figures, and the strip of frames.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/camera_path.h"
#include "svo/render/renderer.h"

namespace svo::tools {

struct PathOptions {
  std::string path = "deep-zoom";  // --path
  std::string path_file;           // --path-file
  uint32_t frames = 60;            // --frames
  float zoom = 1000;               // --zoom
  std::vector<float> target;       // --target X,Y,Z (empty: found on the surface)
  std::string aim = "centre";      // --aim centre|silhouette
  CLI::Option* frames_option = nullptr;
};

// --path, --path-file, --frames, --zoom, --target (group Path).
void add_path_options(CLI::App& cmd, PathOptions& o, uint32_t default_frames);

// Checks the options and reads --path-file: everything that needs no octree.
// Returns the file's path (with --frames applied when given), or nullopt for deep-zoom.
// @throw std::invalid_argument / std::runtime_error as one line naming the option or the file.
std::optional<render::CameraPath> check_path_options(const PathOptions& o);

// The path to render: `loaded` when a path file was given, else the deep
// zoom from the far preset of `tree` to --target or to the surface point on
// the far view's centre ray (render::surface_target).
// @throw std::runtime_error "<svo_name>: ..." when no target is found.
render::CameraPath resolve_path(const PathOptions& o, const std::optional<render::CameraPath>& loaded,
                                const octree::Octree& tree, float aspect, const std::string& svo_name);

// The octree level the tracer samples at distance t along a pixel's cone
// (the formula of svo_step in shaders/common/tracer.glsl, pinhole cone
// radius r = k t with k from trace_setup.cpp), not clamped to the stored
// levels: above depth_count - 1 the cone is finer than the finest voxel.
double lod_level(const octree::Octree& tree, const render::RenderSettings& settings, double t);

struct LevelRange {
  double min = 0, max = 0;  // as the tracer clamps them to [0, depth_count - 1]
  bool any = false;         // some pixel covered
};
// Levels at the G-buffer depth of the covered pixels (the frame must carry a G-buffer).
LevelRange frame_levels(const octree::Octree& tree, const render::RenderSettings& settings,
                        const render::Frame& frame);

// Mean |a - b| over all pixels and the R, G, B channels (same sizes).
double mean_abs_difference(const render::Frame& a, const render::Frame& b);

// Mean linear RGB over the centre window: the middle half of the width and
// of the height (a quarter of the area).
glm::dvec3 centre_mean(const render::Frame& f);

// Frames side by side in rows (rows[r][c]), each shrunk by the integer box
// filter that brings its width to at most `max_tile` pixels, with a 2-pixel
// gap; linear RGB, alpha 1. All frames must have one size.
render::Frame make_strip(const std::vector<std::vector<const render::Frame*>>& rows, uint32_t max_tile);

// `count` frame indices spread evenly over [0, frames - 1], first and last included.
std::vector<uint32_t> strip_indices(uint32_t frames, uint32_t count);

// Creates `dir` (and its parents) unless it exists.
// @throw std::invalid_argument "<dir>: is not a directory" / "<dir>: cannot create: <why>".
void make_output_directory(const std::string& dir);

}  // namespace svo::tools
