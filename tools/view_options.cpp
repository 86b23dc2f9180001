#include "view_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "cli_hint.h"
#include "svo/render/camera.h"
#include "svo/render/passes.h"

namespace svo::tools {

namespace {

// "--dof A[,F]" as the user wrote it, for messages; empty without --dof.
std::string dof_text(const ViewOptions& o) {
  if (o.dof.empty()) return "";
  std::ostringstream s;
  s << "--dof " << o.dof[0];
  if (o.dof.size() == 2) s << "," << o.dof[1];
  return s.str();
}

}  // namespace

void add_size_options(CLI::App& cmd, ViewOptions& o) {
  cmd.add_option("--width", o.width, "Image width, pixels")
      ->default_val(512)
      ->check(CLI::Range(1u, 16384u))
      ->group("Output");
  cmd.add_option("--height", o.height, "Image height, pixels")
      ->default_val(512)
      ->check(CLI::Range(1u, 16384u))
      ->group("Output");
}

void add_camera_options(CLI::App& cmd, ViewOptions& o) {
  auto* view = cmd.add_option("--view", o.preset,
                              "Camera preset from the octree's surface: far (the whole object framed), mid (2x closer, "
                              "its middle), close (a point of the surface seen obliquely, magnified until the finest "
                              "voxel spans 1/64 of the image, 8 pixels at 512; with detail octaves 8 voxels away, "
                              "where the octaves add what no voxel holds)")
                   ->default_val("far")
                   ->group("Camera");
  auto* camera = cmd.add_option("--camera", o.camera,
                                "Camera ex,ey,ez,tx,ty,tz,ux,uy,uz,fov: eye, target, up, vertical fov in (0, 180) "
                                "degrees")
                     ->group("Camera");
  auto* camera_file = cmd.add_option("--camera-file", o.camera_file,
                                     "Camera from JSON: {\"eye\":[x,y,z],\"target\":[..],\"up\":[..],\"fov\":deg,"
                                     "\"aperture\":r,\"focus\":d} (aperture and focus optional)")
                          ->group("Camera");
  view->excludes(camera)->excludes(camera_file);
  camera->excludes(camera_file);
  auto* orbit = cmd.add_option("--orbit", o.orbit,
                               "The preset's direction AZIMUTH,ELEVATION in degrees: azimuth about the vertical (+y) "
                               "axis from +z, elevation above the horizontal in (-90, 90) (default 35,30)")
                    ->delimiter(',')
                    ->expected(2)
                    ->group("Camera");
  auto* distance = cmd.add_option("--distance", o.distance,
                                  "The preset's eye distance from its target in object sizes (the diagonal of the "
                                  "surface's bounds; default: far frames the object, mid is 2x closer)")
                       ->check(CLI::Range(1e-4f, 1e4f))
                       ->group("Camera");
  for (auto* option : {orbit, distance}) option->excludes(camera)->excludes(camera_file);
  cmd.add_option("--dof", o.dof,
                 "Depth of field, a thin lens: APERTURE alone is the lens radius as a fraction of the object's size, "
                 "focused on the target (0.01 is a gentle blur, 0.05 a strong one); APERTURE,FOCUS are a lens "
                 "radius >= 0 and a focus distance > 0 in scene units")
      ->delimiter(',')
      ->expected(1, 2)
      ->group("Camera");
}

void add_light_options(CLI::App& cmd, ViewOptions& o) {
  cmd.add_flag("--shadows", o.shadows, "Soft shadows from each light's extent")->group("Light");
  cmd.add_option("--light", o.lights,
                 "A light, repeatable up to " + std::to_string(render::kMaxLights) +
                     " (default: a key light from the camera's upper left, irradiance 3, and a fill light from "
                     "its right, 0.6):\n"
                     "dir:X,Y,Z[,IRRADIANCE[,ANGLE]] towards (X,Y,Z), irradiance default 3, angular radius "
                     "default 0.02 rad;\n"
                     "point:X,Y,Z[,INTENSITY[,RADIUS]] at (X,Y,Z), default intensity gives irradiance 3 at the "
                     "domain centre, radius default 1% of the distance to it")
      ->allow_extra_args(false)  // one light per --light, so that FILE may follow it
      ->group("Light");
}

void add_film_options(CLI::App& cmd, FilmOptions& o) {
  cmd.add_option("--exposure", o.exposure,
                 "Exposure of 8-bit outputs (.png, .jpg) in stops: radiance times 2^EV before the tone map "
                 "(.exr is written as rendered)")
      ->capture_default_str()
      ->check(CLI::Range(-20.0f, 20.0f))
      ->group("Film");
  cmd.add_option("--tonemap", o.tonemap,
                 "Tone map of 8-bit outputs: none (clamp to [0, 1]) or filmic (the ACES curve as fitted by "
                 "Narkowicz 2015: highlights roll off instead of clipping, 1.0 shows as 0.8); .exr is not tone mapped")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "filmic"}))
      ->group("Film");
}

render::Film make_film(const FilmOptions& o) {
  const std::optional<render::Tonemap> tonemap = render::parse_tonemap(o.tonemap);
  if (!tonemap) throw std::invalid_argument("unknown tone map '" + o.tonemap + "' (tone maps: none, filmic)");
  return render::Film{o.exposure, *tonemap};
}

std::string film_note(const FilmOptions& o, const std::string& path) {
  if (make_film(o) == render::Film{} || render::is_8bit(render::image_format(path))) return "";
  return "svo: note: " + path + " is written as rendered radiance; --exposure and --tonemap apply to .png and .jpg";
}

void add_filter_options(CLI::App& cmd, FilterArgs& o) {
  render::FilterOptions& f = o.options;
  cmd.add_option("--filter", o.weight,
                 "Filter the forward pass's diffuse and specular images apart, each with its lobes (Tokuyoshi 2015): "
                 "lobe (Eq. 12, one spherical Gaussian per pixel), mixture (Eq. 11, up to 3 per pixel: two "
                 "materials, a measured BRDF's fit), asg (Eq. 13, anisotropic, from the voxels' slope covariance), "
                 "normal (Eq. 4, the normal-aware baseline), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "normal", "lobe", "mixture", "asg"}))
      ->group("Filter");
  cmd.add_option("--filter-beta", f.beta, "The lobe-aware weights' power beta (Eq. 11-13)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0e4f))
      ->group("Filter");
  cmd.add_option("--filter-sigma-n", f.sigma_n2, "The normal-aware weight's variance sigma_n^2 (Eq. 4)")
      ->capture_default_str()
      ->check(CLI::Range(1.0e-6f, 1.0e3f))
      ->group("Filter");
  cmd.add_option("--filter-sigma-z", f.sigma_z, "The depth weight's deviation, relative to the pixel's depth (Eq. 3)")
      ->capture_default_str()
      ->check(CLI::Range(1.0e-4f, 1.0e3f))
      ->group("Filter");
  cmd.add_option("--filter-kappa", f.kappa,
                 "The smoothing kernel's sharpness kappa (Eq. 9-10; default: none when filtering, 100 when upsampling)")
      ->check(CLI::Range(0.0f, 1.0e6f))
      ->group("Filter");
  cmd.add_option("--filter-radius", f.radius,
                 "Filtering: taps on each side along each axis of the separable kernel (screen sigma: radius / 2)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 64u))
      ->group("Filter");
  cmd.add_option("--upsample", o.upsample,
                 "Shade at 1/2 or 1/4 of the size and upsample with the filter's weights (joint bilateral, the 2x2 "
                 "shaded texels about each pixel) instead of filtering")
      ->capture_default_str()
      ->check(CLI::IsMember({1u, 2u, 4u}))
      ->group("Filter");
  cmd.add_option("--recompute", f.recompute,
                 "Upsampling: shade a pixel again at full size where its total weight falls under this (paper Fig. 16; "
                 "0: never, a pixel without weight takes the bilinear average of the shaded texels)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f))
      ->group("Filter");
  cmd.add_flag(
         "--filter-no-voxel-slopes", [&f](int64_t) { f.voxel_slopes = false; },
         "The lobes from the materials alone, not widened by the voxels' slope covariance")
      ->group("Filter");
}

bool uses_filter(const FilterArgs& o) { return o.weight != "none" || o.upsample > 1; }

void apply_filter(const FilterArgs& o, render::RenderSettings& settings) {
  settings.filter = o.options;
  settings.filter.weight = render::parse_filter_weight(o.weight);
}

void add_filter_passes(const FilterArgs& o, render::Renderer& renderer) {
  renderer.add_pass(std::make_unique<render::ForwardPass>(render::ForwardOutput{true, o.upsample}));
  renderer.add_pass(std::make_unique<render::LobeFilterPass>(o.upsample));
}

void add_adaptive_options(CLI::App& cmd, render::AdaptiveOptions& o) {
  cmd.add_option(
         "--adaptive-tau", o.tau,
         "--shading adaptive: the variance each pixel aims at, relative to (L + 0.01)^2 (a relMSE) (Bagher Eq. 9 sets "
         "each pixel's sample count from it; smaller: more samples)")
      ->capture_default_str()
      ->check(CLI::Range(1.0e-6f, 1.0e6f))
      ->group("Adaptive");
  cmd.add_option("--adaptive-directions", o.directions,
                 "--shading adaptive: light directions per pixel for its bandwidth and variance (n_b, Eq. 5 and 9)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u))
      ->group("Adaptive");
  cmd.add_option("--adaptive-min-spp", o.min_spp, "--shading adaptive: the fewest samples a shaded pixel takes")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u))
      ->group("Adaptive");
  cmd.add_option("--adaptive-max-spp", o.max_spp, "--shading adaptive: the most samples a shaded pixel takes")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4096u))
      ->group("Adaptive");
  cmd.add_option("--adaptive-coarsest", o.coarsest,
                 "--shading adaptive: the coarsest level shaded, every 2^N-th pixel of each axis (0: every pixel)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 7u))
      ->group("Adaptive");
  cmd.add_option("--adaptive-sigma-z", o.sigma_z,
                 "--shading adaptive: the upsampling depth weight's deviation, in parent spacings times the pixel's "
                 "footprint")
      ->capture_default_str()
      ->check(CLI::Range(1.0e-3f, 1.0e3f))
      ->group("Adaptive");
  cmd.add_option_function<std::string>(
         "--adaptive-variance", [&o](const std::string& v) { o.measured_variance = v == "measured"; },
         "--shading adaptive: how each pixel's sample count is set: bound (Bagher Eq. 9, which assumes uniform "
         "sampling) or measured (the variance of the n_b directions' importance-sampled estimates)")
      ->check(CLI::IsMember({"bound", "measured"}))
      ->default_str("bound")
      ->group("Adaptive");
  cmd.add_option("--adaptive-bandwidth-block", o.bandwidth_block,
                 "--shading adaptive: one bandwidth estimate per pixel (1) or per 2x2 pixels (2: 4x cheaper; "
                 "silhouettes still at the finest level)")
      ->capture_default_str()
      ->check(CLI::IsMember({1u, 2u}))
      ->group("Adaptive");
  cmd.add_flag(
         "--no-slope-limit", [&o](int64_t) { o.slope_limit = false; },
         "--shading adaptive: the voxels' slope variance does not band-limit the reflected light (the paper's "
         "bandwidths alone)")
      ->group("Adaptive");
}

void add_luminaire_options(CLI::App& cmd, LuminaireArgs& o) {
  cmd.add_option("--luminaire", o.files,
                 "Light the scene with a light-field luminaire (.lfl: svo luminaire make|import), repeatable up to " +
                     std::to_string(render::LuminaireOptions::kMaxLuminaires) +
                     "; without --shading forward the luminaires and the faint ambient term are the only light")
      ->allow_extra_args(false)
      ->group("Luminaires");
  cmd.add_option("--luminaire-at", o.at,
                 "X,Y,Z: the centre of the luminaire's emitting plane, scene units (one per --luminaire in order, or "
                 "one for all; default: 1.5 domain sizes above and in front of the domain's centre)")
      ->allow_extra_args(false)
      ->group("Luminaires");
  cmd.add_option("--luminaire-aim", o.aim,
                 "X,Y,Z: the point the luminaire's axis looks at (default: the domain's centre)")
      ->allow_extra_args(false)
      ->group("Luminaires");
  cmd.add_option("--luminaire-size", o.size,
                 "The luminaire's emitting plane across, scene units (default: its own size in metres, as recorded "
                 "in the file)")
      ->allow_extra_args(false)
      ->check(positive_number())
      ->group("Luminaires");
  cmd.add_option("--luminaire-scale", o.scale,
                 "Multiply the luminaire's radiance by S (default 1). An imported ray file's radiance is in its own "
                 "flux unit per mm^2 sr (docs/luminaire.md): a real LED lights a scene far below the default "
                 "lights, so raise it here or with --exposure")
      ->allow_extra_args(false)
      ->check(positive_number())
      ->group("Luminaires");
  cmd.add_option(
         "--sampler", o.sampler,
         "How each point samples the luminaires: restricted (Lu et al.: the images' CDFs restricted to what "
         "each basis function lets reach the point, samples balanced by energy), uniform (the same regions, "
         "uniformly, the same samples per image), global (precomputed CDFs over whole images), box (restricted with "
         "the column marginal of the region's own rows, from the summed-area table: density exactly "
         "proportional to the image)")
      ->capture_default_str()
      ->check(CLI::IsMember({"restricted", "uniform", "global", "box"}))
      ->group("Luminaires");
  cmd.add_option("--luminaire-spp", o.spp, "Samples per pixel of each luminaire (K)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u))
      ->group("Luminaires");
  cmd.add_option("--kmax", o.kmax, "Cap on the samples of one image at one pixel (K_max; 0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1000000u))
      ->group("Luminaires");
  cmd.add_option("--luminaire-visibility", o.visibility,
                 "Shadows of the luminaires by cones through the octree: cells (one cone per basis cell towards its "
                 "reference light position on S, the paper's, shared by the images over it), cells-on-u (one cone "
                 "per basis cell along the line from the point to the cell on U: the same cost, right where S is "
                 "wide, as for a bare LED's ray file), samples (one per sample: slower, accurate), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "cells", "samples", "cells-on-u"}))
      ->group("Luminaires");
  cmd.add_option("--search", o.search,
                 "CDF inversion: secant (the paper's modified secant method), binary (halving), illinois (the "
                 "secant with the Illinois step, which keeps no end of the interval for long), or classic (halving "
                 "that, stopped by --search-depth, takes the interval's midpoint: Fig. 5's classical search)")
      ->capture_default_str()
      ->check(CLI::IsMember({"secant", "binary", "illinois", "classic"}))
      ->group("Luminaires");
  cmd.add_option("--search-depth", o.depth,
                 "Steps of the CDF inversion before it interpolates in the interval left (classic: takes its "
                 "midpoint; 0: until exact)")
      ->capture_default_str()
      ->check(CLI::Range(0u, 255u))
      ->group("Luminaires");
  cmd.add_option("--sequence", o.sequence,
                 "Sample sequence: halton, or random (independent uniform numbers from a hash)")
      ->capture_default_str()
      ->check(CLI::IsMember({"halton", "random"}))
      ->group("Luminaires");
}

namespace {

glm::vec3 parse_point(const std::string& text, const char* option) {
  glm::vec3 p;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%f,%f,%f%c", &p.x, &p.y, &p.z, &tail) != 3 || !std::isfinite(p.x) ||
      !std::isfinite(p.y) || !std::isfinite(p.z)) {
    throw std::invalid_argument(std::string(option) + " '" + text + "': expected X,Y,Z (three finite numbers)");
  }
  return p;
}

template <typename T>
const T* pick(const std::vector<T>& v, size_t i) {
  if (v.empty()) return nullptr;
  return v.size() == 1 ? &v[0] : &v[i];
}

}  // namespace

void check_luminaire_args(const LuminaireArgs& o) {
  const size_t n = o.files.size();
  if (n > render::LuminaireOptions::kMaxLuminaires) {
    throw std::invalid_argument("--luminaire: at most " + std::to_string(render::LuminaireOptions::kMaxLuminaires) +
                                " luminaires");
  }
  for (const auto& [count, name] :
       {std::pair{o.at.size(), "--luminaire-at"}, std::pair{o.aim.size(), "--luminaire-aim"},
        std::pair{o.size.size(), "--luminaire-size"}, std::pair{o.scale.size(), "--luminaire-scale"}}) {
    if (count == 0) continue;
    if (n == 0) throw std::invalid_argument(std::string(name) + " places a luminaire: give --luminaire FILE.lfl");
    if (count != 1 && count != n) {
      throw std::invalid_argument(std::string(name) + " is given " + std::to_string(count) + " times for " +
                                  std::to_string(n) + " luminaires: give it once, or once per --luminaire");
    }
  }
  for (const auto& t : o.at) parse_point(t, "--luminaire-at");
  for (const auto& t : o.aim) parse_point(t, "--luminaire-aim");
}

void apply_luminaires(const LuminaireArgs& o, const octree::Octree* tree, render::RenderSettings& settings) {
  const float size = tree ? tree->size : 1.0f;
  const glm::vec3 centre = tree ? tree->origin + glm::vec3(0.5f * size) : glm::vec3(0.0f);
  apply_luminaires(o, centre, size, settings);
}

void apply_luminaires(const LuminaireArgs& o, glm::vec3 centre, float size, render::RenderSettings& settings) {
  check_luminaire_args(o);
  render::LuminaireOptions& l = settings.luminaire;
  l.sampler = render::parse_luminaire_sampler(o.sampler);
  l.search = render::parse_luminaire_search(o.search);
  l.visibility = render::parse_luminaire_visibility(o.visibility);
  l.sequence = render::parse_luminaire_sequence(o.sequence);
  l.spp = o.spp;
  l.kmax = o.kmax;
  l.search_depth = o.depth;
  l.seed = settings.shading.seed;
  l.luminaires.clear();
  for (size_t i = 0; i < o.files.size(); ++i) {
    render::PlacedLuminaire p;
    render::LightField field = render::load_light_field(o.files[i]);
    if (const float* k = pick(o.scale, i); k && *k != 1.0f) {
      float brightest = 0.0f;
      for (const auto& image : field.images) {
        for (float v : image) brightest = std::max(brightest, v);
      }
      if (!std::isfinite(brightest * *k)) {
        std::ostringstream why;
        why << "--luminaire-scale " << *k << ": " << o.files[i] << "'s brightest texel (" << brightest
            << ") would exceed the float range";
        throw std::invalid_argument(why.str());
      }
      for (auto& image : field.images) {
        for (float& v : image) v *= *k;
      }
    }
    p.field = std::make_shared<const render::LightField>(std::move(field));
    const std::string* at = pick(o.at, i);
    const std::string* aim = pick(o.aim, i);
    const float* s = pick(o.size, i);
    p.placement.at = at ? parse_point(*at, "--luminaire-at") : centre + size * glm::vec3(0.0f, 1.2f, 0.9f);
    p.placement.aim = aim ? parse_point(*aim, "--luminaire-aim") : centre;
    p.placement.size = s ? *s : 0.0f;
    render::luminaire_frame(*p.field, p.placement);  // at == aim fails here
    l.luminaires.push_back(p);
  }
}

void add_lighting_options(CLI::App& cmd, LightingOptions& o) {
  cmd.add_option("--env", o.env,
                 "Environment map lighting the scene and seen behind it: latitude-longitude, +Y up, linear RGB "
                 "(EXR or Radiance .hdr; e.g. /usr/share/blender/datafiles/studiolights/world/*.exr)")
      ->group("Light");
  cmd.add_option("--env-rotate", o.env_rotate, "Turn the environment about +Y by DEG degrees")
      ->check(CLI::Range(-3600.0f, 3600.0f))
      ->group("Light");
  cmd.add_option("--env-scale", o.env_scale, "Multiply the environment's radiance by S")
      ->check(CLI::Range(0.0f, 1.0e6f))
      ->group("Light");
  cmd.add_option(
         "--material", o.material,
         "Material JSON: {\"brdf\": \"lambert|beckmann|ggx|phong|merl\", \"diffuse\": [r,g,b], "
         "\"roughness\": a, \"f0\": [r,g,b] or \"ior\": n, \"exponent\": e, \"file\": \"x.binary\"}; "
         "the diffuse part is tinted by the voxels' colour (default: white diffuse and a Beckmann lobe of the file's "
         "roughness, f0 0.04; docs/materials.md)")
      ->group("Light");
  cmd.add_flag("--env-shadows", o.env_shadows,
               "Environment samples see visibility cones through the octree (off: no visibility, as Bagher et al.)")
      ->group("Light");
  cmd.add_flag("--env-preconvolved", o.env_preconvolved,
               "Light by the environment without samples: each pixel's diffuse and specular lobes (the material's "
               "widened by the voxels' slopes) looked up once in the map pre-convolved with spherical Gaussians, "
               "through one cone along each lobe with --env-shadows. Smooth and fast, an approximation (the lobe as "
               "one spherical Gaussian, the diffuse without Smith masking). Measured BRDFs are still sampled, from "
               "the BRDF alone, each sample reading the map pre-convolved at the BRDF's sharpest lobe (Bagher et al. "
               "2013, Eq. 10: fewer samples, a slightly blurred highlight). Built from the map once (about 0.4 s for "
               "a 1024x512 map on 2 cores)")
      ->group("Light");
  cmd.add_option("--env-sampling", o.env_sampling,
                 "How forward and adaptive shading sample the environment: mis (one BRDF and one map sample per "
                 "sample, combined by multiple importance sampling) or brdf (the BRDF's sample alone, as Bagher et "
                 "al. 2013 do: half the cost per sample, more noise under a sharp map)")
      ->check(CLI::IsMember({"mis", "brdf"}))
      ->capture_default_str()
      ->group("Light");
}

void add_area_light_options(CLI::App& cmd, LightingOptions& o) {
  cmd.add_option("--area-light", o.area_light,
                 "A textured planar area light (Bagher et al. 2013, Fig. 17), sampled directly by every shading "
                 "sample: 'white', or an image (EXR, HDR, PNG, ...; at most 1024 texels a side) whose texels, linear "
                 "RGB times --area-light-radiance, are its radiance. It emits from its front, towards "
                 "--area-light-aim; the adaptive pass reads the texture's spatial bandwidth (zero-padded wavelets). "
                 "Casts shadows with --shadows")
      ->group("Light");
  cmd.add_option("--area-light-at", o.area_at,
                 "X,Y,Z: the area light's centre (default: 1.2 domain sizes above "
                 "the domain's centre)")
      ->group("Light");
  cmd.add_option("--area-light-aim", o.area_aim, "X,Y,Z: the point it faces (default: the domain's centre)")
      ->group("Light");
  cmd.add_option("--area-light-size", o.area_size,
                 "Its larger side in scene units, the other from the image's aspect (default: half the domain)")
      ->check(CLI::Range(0.0f, 1.0e6f))
      ->group("Light");
  cmd.add_option("--area-light-radiance", o.area_radiance, "The radiance of a white texel")
      ->check(CLI::Range(0.0f, 1.0e6f))
      ->capture_default_str()
      ->group("Light");
}

void apply_area_light(const LightingOptions& o, glm::vec3 centre, float size, render::RenderSettings& settings) {
  const bool placed = !o.area_at.empty() || !o.area_aim.empty() || o.area_size > 0;
  if (o.area_light.empty()) {
    if (placed) throw std::invalid_argument("--area-light-at, -aim and -size need --area-light");
    return;
  }
  if (settings.shading.preconvolved) throw std::invalid_argument("--area-light: not with --env-preconvolved");
  uint32_t w = 1, h = 1;
  std::vector<float> rgb{1.0f, 1.0f, 1.0f};
  if (o.area_light != "white") {
    render::Environment image;
    try {
      image = render::load_environment(o.area_light);
    } catch (const std::exception& e) {
      // load_environment's message, as the area light's.
      std::string why = e.what();
      const std::string prefix = "environment: ";
      if (why.rfind(prefix, 0) == 0) why = why.substr(prefix.size());
      throw std::runtime_error("--area-light: " + why);
    }
    w = image.width, h = image.height, rgb = std::move(image.rgb);
  }
  for (float& v : rgb) v *= o.area_radiance;
  const glm::vec3 at =
      o.area_at.empty() ? centre + glm::vec3(0.0f, 1.2f * size, 0.0f) : parse_point(o.area_at, "--area-light-at");
  const glm::vec3 aim = o.area_aim.empty() ? centre : parse_point(o.area_aim, "--area-light-aim");
  settings.shading.area_light = std::make_shared<const render::AreaLight>(render::AreaLight::placed(
      at, aim, o.area_size > 0 ? o.area_size : 0.5f * size, w, h, std::move(rgb), o.area_light));
  render::validate_area_light(*settings.shading.area_light);
  settings.ambient = glm::vec3(0);
}

bool uses_lighting(const LightingOptions& o) { return !o.env.empty() || !o.material.empty() || !o.area_light.empty(); }

bool shades_forward(const LightingOptions& o, const octree::Octree& tree) {
  return uses_lighting(o) || !tree.materials.empty();
}

void apply_lighting(const LightingOptions& o, render::RenderSettings& settings) {
  render::ShadingOptions& s = settings.shading;
  if (!o.env.empty()) {
    std::string warning;
    s.environment = std::make_shared<const render::Environment>(render::load_environment(o.env, &warning));
    if (!warning.empty()) std::fprintf(stderr, "svo: warning: %s\n", warning.c_str());
    settings.ambient = glm::vec3(0);
  }
  s.env_rotate_deg = o.env_rotate;
  s.env_scale = o.env_scale;
  s.env_shadows = o.env_shadows;
  s.brdf_sampling = o.env_sampling == "brdf";
  if (o.env_preconvolved && !s.environment) throw std::invalid_argument("--env-preconvolved needs --env");
  if (o.env_preconvolved)
    s.preconvolved =
        std::make_shared<const render::PreconvolvedEnvironment>(render::preconvolve_environment(*s.environment));
  if (!o.material.empty()) s.material = std::make_shared<const render::Material>(render::load_material(o.material));
}

bool uses_preset(const ViewOptions& o) { return o.camera.empty() && o.camera_file.empty(); }

std::string view_name(const ViewOptions& o) {
  if (uses_preset(o)) return o.preset;
  return o.camera.empty() ? "camera-file" : "camera";
}

std::optional<render::Camera> check_view_options(const ViewOptions& o) {
  const auto presets = render::view_preset_names();
  if (uses_preset(o) && std::find(presets.begin(), presets.end(), o.preset) == presets.end()) {
    throw std::invalid_argument("unknown view '" + o.preset + "' (views: far, mid, close)");
  }
  if (o.lights.size() > size_t(render::kMaxLights)) {
    throw std::invalid_argument("--light given " + std::to_string(o.lights.size()) + " times, at most " +
                                std::to_string(render::kMaxLights));
  }
  for (const auto& light : o.lights) render::parse_light(light, glm::vec3(0));  // syntax only
  if (!o.dof.empty()) {
    if (!(o.dof[0] >= 0)) throw std::invalid_argument(dof_text(o) + ": aperture must be >= 0");
    if (o.dof.size() == 1 && !(o.dof[0] <= 1)) {
      throw std::invalid_argument(dof_text(o) +
                                  ": one number is the aperture as a fraction of the object's size, "
                                  "at most 1 (give APERTURE,FOCUS for scene units)");
    }
    if (o.dof.size() == 2 && !(o.dof[1] > 0)) throw std::invalid_argument(dof_text(o) + ": focus must be > 0");
  }
  if (!o.orbit.empty() && !(std::isfinite(o.orbit[0]) && std::abs(o.orbit[1]) < 90.0f)) {
    std::ostringstream s;
    s << "--orbit " << o.orbit[0] << "," << o.orbit[1] << ": elevation must be within (-90, 90) degrees";
    throw std::invalid_argument(s.str());
  }
  std::optional<render::Camera> camera;
  if (!o.camera.empty()) camera = render::parse_camera(o.camera);
  if (!o.camera_file.empty()) camera = render::load_camera_json(o.camera_file);
  return camera;
}

render::PresetOptions preset_options(const ViewOptions& o) {
  render::PresetOptions p;
  if (o.orbit.size() == 2) p.azimuth_deg = o.orbit[0], p.elevation_deg = o.orbit[1];
  p.distance = o.distance;
  return p;
}

render::Camera resolve_camera(const ViewOptions& o, std::optional<render::Camera> given, const octree::Octree* tree,
                              float object_size) {
  if (!given) {
    if (!tree) throw std::invalid_argument("view preset '" + o.preset + "' needs an octree");
    given = render::view_preset(*tree, o.preset, float(o.width) / float(o.height), preset_options(o));
  }
  if (o.dof.size() == 2) {
    given->aperture = o.dof[0];
    given->focus = o.dof[1];
  } else if (o.dof.size() == 1) {
    if (tree) object_size = render::object_size(*tree);
    if (!(object_size > 0)) throw std::invalid_argument(dof_text(o) + ": the object's size is unknown here");
    given->aperture = o.dof[0] * object_size;
    given->focus = glm::length(given->target - given->eye);
  }
  if (!o.dof.empty()) render::validate_camera(*given, dof_text(o));
  return *given;
}

std::vector<render::Light> make_lights(const ViewOptions& o, glm::vec3 scene_centre, const render::Camera& camera) {
  if (o.lights.empty()) return render::default_lights(camera);
  std::vector<render::Light> lights;
  for (const auto& light : o.lights) lights.push_back(render::parse_light(light, scene_centre));
  return lights;
}

double json_float(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

nlohmann::json vec_json(glm::vec3 v) { return {json_float(v.x), json_float(v.y), json_float(v.z)}; }

nlohmann::json camera_json(const render::Camera& c) {
  return {{"eye", vec_json(c.eye)},       {"target", vec_json(c.target)},       {"up", vec_json(c.up)},
          {"fov", json_float(c.fov_deg)}, {"aperture", json_float(c.aperture)}, {"focus", json_float(c.focus)}};
}

nlohmann::json lights_json(const std::vector<render::Light>& lights) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& l : lights) {
    out.push_back({{"type", l.point ? "point" : "directional"},
                   {"vector", vec_json(l.vector)},
                   {"radiance", vec_json(l.radiance)},
                   {"size", json_float(l.size)}});
  }
  return out;
}

}  // namespace svo::tools
