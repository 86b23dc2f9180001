// The reference under light-field luminaires (DESIGN 10.4): the dense
// quadrature on the exact surface against an independent integral over
// directions, and exact shadows of an occluder.
#include "svo/render/luminaire.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <memory>
#include <utility>

#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/shading.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The ground: the slab [-2, 2] x [-0.1, 0] x [-2, 2], and optionally a thin
// square occluder of half-size `occluder` centred at (0, 0.25, 0).
class GroundScene : public voxelizer::AnalyticScene {
 public:
  explicit GroundScene(float occluder = 0.0f) : occluder_(occluder) {}
  float distance(glm::vec3 p) const override {
    float d = box(p, glm::vec3(0, -0.05f, 0), glm::vec3(2.0f, 0.05f, 2.0f));
    if (occluder_ > 0) d = std::min(d, box(p, glm::vec3(0, 0.25f, 0), glm::vec3(occluder_, 0.01f, occluder_)));
    return d;
  }
  glm::vec3 colour(glm::vec3) const override { return glm::vec3(0.6f); }
  std::string name() const override { return "ground"; }
  voxelizer::Box bounds() const override { return {glm::vec3(-2, -0.1f, -2), glm::vec3(2, 0.3f, 2)}; }

 private:
  static float box(glm::vec3 p, glm::vec3 c, glm::vec3 e) {
    glm::vec3 q = glm::abs(p - c) - e;
    return glm::length(glm::max(q, glm::vec3(0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
  }
  float occluder_;
};

// A checkered panel 0.4 across, 0.5 above the ground's origin, facing it
// (3 x 3 checks: more bright than dark ones, so that the colour varies).
render::PlacedLuminaire panel() {
  render::PlacedLuminaire p;
  p.field = std::make_shared<const render::LightField>(render::make_panel_luminaire(15, 3, 10.0f, 3));
  p.placement.at = glm::vec3(0, 0.5f, 0);
  p.placement.aim = glm::vec3(0);
  p.placement.size = 0.4f;
  return p;
}

ReferenceSettings lit_by(const render::PlacedLuminaire& lum, render::Camera camera, uint32_t w, uint32_t h) {
  ReferenceSettings s;
  s.render.width = w;
  s.render.height = h;
  s.render.camera = camera;
  s.render.lights.clear();
  s.render.ambient = glm::vec3(0);
  s.render.background = glm::vec3(0);
  auto lambert = std::make_shared<render::Material>();
  lambert->kind = render::BrdfKind::Lambert;
  lambert->diffuse = glm::vec3(1.0f);
  s.render.shading.material = lambert;
  s.render.luminaire.luminaires = {lum};
  return s;
}

// The irradiance E = integral of L cos over the hemisphere above the ground
// point p (normal +y), by Malley's method: a fine grid of the projected
// disk of directions (each cell the same projected solid angle), each
// direction followed back to where it leaves plane S and comes from U, and
// the light field's radiance there (LightField::radiance, file units).
glm::dvec3 brute_force_irradiance(const render::PlacedLuminaire& lum, glm::dvec3 p, double half, int n) {
  const render::LuminaireFrame f = render::luminaire_frame(*lum.field, lum.placement);
  const glm::dvec3 x(f.x), y(f.y), z(f.z), c(f.centre);
  const double scale = f.scale, delta = lum.field->delta * scale;
  const glm::dvec2 extent = glm::dvec2(lum.field->extent) * scale;
  const glm::dvec3 pl(glm::dot(p - c, x), glm::dot(p - c, y), glm::dot(p - c, z));
  const double cell = 2 * half / n;
  glm::dvec3 sum(0);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double a = -half + (i + 0.5) * cell, b = -half + (j + 0.5) * cell;
      const double r2 = a * a + b * b;
      if (r2 >= 1) continue;
      const glm::dvec3 w(a, std::sqrt(1 - r2), b);  // towards the light
      const glm::dvec3 wl(glm::dot(w, x), glm::dot(w, y), glm::dot(w, z));
      if (!(wl.z < 0)) continue;  // light comes from -z of the frame
      const double ts = -pl.z / wl.z, tu = (-delta - pl.z) / wl.z;
      const glm::dvec2 s = glm::dvec2(pl) + ts * glm::dvec2(wl), u = glm::dvec2(pl) + tu * glm::dvec2(wl);
      if (std::abs(s.x) >= 0.5 * extent.x || std::abs(s.y) >= 0.5 * extent.y) continue;
      sum += glm::dvec3(lum.field->radiance(glm::vec2(u / scale), glm::vec2(s / scale)));
    }
  }
  return sum * (cell * cell);
}

glm::dvec3 pixel(const render::Frame& f, uint32_t x, uint32_t y) {
  return glm::dvec3(glm::vec3(f.colour[size_t(y) * f.width + x]));
}

TEST(ReferenceLuminaire, PanelOverAPlaneMatchesTheIntegralOverDirections) {
  GroundScene ground;
  auto geometry = scene_geometry(ground);
  const render::PlacedLuminaire lum = panel();
  // A narrow view of the origin: the centre pixel's footprint is < 0.01
  // across, where the irradiance is flat to 1e-4 (the panel is symmetric).
  ReferenceSettings s = lit_by(lum, test::looking_at_origin({0.0f, 1.0f, 0.6f}, 4.0f), 9, 9);
  s.spp = 4;
  // The panel seen from the origin: |direction.xz| < 0.2 / sqrt(0.25 + 0.04) < 0.38.
  const glm::dvec3 exact = 0.6 / kPi * brute_force_irradiance(lum, glm::dvec3(0), 0.4, 3000);
  // The midpoint rule's error falls as 1 / k^2 (k = 1: 0.2%).
  for (const auto& [k, tolerance] : {std::pair{1u, 5e-3}, std::pair{3u, 5e-4}}) {
    s.luminaire_quadrature = k;
    const render::Frame f = render_reference(*geometry, s);
    test::save_for_inspection(f, "reference-luminaire-k" + std::to_string(k));
    const glm::dvec3 got = pixel(f, 4, 4);
    std::printf("k = %u: centre pixel (%.6f, %.6f, %.6f), integral over directions (%.6f, %.6f, %.6f)\n", k, got.x,
                got.y, got.z, exact.x, exact.y, exact.z);
    EXPECT_GT(exact.x, 0.1);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], exact[c], tolerance * exact[c]) << "k = " << k << ", channel " << c;
  }
  // Nothing behind the panel: the same luminaire turned away lights nothing.
  render::PlacedLuminaire away = lum;
  away.placement.aim = glm::vec3(0, 1.0f, 0);
  s.render.luminaire.luminaires = {away};
  const render::Frame dark = render_reference(*geometry, s);
  EXPECT_EQ(pixel(dark, 4, 4), glm::dvec3(0));
}

TEST(ReferenceLuminaire, AnOccluderDarkensItsUmbraAndNothingElse) {
  // An occluder 0.3 across halfway between the panel (0.4 across, 0.5 up)
  // and the ground: every line from the panel to a ground point with |x|,
  // |z| < 0.1 crosses it (the umbra); none to a point with |x| or |z| > 0.5.
  GroundScene open, shaded(0.15f);
  const render::PlacedLuminaire lum = panel();
  // Under the occluder (whose bottom is at 0.24): no ray from the eye meets it.
  const render::Camera camera = test::looking_at_origin({0.0f, 0.2f, 0.6f}, 30.0f);
  ReferenceSettings s = lit_by(lum, camera, 48, 36);
  s.spp = 4;
  const render::Frame lit = render_reference(*scene_geometry(open), s);
  const render::Frame dark = render_reference(*scene_geometry(shaded), s);
  test::save_for_inspection(lit, "reference-luminaire-open");
  test::save_for_inspection(dark, "reference-luminaire-occluded");
  const glm::dvec3 eye(camera.eye), fw = glm::normalize(glm::dvec3(camera.target) - eye);
  const glm::dvec3 u = glm::normalize(glm::cross(fw, glm::dvec3(camera.up))), v = glm::cross(u, fw);
  const double t = std::tan(double(camera.fov_deg) * kPi / 360.0);
  int umbra = 0, outside = 0;
  for (uint32_t y = 0; y < s.render.height; ++y) {
    for (uint32_t x = 0; x < s.render.width; ++x) {
      // The ground under the pixel's corners (they hold its footprint disk).
      glm::dvec2 lo(1e30), hi(-1e30);
      bool ground = true;
      for (int corner = 0; corner < 4; ++corner) {
        const double nx = double(x + corner % 2) / s.render.width * 2 - 1;
        const double ny = double(y + corner / 2) / s.render.height * 2 - 1;
        const glm::dvec3 d = glm::normalize(fw + nx * t * s.render.width / s.render.height * u - ny * t * v);
        ground = ground && d.y < 0;
        const glm::dvec3 q = eye + (-eye.y / d.y) * d;
        lo = glm::min(lo, glm::dvec2(q.x, q.z));
        hi = glm::max(hi, glm::dvec2(q.x, q.z));
      }
      if (!ground) continue;
      if (lo.x > -0.1 && hi.x < 0.1 && lo.y > -0.1 && hi.y < 0.1) {
        ++umbra;
        EXPECT_GT(pixel(lit, x, y).x, 0.1) << "open ground " << x << "," << y;
        EXPECT_EQ(pixel(dark, x, y), glm::dvec3(0)) << "umbra " << x << "," << y;
      } else if ((lo.x > 0.5 || hi.x < -0.5 || lo.y > 0.5 || hi.y < -0.5) && lo.x > -2 && hi.x < 2 && lo.y > -2 &&
                 hi.y < 2) {
        ++outside;
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(pixel(dark, x, y)[c], pixel(lit, x, y)[c], 1e-4 * pixel(lit, x, y)[c] + 1e-7)
              << "unshadowed " << x << "," << y;
        }
      }
    }
  }
  std::printf("%d umbra pixels, %d unshadowed ones\n", umbra, outside);
  EXPECT_GT(umbra, 6);
  EXPECT_GT(outside, 50);
}

TEST(ReferenceLuminaire, RefusesBadSettings) {
  GroundScene ground;
  auto geometry = scene_geometry(ground);
  ReferenceSettings s = lit_by(panel(), test::looking_at_origin({0.0f, 1.0f, 0.6f}, 40.0f), 4, 4);
  s.luminaire_quadrature = 0;
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
  s.luminaire_quadrature = 1;
  s.render.luminaire.luminaires[0].field.reset();
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
  s.render.luminaire.luminaires = {panel()};
  s.render.luminaire.luminaires[0].placement.aim = s.render.luminaire.luminaires[0].placement.at;
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
}

}  // namespace
}  // namespace svo::reference
