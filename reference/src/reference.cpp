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
#include "svo/render/luminaire.h"
#include "svo/render/shading.h"

namespace svo::math {

// The environment and material of shaders/common, as the forward pass reads
// them, for the reference's own sampling.
struct ReferenceLighting : render::NativeShadingReader {
#include "common/area_light.glsl"
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

// A placed luminaire in scene units (render::luminaire_frame), for the
// quadrature of its light-field integral.
struct LumSetup {
  const render::LightField* field = nullptr;
  glm::dvec3 centre{0}, x{0}, y{0}, z{0};  // plane S's centre and axes; z away from U
  double delta = 0, spacing = 0;           // U to S, the basis grid's spacing
  glm::dvec2 extent{0};                    // S across
  glm::dvec2 u_lo{0}, u_hi{0};             // the union of the basis supports on U
  double texel_area = 0;
  int32_t cells = 3;  // the basis support in cells
};

std::vector<LumSetup> make_luminaires(const ReferenceSettings& settings) {
  const render::LuminaireOptions& o = settings.render.luminaire;
  if (o.luminaires.size() > render::LuminaireOptions::kMaxLuminaires) {
    throw std::invalid_argument("reference: at most " + std::to_string(render::LuminaireOptions::kMaxLuminaires) +
                                " luminaires, got " + std::to_string(o.luminaires.size()));
  }
  if (!o.luminaires.empty() && settings.luminaire_quadrature == 0) {
    throw std::invalid_argument("reference: the luminaire quadrature must be at least 1 point per texel side");
  }
  std::vector<LumSetup> out;
  for (size_t i = 0; i < o.luminaires.size(); ++i) {
    const render::PlacedLuminaire& p = o.luminaires[i];
    if (!p.field) throw std::invalid_argument("reference: luminaire " + std::to_string(i + 1) + " has no light field");
    const render::LightField& f = *p.field;
    const render::LuminaireFrame frame = render::luminaire_frame(f, p.placement);
    LumSetup l;
    l.field = &f;
    l.centre = glm::dvec3(frame.centre);
    l.x = glm::dvec3(frame.x);
    l.y = glm::dvec3(frame.y);
    l.z = glm::dvec3(frame.z);
    const double scale = frame.scale;
    l.delta = double(f.delta) * scale;
    l.spacing = double(f.spacing) * scale;
    l.extent = glm::dvec2(f.extent) * scale;
    l.texel_area = l.extent.x * l.extent.y / (double(f.width) * double(f.height));
    l.cells = int32_t(render::luminaire_basis_cells(f.basis));
    const double half = 0.5 * l.cells * l.spacing;
    l.u_lo = glm::dvec2(f.basis_centre(0)) * scale - half;
    l.u_hi = glm::dvec2(f.basis_centre(f.image_count() - 1)) * scale + half;
    out.push_back(l);
  }
  return out;
}

// The light of luminaire `lum` that the exact surface point `hit` reflects
// along `view` (the material `mat` tinted by `tint`, `f` the tangent frame,
// `v` the view in it): the dense quadrature of reference.h, k^2 points per
// texel, one exact shadow ray per point where the rest is not 0.
glm::dvec3 shade_luminaire(const Geometry& geometry, svo::math::ReferenceLighting& lit, const LumSetup& lum, uint32_t k,
                           const SurfaceHit& hit, const svo::math::SvoMaterial& mat, const svo::math::SvoFrame& f,
                           glm::vec3 v) {
  const render::LightField& field = *lum.field;
  const glm::dvec3 d = hit.position - lum.centre;
  const glm::dvec3 pl(glm::dot(d, lum.x), glm::dot(d, lum.y), glm::dot(d, lum.z));
  if (!(pl.z > 1.0e-5 * lum.delta)) return glm::dvec3(0);  // behind S (or on it): nothing
  const glm::dvec2 p2(pl);
  const double to_s = pl.z / (pl.z + lum.delta), to_u = (pl.z + lum.delta) / pl.z;
  // The box of S that the supports reach from p (Eq. 7, over all images), in texels.
  const glm::dvec2 res(field.width, field.height);
  const glm::dvec2 t_lo = ((p2 + (lum.u_lo - p2) * to_s) / lum.extent + 0.5) * res;
  const glm::dvec2 t_hi = ((p2 + (lum.u_hi - p2) * to_s) / lum.extent + 0.5) * res;
  const int64_t x0 = std::max<int64_t>(0, int64_t(std::floor(t_lo.x)));
  const int64_t y0 = std::max<int64_t>(0, int64_t(std::floor(t_lo.y)));
  const int64_t x1 = std::min<int64_t>(field.width, int64_t(std::ceil(t_hi.x)));
  const int64_t y1 = std::min<int64_t>(field.height, int64_t(std::ceil(t_hi.y)));
  if (x0 >= x1 || y0 >= y1) return glm::dvec3(0);
  const glm::dvec3 origin = hit.position + geometry.shadow_offset() * glm::dvec3(hit.normal);
  const glm::vec3 n = hit.normal, tint = hit.colour;
  const int32_t gw = int32_t(field.grid_w), gh = int32_t(field.grid_h);
  const double half_cells = 0.5 * lum.cells;
  const glm::dvec2 grid_half(0.5 * (gw - 1), 0.5 * (gh - 1));
  glm::dvec3 sum(0);
  for (int64_t ty = y0; ty < y1; ++ty) {
    for (int64_t tx = x0; tx < x1; ++tx) {
      const size_t texel = 3 * (size_t(ty) * field.width + size_t(tx));
      for (uint32_t j = 0; j < k; ++j) {
        for (uint32_t i = 0; i < k; ++i) {
          const glm::dvec2 t(double(tx) + (i + 0.5) / k, double(ty) + (j + 0.5) / k);
          const glm::dvec2 s = (t / res - 0.5) * lum.extent;
          // u on U, in grid cells from basis (0, 0); the images whose support holds it.
          const glm::dvec2 g = (p2 + (s - p2) * to_u) / lum.spacing + grid_half;
          const int32_t i0 = std::max(0, int32_t(std::ceil(g.x - half_cells)));
          const int32_t i1 = std::min(gw - 1, int32_t(std::floor(g.x + half_cells)));
          const int32_t j0 = std::max(0, int32_t(std::ceil(g.y - half_cells)));
          const int32_t j1 = std::min(gh - 1, int32_t(std::floor(g.y + half_cells)));
          glm::dvec3 c(0);
          for (int32_t b = j0; b <= j1; ++b) {
            const float phi_y = render::luminaire_basis_phi(field.basis, float(g.y - b));
            if (!(phi_y > 0.0f)) continue;
            for (int32_t a = i0; a <= i1; ++a) {
              const float phi = phi_y * render::luminaire_basis_phi(field.basis, float(g.x - a));
              if (!(phi > 0.0f)) continue;
              const float* rgb = &field.images[size_t(b) * gw + a][texel];
              c += double(phi) * glm::dvec3(rgb[0], rgb[1], rgb[2]);
            }
          }
          if (!(c.x + c.y + c.z > 0)) continue;
          const glm::dvec3 q = lum.centre + s.x * lum.x + s.y * lum.y;
          const glm::dvec3 to = q - hit.position;
          const double r = glm::length(to);
          if (!(r > 0)) continue;
          const glm::vec3 l(to / r);
          const glm::vec3 ll(glm::dot(l, f.t), glm::dot(l, f.b), glm::dot(l, n));
          if (!(ll.z > 0.0f)) continue;
          const glm::vec3 fr = lit.svo_material_brdf(mat, tint, v, ll) * ll.z;
          if (!(fr.x + fr.y + fr.z > 0.0f)) continue;
          const glm::dvec3 ray = q - origin;
          const double dist = glm::length(ray);
          if (dist > 0 && geometry.occluded(origin, ray / dist, 0.0, dist)) continue;
          sum += c * glm::dvec3(fr) * (pl.z / (r * r * r));
        }
      }
    }
  }
  return sum * (lum.texel_area / (double(k) * k));
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

// One point of the area light (area_light.glsl, drawn as the forward pass
// draws it, with uniform u) lighting the exact surface point `hit` seen
// along -view, through a shadow ray to the point when `shadows`.
glm::dvec3 shade_area_light(const Geometry& geometry, svo::math::ReferenceLighting& lit, bool shadows,
                            const SurfaceHit& hit, glm::dvec3 view, glm::vec2 u) {
  using namespace svo::math;
  const auto a = lit.svo_area_sample(lit.shade, glm::vec3(hit.position), u);
  if (!(a.pdf > 0)) return glm::dvec3(0);
  const glm::vec3 n = hit.normal;
  const SvoFrame f = svo_tangent_frame(n);
  const glm::vec3 vw(view);
  const glm::vec3 v(glm::dot(vw, f.t), glm::dot(vw, f.b), glm::dot(vw, n));
  const glm::vec3 ll(glm::dot(a.l, f.t), glm::dot(a.l, f.b), glm::dot(a.l, n));
  if (!(ll.z > 0)) return glm::dvec3(0);
  const glm::vec3 fr = lit.svo_material_brdf(lit.svo_scene_material(hit.material), hit.colour, v, ll);
  if (fr == glm::vec3(0)) return glm::dvec3(0);
  if (shadows) {
    const glm::dvec3 origin = hit.position + geometry.shadow_offset() * glm::dvec3(hit.normal);
    const glm::dvec3 ray = glm::dvec3(hit.position) + double(a.dist) * glm::dvec3(a.l) - origin;
    const double dist = glm::length(ray);
    if (dist > 0 && geometry.occluded(origin, ray / dist, 0.0, dist * (1 - 1e-6))) return glm::dvec3(0);
  }
  return glm::dvec3(fr * a.radiance) * double(ll.z / a.pdf);
}

}  // namespace

render::Frame render_reference(const Geometry& geometry, const ReferenceSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const Setup c = make_setup(geometry, settings);
  const std::vector<LumSetup> luminaires = make_luminaires(settings);
  const uint32_t quadrature = settings.luminaire_quadrature;
  // An environment or a material: shaded with the forward pass's lighting code.
  render::ShadingOptions so = settings.render.shading;
  // Without --material, the source's own materials, as the octree carries them.
  if (!so.material && so.scene_materials.empty()) {
    so.scene_materials = render::parse_scene_materials(geometry.materials(), "the scene");
  }
  const bool lighting = so.environment || so.material || !so.scene_materials.empty() || so.area_light;
  // Luminaires shade with the materials' code too (the built-in material
  // when there is no other, as the luminaire pass).
  const render::ShadingTables tables =
      lighting || !luminaires.empty()
          ? render::build_shading_tables(so, render::builtin_material(c.specular, geometry.sigma_rho2()), false)
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
          if (!luminaires.empty()) {
            const svo::math::SvoMaterial mat = lit.svo_scene_material(hit->material);
            const svo::math::SvoFrame tf = svo::math::svo_tangent_frame(hit->normal);
            const glm::vec3 vw(-dir);
            const glm::vec3 vl(glm::dot(vw, tf.t), glm::dot(vw, tf.b), glm::dot(vw, hit->normal));
            for (const LumSetup& lum : luminaires) {
              sum += shade_luminaire(geometry, lit, lum, quadrature, *hit, mat, tf, vl);
            }
          }
          if (environment) {
            // The forward pass's sequence (dimensions 2-6), another seed.
            const uint32_t px = uint32_t(index), sd = uint32_t(settings.seed) ^ 0x5EEDu;
            const double u[5] = {lit.svo_sample_1d(px, sd, i, 2), lit.svo_sample_1d(px, sd, i, 3),
                                 lit.svo_sample_1d(px, sd, i, 4), lit.svo_sample_1d(px, sd, i, 5),
                                 lit.svo_sample_1d(px, sd, i, 6)};
            sum += shade_environment(geometry, lit, so.env_shadows, *hit, -dir, u);
          }
          if (so.area_light) {
            const uint32_t px = uint32_t(index), sd = uint32_t(settings.seed) ^ 0xA2EAu;
            sum += shade_area_light(geometry, lit, c.shadows, *hit, -dir,
                                    glm::vec2(lit.svo_sample_1d(px, sd, i, 8), lit.svo_sample_1d(px, sd, i, 9)));
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
