#include "svo/reference/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/shared_math.h"
#include "svo/render/camera.h"
#include "svo/render/shading.h"

namespace svo::math {

// The environment and material of shaders/common, as the forward pass reads
// them, for the reference's own sampling.
struct ReferenceLighting : render::NativeShadingReader {
#include "common/environment.glsl"
#include "common/material.glsl"
#include "common/sequence.glsl"
};

}  // namespace svo::math

namespace svo::reference {

namespace {

constexpr double kPi = 3.14159265358979323846;

// SplitMix64 (Steele et al. 2014): a small generator seeded per pixel, so
// that the image does not depend on how rows are spread over threads.
struct Rng {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  uint32_t below(uint32_t n) { return uint32_t(uniform() * n); }
};

// Cells of the stratified grid: a x b = n, a the largest divisor of n not above sqrt(n).
glm::uvec2 grid_shape(uint32_t n) {
  uint32_t a = uint32_t(std::sqrt(double(n)));
  while (a > 1 && n % a != 0) --a;
  return {a, n / a};
}

// The concentric mapping of the unit square onto the unit disk (Shirley &
// Chiu 1997): area-preserving, so strata of the square stay strata of equal
// area on the disk.
glm::dvec2 concentric_disk(glm::dvec2 u) {
  glm::dvec2 o = 2.0 * u - 1.0;
  if (o.x == 0 && o.y == 0) return {0, 0};
  double r, theta;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x, theta = kPi / 4 * (o.y / o.x);
  } else {
    r = o.y, theta = kPi / 2 - kPi / 4 * (o.x / o.y);
  }
  return r * glm::dvec2(std::cos(theta), std::sin(theta));
}

// n jittered stratified points of the unit disk, in random order when `shuffle`.
void stratified_disk(uint32_t n, glm::uvec2 shape, Rng& rng, bool shuffle, std::vector<glm::dvec2>& out) {
  out.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    glm::dvec2 cell(i % shape.x, i / shape.x);
    glm::dvec2 u((cell.x + rng.uniform()) / shape.x, (cell.y + rng.uniform()) / shape.y);
    out[i] = concentric_disk(u);
  }
  if (shuffle) {
    for (uint32_t i = n; i > 1; --i) std::swap(out[i - 1], out[rng.below(i)]);
  }
}

// Two unit vectors perpendicular to unit `d` and to each other.
void perpendicular_frame(glm::dvec3 d, glm::dvec3& a, glm::dvec3& b) {
  glm::dvec3 helper = std::abs(d.x) < 0.5 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  a = glm::normalize(glm::cross(d, helper));
  b = glm::cross(d, a);
}

// A direction within the cone of half-angle `angle` around unit `axis`,
// uniform in solid angle for a uniform point `disk` of the unit disk.
glm::dvec3 cone_direction(glm::dvec3 axis, double angle, glm::dvec2 disk) {
  const double r2 = glm::dot(disk, disk);
  if (!(angle > 0) || r2 == 0) return axis;
  const double one_minus_cos =
      r2 * 2 * std::pow(std::sin(0.5 * angle), 2);  // 1 - cos(alpha), uniform in [0, 1 - cos(angle)]
  const double cos_a = 1 - one_minus_cos, sin_a = std::sqrt(std::max(0.0, one_minus_cos * (2 - one_minus_cos)));
  glm::dvec3 a, b;
  perpendicular_frame(axis, a, b);
  const glm::dvec2 u = disk / std::sqrt(r2);
  return glm::normalize(cos_a * axis + sin_a * (u.x * a + u.y * b));
}

struct Lamp {
  bool point;
  glm::dvec3 vector;  // unit direction towards a directional light; position of a point light
  glm::dvec3 radiance;
  double size;
};

// Everything a pixel needs, fixed for the frame.
struct Setup {
  glm::dvec3 eye, u, v, w;  // camera: right, up, forward (unit)
  double tan_half = 0, aspect = 1;
  double slope = 0;  // footprint radius per unit distance: pixel side / sqrt(pi)
  double aperture = 0, focus = 0;
  std::vector<Lamp> lamps;
  glm::dvec3 ambient, background;
  float specular = 0;
  bool shadows = false;
  glm::vec2 total_variance{0};  // svo_total_slope_variance(0, sigma_rho^2)
};

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Setup make_setup(const Geometry& geometry, const ReferenceSettings& settings) {
  const render::RenderSettings& s = settings.render;
  if (s.width == 0 || s.height == 0) throw std::invalid_argument("reference: image size must be at least 1x1");
  if (settings.spp == 0) throw std::invalid_argument("reference: spp must be at least 1");
  if (s.lights.size() > size_t(render::kMaxLights)) {
    throw std::invalid_argument("reference: at most " + std::to_string(render::kMaxLights) + " lights, got " +
                                std::to_string(s.lights.size()));
  }
  render::validate_camera(s.camera, "reference: camera");
  Setup c;
  const render::Camera& cam = s.camera;
  c.eye = glm::dvec3(cam.eye);
  c.w = glm::normalize(glm::dvec3(cam.target) - c.eye);
  c.u = glm::normalize(glm::cross(c.w, glm::dvec3(cam.up)));
  c.v = glm::cross(c.u, c.w);
  c.tan_half = std::tan(glm::radians(double(cam.fov_deg)) * 0.5);
  c.aspect = double(s.width) / double(s.height);
  c.slope = 2.0 * c.tan_half / double(s.height) / std::sqrt(kPi);
  c.aperture = cam.aperture;
  c.focus = cam.focus;
  for (size_t i = 0; i < s.lights.size(); ++i) {
    const render::Light& l = s.lights[i];
    const std::string where = "reference: light " + std::to_string(i + 1);
    if (!finite(l.vector) || !finite(l.radiance) || !std::isfinite(l.size) || l.size < 0) {
      throw std::invalid_argument(where + " is not finite or has a negative size");
    }
    glm::dvec3 vec(l.vector);
    if (!l.point) {
      if (!(glm::length(vec) > 0)) throw std::invalid_argument(where + " has no direction");
      vec = glm::normalize(vec);
    }
    c.lamps.push_back({l.point, vec, glm::dvec3(l.radiance), double(l.size)});
  }
  c.ambient = glm::dvec3(s.ambient);
  c.background = glm::dvec3(s.background);
  c.specular = s.specular;
  c.shadows = s.shadows;
  c.total_variance = svo::math::svo_total_slope_variance(glm::vec2(0), glm::vec2(geometry.sigma_rho2()));
  return c;
}

// Whether a shadow ray from `hit` towards a point of the light's extent
// (`disk`: a point of the unit disk) reaches the light.
bool light_visible(const Geometry& geometry, const SurfaceHit& hit, const Lamp& lamp, glm::dvec2 disk) {
  const glm::dvec3 origin = hit.position + geometry.shadow_offset() * glm::dvec3(hit.normal);
  if (!lamp.point) {
    glm::dvec3 dir = cone_direction(lamp.vector, lamp.size, disk);
    return !geometry.occluded(origin, dir, 0.0, std::numeric_limits<double>::infinity());
  }
  const glm::dvec3 to = lamp.vector - origin;
  const double dist = glm::length(to);
  if (!(dist > lamp.size)) return true;  // inside the light
  const glm::dvec3 axis = to / dist;
  const glm::dvec3 dir = cone_direction(axis, std::asin(lamp.size / dist), disk);
  // Up to where the ray meets the light's sphere.
  const double b = glm::dot(dir, to), disc = lamp.size * lamp.size - (dist * dist - b * b);
  const double t_max = b - std::sqrt(std::max(0.0, disc));
  return !geometry.occluded(origin, dir, 0.0, t_max);
}

// svo_shade (shaders/common/tracer.glsl) with the micro-BRDF alone: Lambda =
// 0, so abar(v, l) = a; slope variance sigma_rho^2. `shadow[i]`: the point
// of light i's extent for this sample's shadow ray.
glm::dvec3 shade(const Geometry& geometry, const Setup& c, const SurfaceHit& hit, glm::dvec3 view,
                 const glm::dvec2* shadow, svo::math::ReferenceLighting* lit) {
  using namespace svo::math;
  const glm::vec3 n = hit.normal, a = hit.colour;
  const SvoFrame f = svo_tangent_frame(n);
  const glm::vec3 vf(view);
  const glm::vec3 vl(glm::dot(vf, f.t), glm::dot(vf, f.b), glm::dot(vf, n));
  glm::dvec3 radiance = c.ambient * glm::dvec3(a);
  for (size_t i = 0; i < c.lamps.size(); ++i) {
    const Lamp& lamp = c.lamps[i];
    glm::dvec3 l = lamp.vector, e = lamp.radiance;
    if (lamp.point) {
      const glm::dvec3 to = lamp.vector - hit.position;
      const double dist = glm::length(to);
      l = to / std::max(dist, 1e-300);
      e = lamp.radiance / std::max(dist * dist, 1e-300);
    }
    const glm::vec3 lf(l);
    const float ndl = glm::dot(n, lf);
    if (!(ndl > 0.0f)) continue;
    if (c.shadows && !light_visible(geometry, hit, lamp, shadow[i])) continue;
    const glm::vec3 ll(glm::dot(lf, f.t), glm::dot(lf, f.b), ndl);
    const glm::vec3 rho = lit ? lit->svo_material_brdf(lit->svo_scene_material(hit.material), a, vl, ll)
                              : a / SVO_PI + glm::vec3(c.specular * svo_specular_brdf(vl, ll, c.total_variance));
    radiance += e * glm::dvec3(rho) * double(ndl);
  }
  return radiance;
}

double power_heuristic(double a, double b) { return a * a + b * b > 0 ? a * a / (a * a + b * b) : 0.0; }

// One sample of the environment lighting the exact surface point `hit`
// seen along -view: one direction from the material, one from the
// environment, combined by the power heuristic; `u`: five uniforms.
glm::dvec3 shade_environment(const Geometry& geometry, svo::math::ReferenceLighting& lit, bool shadows,
                             const SurfaceHit& hit, glm::dvec3 view, const double* u) {
  using namespace svo::math;
  const SvoMaterial mat = lit.svo_scene_material(hit.material);
  const glm::vec3 n = hit.normal;
  const SvoFrame f = svo_tangent_frame(n);
  const glm::vec3 vw(view);
  const glm::vec3 v(glm::dot(vw, f.t), glm::dot(vw, f.b), glm::dot(vw, n));
  const glm::vec3 tint = hit.colour;
  const glm::dvec3 origin = hit.position + geometry.shadow_offset() * glm::dvec3(hit.normal);
  auto seen = [&](glm::vec3 l) {
    return !shadows || !geometry.occluded(origin, glm::dvec3(l), 0.0, std::numeric_limits<double>::infinity());
  };
  glm::dvec3 sum(0);
  const glm::vec4 b = lit.svo_sample_material(mat, tint, v, glm::vec3(u[0], u[1], u[2]));
  if (b.w > 0) {
    const glm::vec3 l = b.x * f.t + b.y * f.b + b.z * n;
    const glm::vec3 fr = lit.svo_material_brdf(mat, tint, v, glm::vec3(b));
    const double w = power_heuristic(b.w, lit.svo_env_pdf(lit.shade, l));
    if (fr != glm::vec3(0) && seen(l)) sum += glm::dvec3(fr * lit.svo_env_radiance(lit.shade, l)) * (b.z * w / b.w);
  }
  const glm::vec4 e = lit.svo_env_sample(lit.shade, glm::vec2(u[3], u[4]));
  if (e.w > 0) {
    const glm::vec3 l(e);
    const glm::vec3 ll(glm::dot(l, f.t), glm::dot(l, f.b), glm::dot(l, n));
    const glm::vec3 fr = lit.svo_material_brdf(mat, tint, v, ll);
    const double w = power_heuristic(e.w, lit.svo_material_pdf(mat, tint, v, ll));
    if (fr != glm::vec3(0) && seen(l)) sum += glm::dvec3(fr * lit.svo_env_radiance(lit.shade, l)) * (ll.z * w / e.w);
  }
  return sum;
}

}  // namespace

render::Frame render_reference(const Geometry& geometry, const ReferenceSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const Setup c = make_setup(geometry, settings);
  // An environment or a material: shaded with the forward pass's lighting code.
  render::ShadingOptions so = settings.render.shading;
  // Without --material, the source's own materials, as the octree carries them.
  if (!so.material && so.scene_materials.empty()) {
    so.scene_materials = render::parse_scene_materials(geometry.materials(), "the scene");
  }
  const bool lighting = so.environment || so.material || !so.scene_materials.empty();
  const render::ShadingTables tables =
      lighting ? render::build_shading_tables(so, render::builtin_material(c.specular, geometry.sigma_rho2()), false)
               : render::ShadingTables{};
  // Its functions only read (non-const members: the GLSL is included in the struct).
  svo::math::ReferenceLighting lit{{tables.params, tables.floats.data()}};
  const bool environment = bool(so.environment);
  const uint32_t width = settings.render.width, height = settings.render.height, n = settings.spp;
  const glm::uvec2 shape = grid_shape(n);
  render::Frame frame;
  frame.width = width;
  frame.height = height;
  frame.colour.assign(size_t(width) * height, glm::vec4(0));
  std::atomic<uint32_t> rows_done{0};
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height, 1), [&](const tbb::blocked_range<uint32_t>& rows) {
    std::vector<glm::dvec2> footprint, lens;
    std::vector<std::vector<glm::dvec2>> shadow(c.lamps.size());
    std::vector<glm::dvec2> shadow_of_sample(c.lamps.size());
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      for (uint32_t x = 0; x < width; ++x) {
        const uint64_t index = uint64_t(y) * width + x;
        Rng rng{settings.seed * 0x9E3779B97F4A7C15ull ^ (index * 0xD1B54A32D192ED03ull + 1)};
        stratified_disk(n, shape, rng, false, footprint);
        if (c.aperture > 0) stratified_disk(n, shape, rng, true, lens);
        if (c.shadows) {
          for (auto& s : shadow) stratified_disk(n, shape, rng, true, s);
        }
        // The cone through the pixel centre (svo_trace_pixel's axis).
        const double nx = (x + 0.5) / width * 2 - 1, ny = (y + 0.5) / height * 2 - 1;
        const glm::dvec3 axis = glm::normalize(c.w + nx * c.tan_half * c.aspect * c.u - ny * c.tan_half * c.v);
        glm::dvec3 fa, fb;
        perpendicular_frame(axis, fa, fb);
        glm::dvec3 sum(0);
        uint32_t covered = 0;
        for (uint32_t i = 0; i < n; ++i) {
          const glm::dvec2 p = footprint[i] * c.slope;
          glm::dvec3 dir = glm::normalize(axis + p.x * fa + p.y * fb);
          glm::dvec3 origin = c.eye;
          if (c.aperture > 0) {
            const glm::dvec3 in_focus = c.eye + dir * (c.focus / glm::dot(dir, c.w));
            origin = c.eye + c.aperture * (lens[i].x * c.u + lens[i].y * c.v);
            dir = glm::normalize(in_focus - origin);
          }
          const std::optional<SurfaceHit> hit =
              geometry.intersect(origin, dir, 0.0, std::numeric_limits<double>::infinity());
          if (!hit) {
            sum += environment ? glm::dvec3(lit.svo_env_background(lit.shade, glm::vec3(dir))) : c.background;
            continue;
          }
          ++covered;
          for (size_t l = 0; l < shadow.size() && c.shadows; ++l) shadow_of_sample[l] = shadow[l][i];
          sum += shade(geometry, c, *hit, -dir, shadow_of_sample.data(), lighting ? &lit : nullptr);
          if (environment) {
            // The forward pass's sequence (dimensions 2-6), another seed.
            const uint32_t px = uint32_t(index), sd = uint32_t(settings.seed) ^ 0x5EEDu;
            const double u[5] = {lit.svo_sample_1d(px, sd, i, 2), lit.svo_sample_1d(px, sd, i, 3),
                                 lit.svo_sample_1d(px, sd, i, 4), lit.svo_sample_1d(px, sd, i, 5),
                                 lit.svo_sample_1d(px, sd, i, 6)};
            sum += shade_environment(geometry, lit, so.env_shadows, *hit, -dir, u);
          }
        }
        frame.colour[index] = glm::vec4(glm::vec3(sum / double(n)), float(double(covered) / double(n)));
      }
      const uint32_t done = ++rows_done;
      if (settings.progress) settings.progress(double(done) / double(height));
    }
  });
  for (const auto& px : frame.colour) frame.covered_pixels += px.a > 0 ? 1 : 0;
  frame.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

}  // namespace svo::reference
