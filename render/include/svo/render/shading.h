// Lighting and materials of the shading passes (DESIGN section 10.2):
// environment maps, materials (analytic and measured), and the shading
// tables and parameters the shared GLSL reads (shaders/common/
// shade_params.glsl, environment.glsl, material.glsl, distribution.glsl).
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/shared_math.h"

namespace svo::render {

struct MerlBrdf;

// The host contract of the shading GLSL on the native host: the shading
// tables (distribution.glsl's svo_table) and the parameters (forward.glsl's
// `shade`). A kernel derives from it and includes the GLSL it needs in its
// body, as NativeOctreeReader's kernels do.
struct NativeShadingReader {
  svo::math::SvoShadeParams shade{};
  const float* tables = nullptr;
  float svo_table(uint32_t i) const { return tables[i]; }
};

// A latitude-longitude environment map, +Y up, linear RGB.
struct Environment {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, row 0 at +Y
  std::string source;      // the file, or a description
};

// Reads an EXR or Radiance HDR map through OpenImageIO. Small negative texels
// (above -1e-3 of the map's largest value, as DWAB compression leaves) are
// clamped to 0 with one line in `*warning`.
// @throw std::runtime_error "environment: PATH: why" (one line): not a
//        regular file, unreadable, fewer than 3 channels, smaller than 2x1 or
//        larger than 16384x8192, a NaN or Inf texel, a texel below the
//        clamping bound, or a map that is black everywhere.
Environment load_environment(const std::filesystem::path& path, std::string* warning = nullptr);

// A map of one radiance everywhere (the white furnace), width x height texels.
Environment constant_environment(glm::vec3 radiance, uint32_t width = 16, uint32_t height = 8);

// Checks a map made in memory as load_environment checks a file's.
// @throw std::runtime_error "environment: SOURCE: why"
void validate_environment(const Environment& env);

// The environment pre-convolved (shaders/common/environment.glsl,
// svo_env_preconvolved): latitude-longitude maps of the radiance convolved
// with normalised spherical Gaussians exp(lambda (cos - 1)) of sharpness
// lambda = 1, 2, 4, ... (a Phong lobe cos^e is close to the SG of sharpness
// e), each at about two texels per lobe deviation 1/sqrt(lambda) and at
// most the map's own size, up to the sharpness whose lobe spans two of the
// map's texels; and the irradiance over pi (the clamped cosine, normalised),
// what a Lambert surface reflects. Built once per map (about 0.4 s for
// a 1024x512 map on 2 cores): shading then looks a pixel's whole lobe up
// without samples (Bagher et al. 2013's pre-convolved shading; the smooth
// specular input of Tokuyoshi 2015's upsampling).
struct PreconvolvedEnvironment {
  struct Level {
    uint32_t width = 0, height = 0;
    float sharpness = 0;     // 0: the irradiance over pi
    std::vector<float> rgb;  // width * height * 3, row 0 at +Y, as Environment
  };
  std::vector<Level> levels;  // sharpness 1, 2, 4, ... doubling
  Level irradiance;
};
PreconvolvedEnvironment preconvolve_environment(const Environment& env);

// A textured planar area light (Bagher et al. 2013, section 4.3, Fig. 17;
// shaders/common/area_light.glsl): a parallelogram of centre `centre` and
// edge vectors `edge_u`, `edge_v`, emitting from its front side (towards
// edge_u x edge_v) the radiance of its texture, piecewise constant over the
// texels, row 0 along the +edge_v edge. Every shading sample draws one point
// of it from the texels' luminance; its spatial bandwidth (the texture's,
// zero-padded, render::area_light_bandwidth) enters the adaptive pass's
// bandwidth by transport from the light (Eq. 4).
struct AreaLight {
  glm::vec3 centre{0.0f, 2.0f, 0.0f};
  glm::vec3 edge_u{1.0f, 0.0f, 0.0f};
  glm::vec3 edge_v{0.0f, 0.0f, -1.0f};  // front: edge_u x edge_v = -Y, down
  uint32_t width = 1, height = 1;
  // width * height (each 1 to 1024) * 3 radiances, finite, >= 0, not all 0
  std::vector<float> rgb{1.0f, 1.0f, 1.0f};
  std::string source = "white";
  // The light of `size` across (its larger side; the texture's aspect) at
  // `at` facing `aim`, edge_v as close to +Y as the facing allows (to -Z
  // when it faces along Y).
  static AreaLight placed(glm::vec3 at, glm::vec3 aim, float size, uint32_t width, uint32_t height,
                          std::vector<float> rgb, std::string source);
};
// Checks the light's geometry and texels.
// @throw std::invalid_argument "area light: SOURCE: why" (one line)
void validate_area_light(const AreaLight& light);

enum class BrdfKind : uint32_t { Lambert = 0, Beckmann = 1, Ggx = 2, Phong = 3, Merl = 4 };
const char* brdf_name(BrdfKind kind);  // "lambert", ...

// A material (DESIGN 10.2's JSON): a diffuse part, tinted by the voxels'
// abar, plus one specular lobe.
struct Material {
  std::string name = "default";
  BrdfKind kind = BrdfKind::Beckmann;
  glm::vec3 diffuse{1.0f};               // "diffuse" (or "colour" for lambert): diffuse albedo, times abar
  glm::vec3 f0{0.04f};                   // "f0" [r, g, b], or from "ior" n: ((n - 1) / (n + 1))^2
  float roughness = 0.2f;                // "roughness": alpha of Beckmann (alpha^2 = 2 sigma^2) and GGX, in (0, 4]
  float exponent = 100.0f;               // "exponent": the Phong NDF's, in [0, 1e6]
  std::filesystem::path file;            // "file": a MERL binary, relative to the JSON's folder
  std::shared_ptr<const MerlBrdf> merl;  // loaded from `file`
};

// Parses a material from JSON text; `base` resolves a relative "file".
// Unknown keys, wrong types, values out of range and a missing "brdf" are
// one-line errors naming the key.
// @throw std::runtime_error "material: WHERE: key 'KEY': why"
Material parse_material(const std::string& json_text, const std::filesystem::path& base,
                        const std::string& where = "material");
// Reads FILE.json (at most 1 MiB, a regular file) and parses it.
Material load_material(const std::filesystem::path& path);
// The material as JSON (the keys parse_material reads), one line.
std::string material_json(const Material& material);

// The materials of a scene (Octree::materials, SurfaceSource::materials):
// JSON texts parsed as parse_material parses them, a relative "file" taken
// from the working directory.
// @throw std::runtime_error "material: material N of SOURCE: ..." (one line)
std::vector<std::shared_ptr<const Material>> parse_scene_materials(const std::vector<std::string>& texts,
                                                                   const std::string& source);

// The material of frames without --material: a white diffuse part and the
// Beckmann lobe of the tracer's built-in shading (f0 = `specular`, slope
// variance sigma_rho^2: alpha = sqrt(2 sigma_rho^2)).
Material builtin_material(float specular, float sigma_rho2);

// A material's BRDF as the shading kernels evaluate and sample it, for a flat
// point of colour `tint` (local frame, normal +z): for `svo material`, the
// MERL export and the tests.
class MaterialEvaluator {
 public:
  explicit MaterialEvaluator(const Material& material);
  ~MaterialEvaluator();
  MaterialEvaluator(const MaterialEvaluator&) = delete;
  MaterialEvaluator& operator=(const MaterialEvaluator&) = delete;
  // f(wi, wo): tint diffuse / pi plus the lobe; 0 where either is at or below the plane.
  glm::vec3 brdf(glm::vec3 tint, glm::vec3 wi, glm::vec3 wo) const;
  // The directional albedo int f cos over the hemisphere for view wo, by
  // `samples` samples of the material's own sampler.
  glm::vec3 albedo(glm::vec3 tint, glm::vec3 wo, uint32_t samples) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What a frame's shading passes need besides the G-buffer.
struct ShadingOptions {
  std::shared_ptr<const Environment> environment;  // null: none
  float env_rotate_deg = 0.0f;                     // about +Y
  float env_scale = 1.0f;                          // radiance multiplier, >= 0
  std::shared_ptr<const Material> material;        // null: the scene's, else Beckmann from the render settings
  // The scene's materials (an octree's or a source's), indexed by the
  // G-buffer's material indices; used when `material` is null. The forward
  // pass fills them from the octree; the reference from the source.
  std::vector<std::shared_ptr<const Material>> scene_materials;
  uint32_t spp = 16;  // samples per pixel of the forward pass, >= 1
  uint32_t seed = 1;
  bool env_shadows = false;  // environment samples see visibility cones through the octree
  // Non-null (with `environment`, pre-convolved from it): the environment's
  // light by one lookup per material lobe at the lobe's width instead of
  // samples (forward.glsl, svo_forward_preconvolved), seen through one cone
  // along the lobe when env_shadows is set. Lights are still evaluated.
  std::shared_ptr<const PreconvolvedEnvironment> preconvolved;
  // The environment's light sampled from the BRDF alone, as Bagher et al.
  // 2013 do (section 3.3), instead of one BRDF and one map sample combined
  // by multiple importance sampling; a sample then costs one direction
  // instead of two. Measured BRDFs against the pre-convolved map are
  // always sampled so (forward.glsl, svo_filtered_sharpness).
  bool brdf_sampling = false;
  // Non-null: a textured area light, sampled directly by every sample (one
  // point each), seen through a visibility cone where the lights cast
  // shadows. Not with `preconvolved`.
  std::shared_ptr<const AreaLight> area_light;
};

// The bandwidth-adaptive pass's parameters (render::AdaptivePass; Bagher
// et al. 2013, DESIGN 10.3).
struct AdaptiveOptions {
  uint32_t directions = 16;  // n_b: light directions per pixel for the bandwidth and the variance (Eq. 5, 9)
  float tau = 0.02f;         // the variance each pixel's estimate aims at, relative to (L + 0.01)^2, a relMSE (Eq. 9)
  uint32_t min_spp = 1;      // the fewest samples a shaded pixel takes
  uint32_t max_spp = 256;    // and the most
  uint32_t coarsest = 7;     // the coarsest level shaded: every 2^coarsest-th pixel (at most 7)
  float sigma_z = 1.0f;      // the upsampling depth weight's deviation, in parent spacings x the pixel's footprint
  bool slope_limit = true;   // the voxels' slope variance band-limits the reflected light (our addition)
  // Each pixel's sample count from the n_b directions' measured variance
  // (the estimator's own, importance sampling included) instead of Eq. 9's
  // bound, which assumes uniform sampling (the paper's section 4.4).
  bool measured_variance = false;
  // The bandwidth buffer's estimates made once per block of this many pixels
  // a side (1 or 2), at its most covered pixel, silhouettes still at level 0:
  // the level-1 mip is the block's minimum anyway (our shortcut, 4x cheaper).
  uint32_t bandwidth_block = 2;
  // Every pixel shaded at level 0 with ShadingOptions::spp samples: forward
  // shading through the adaptive pass (its test).
  bool finest = false;
};

// The directional weight of the lobe-aware filter (shaders/common/
// lobe_filter.glsl, SVO_FILTER_*; values are stable).
enum class FilterWeight : uint32_t { None = 0, Normal = 1, Lobe = 2, Mixture = 3, Asg = 4 };
const char* filter_weight_name(FilterWeight weight);  // "none", "normal", "lobe", "mixture", "asg"
// @throw std::invalid_argument naming the weights there are
FilterWeight parse_filter_weight(const std::string& name);

// The lobe-aware filter's parameters (render::LobeFilterPass; Tokuyoshi 2015).
struct FilterOptions {
  FilterWeight weight = FilterWeight::Lobe;
  float beta = 5.0f;       // the power of the lobe-aware weights (Eq. 11-13; svo bench lobe-filter: best 1-5 filtering)
  float sigma_n2 = 0.01f;  // the normal-aware weight's variance (Eq. 4)
  float sigma_z = 0.05f;   // the depth weight's deviation, relative to the pixel's depth (Eq. 3)
  float kappa = -1.0f;     // the smoothing kernel's sharpness (Eq. 9-10); < 0: none when filtering, 100 when upsampling
  uint32_t radius = 8;     // filtering: taps on each side, per axis (the screen kernel's sigma is radius / 2)
  float recompute = 0.25f;   // upsampling: shade again where the total weight falls under this (the paper's Fig. 16)
  bool voxel_slopes = true;  // widen the lobes with the voxels' slope covariance
};

// The shading tables (the floats svo_table reads) and the parameters.
struct ShadingTables {
  std::vector<float> floats;
  svo::math::SvoShadeParams params{};
};

// `default_material` is used when options.material is null and the scene
// has no materials; light_shadows sets SVO_SHADE_LIGHT_SHADOWS.
ShadingTables build_shading_tables(const ShadingOptions& options, const Material& default_material, bool light_shadows);
// SvoShadeParams::sampling.z of these options (SVO_SHADE_*).
uint32_t shade_flags(const ShadingOptions& options, bool light_shadows);

// The environment's texels as a piecewise-constant distribution of their
// luminance times sin(theta), appended to `tables`; returns its offset.
uint32_t append_environment_distribution(const Environment& env, std::vector<float>& tables);
// A piecewise-constant 2D distribution of f (nv rows of nu values, >= 0)
// appended to `tables` in distribution.glsl's layout; returns its offset.
uint32_t append_distribution(const std::vector<float>& f, uint32_t nu, uint32_t nv, std::vector<float>& tables);

}  // namespace svo::render
