// The options svo render and svo reference share, so that a frame and its
// ground truth are asked for with the same words and see the same view:
// image size, camera (preset, text, file, depth of field), lights, shadows;
// and the JSON forms of cameras and lights in their reports.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"

namespace svo::tools {

struct ViewOptions {
  uint32_t width = 512;
  uint32_t height = 512;
  std::string preset = "far";  // --view
  std::string camera;          // --camera text
  std::string camera_file;     // --camera-file path
  std::vector<float> orbit;    // --orbit AZIMUTH,ELEVATION degrees (empty: the preset's 35,30)
  float distance = 0;          // --distance in object sizes (0: the preset's)
  std::vector<float> dof;      // --dof APERTURE[,FOCUS] (empty: pinhole)
  bool shadows = false;
  std::vector<std::string> lights;  // --light texts
};

// Image-based lighting and materials (DESIGN 10.2), the same words for
// svo render, svo reference and the others.
struct LightingOptions {
  std::string env;       // --env FILE (EXR or Radiance HDR)
  float env_rotate = 0;  // --env-rotate DEG
  float env_scale = 1;   // --env-scale S
  std::string material;  // --material FILE.json
  bool env_shadows = false;
  bool env_preconvolved = false;     // --env-preconvolved
  std::string env_sampling = "mis";  // --env-sampling mis|brdf
  // The area light (add_area_light_options; render and reference only).
  std::string area_light;         // --area-light white|IMAGE
  std::string area_at, area_aim;  // --area-light-at, --area-light-aim "X,Y,Z"
  float area_size = 0;            // --area-light-size S (0: half the domain)
  float area_radiance = 10;       // --area-light-radiance R
};

// The lobe-aware filter and upsampling (Tokuyoshi 2015, DESIGN 10.5):
// --filter, --filter-beta, --filter-sigma-n, --filter-sigma-z,
// --filter-kappa, --filter-radius, --upsample, --recompute, --filter-no-voxel-slopes.
struct FilterArgs {
  std::string weight = "none";  // --filter
  render::FilterOptions options;
  uint32_t upsample = 1;  // --upsample: 1, 2, 4
};

// Light-field luminaires (Lu et al. 2015, DESIGN 10.4): --luminaire FILE.lfl
// (repeatable) with --luminaire-at, --luminaire-aim, --luminaire-size,
// --luminaire-scale (one each per luminaire, in order, or one for all), and
// the sampling options.
struct LuminaireArgs {
  std::vector<std::string> files;
  std::vector<std::string> at, aim;  // "X,Y,Z"
  std::vector<float> size;
  std::vector<float> scale;  // the images' radiance times this
  std::string sampler = "restricted";
  std::string search = "secant";
  std::string visibility = "cells-on-u";
  std::string sequence = "halton";
  uint32_t spp = 200;
  uint32_t kmax = 0;
  uint32_t depth = 0;
};

// How linear radiance becomes an 8-bit PNG or JPEG (render::Film): the same
// words for svo render, reference, flythrough, demo and view. EXR outputs
// are never touched, so two .exr files compare as radiance whatever the film.
struct FilmOptions {
  float exposure = 0;            // --exposure EV
  std::string tonemap = "none";  // --tonemap none|filmic
};
// --exposure and --tonemap (group Film).
void add_film_options(CLI::App& cmd, FilmOptions& o);
// The options as a render::Film (for render::write_colour).
render::Film make_film(const FilmOptions& o);
// A one-line note for stderr when a film other than the default is asked
// for and `path` is a float output, which it does not change; "" otherwise.
std::string film_note(const FilmOptions& o, const std::string& path);

// --width and --height (group Output).
void add_size_options(CLI::App& cmd, ViewOptions& o);
// --view, --camera, --camera-file (mutually exclusive), --orbit, --distance
// (with a preset) and --dof (group Camera).
void add_camera_options(CLI::App& cmd, ViewOptions& o);
// --shadows and --light (group Shading).
void add_light_options(CLI::App& cmd, ViewOptions& o);

// --env, --env-rotate, --env-scale, --material, --env-shadows (group Lighting).
void add_lighting_options(CLI::App& cmd, LightingOptions& o);
// The filter's options (group Filter).
void add_filter_options(CLI::App& cmd, FilterArgs& o);
// Whether the frame is filtered or upsampled (it is then forward shaded).
bool uses_filter(const FilterArgs& o);
// Checks --filter's name and puts the options into `settings`.
// @throw std::invalid_argument naming the weights there are
void apply_filter(const FilterArgs& o, render::RenderSettings& settings);
// After the tracer: the forward pass with diffuse and specular apart (at
// 1/upsample of the size) and the lobe-aware filter.
void add_filter_passes(const FilterArgs& o, render::Renderer& renderer);

// The bandwidth-adaptive pass's options (group Adaptive): --adaptive-tau,
// --adaptive-directions, --adaptive-min-spp, --adaptive-max-spp,
// --adaptive-coarsest, --adaptive-sigma-z, --no-slope-limit.
void add_adaptive_options(CLI::App& cmd, render::AdaptiveOptions& o);

// The luminaire options (group Luminaires).
void add_luminaire_options(CLI::App& cmd, LuminaireArgs& o);
// Checks the names and placements (no file read).
// @throw std::invalid_argument naming the option
void check_luminaire_args(const LuminaireArgs& o);
// Loads the luminaires and puts them and the options into `settings`; a
// luminaire without a placement stands above and in front of the domain's
// centre at 1.5 domain sizes, aimed at the centre.
// @throw std::runtime_error for a file that does not load
void apply_luminaires(const LuminaireArgs& o, const octree::Octree* tree, render::RenderSettings& settings);
// The same about a domain of centre `centre` and size `size` (svo reference
// without an octree: the source's bounds).
void apply_luminaires(const LuminaireArgs& o, glm::vec3 centre, float size, render::RenderSettings& settings);

// The area light's options (group Light): --area-light, --area-light-at,
// --area-light-aim, --area-light-size, --area-light-radiance.
void add_area_light_options(CLI::App& cmd, LightingOptions& o);
// Loads the area light's texture and places it about a domain of centre
// `centre` and size `size`: by default half the domain across, 1.2 domain
// sizes above the centre, facing it. The ambient term is then 0; the
// commands drop the default lights unless --light is given.
// @throw std::runtime_error naming the file; std::invalid_argument naming the option
void apply_area_light(const LightingOptions& o, glm::vec3 centre, float size, render::RenderSettings& settings);

// Whether an environment, a material or an area light is asked for.
bool uses_lighting(const LightingOptions& o);
// Whether a frame of `tree` shades with the forward pass by default: with an
// environment or a material, or when the octree carries materials of its own.
bool shades_forward(const LightingOptions& o, const octree::Octree& tree);
// Loads the environment and the material into `shading` (a warning about
// clamped texels goes to stderr); with an environment the ambient term is 0.
// @throw std::runtime_error as one line naming the file.
void apply_lighting(const LightingOptions& o, render::RenderSettings& settings);

// Checks everything that needs neither an octree nor a device: the preset's
// name, the lights' count and syntax, the depth of field, and reads --camera
// or --camera-file. Returns that camera, or nullopt when a preset is asked for.
// @throw std::invalid_argument / std::runtime_error as one line naming the option.
std::optional<render::Camera> check_view_options(const ViewOptions& o);

// Whether the camera comes from a preset (neither --camera nor --camera-file).
bool uses_preset(const ViewOptions& o);

// How the camera was given, for reports: the preset's name, "camera" or "camera-file".
std::string view_name(const ViewOptions& o);

// The preset's direction and distance from --orbit and --distance.
render::PresetOptions preset_options(const ViewOptions& o);

// The camera: `given` (from check_view_options) or the preset of `tree`
// (required then), with --dof applied: one number is the lens radius as a
// fraction of the object's size (render::object_size of `tree`, else
// `object_size`), focused on the target; two are a lens radius and a focus
// distance in scene units.
// @throw std::invalid_argument for a camera --dof makes invalid; what view_preset throws.
render::Camera resolve_camera(const ViewOptions& o, std::optional<render::Camera> given, const octree::Octree* tree,
                              float object_size = 0);

// The lights of --light; without any, render::default_lights of `camera`
// (a key light from the camera's upper side and a dim fill). Point-light
// defaults are relative to `scene_centre`.
std::vector<render::Light> make_lights(const ViewOptions& o, glm::vec3 scene_centre, const render::Camera& camera);

// A float as the shortest decimal that reads back as the same float (0.1, not 0.10000000149011612).
double json_float(float v);
nlohmann::json vec_json(glm::vec3 v);
// {"eye", "target", "up", "fov", "aperture", "focus"}, as --save-camera writes.
nlohmann::json camera_json(const render::Camera& c);
// [{"type", "vector", "radiance", "size"}, ...]
nlohmann::json lights_json(const std::vector<render::Light>& lights);

}  // namespace svo::tools
