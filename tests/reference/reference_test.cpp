// The reference tracer against answers worked out here independently: a
// diffuse sphere's closed form averaged over each pixel's footprint disk,
// the exact covered fraction of silhouette pixels, hard shadows of a sphere
// on a plate, the blur of a thin lens, stratified convergence, and Embree's
// mesh path against the sphere tracer on the same box.
#include "svo/reference/reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <optional>

#include "temp_dir.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The camera contract written out again (render/src/trace_setup.cpp): the
// cone through the centre of pixel (x, y), y down, whose cross-section at
// unit distance is a disk of the pixel's area.
struct PixelCone {
  glm::dvec3 axis, a, b;  // unit axis; a, b span the footprint
  double radius;          // footprint radius per unit distance
};

PixelCone pixel_cone(const render::Camera& c, uint32_t w, uint32_t h, uint32_t x, uint32_t y) {
  glm::dvec3 fw = glm::normalize(glm::dvec3(c.target - c.eye));
  glm::dvec3 u = glm::normalize(glm::cross(fw, glm::dvec3(c.up))), v = glm::cross(u, fw);
  double t = std::tan(double(c.fov_deg) * kPi / 360.0);
  double nx = (x + 0.5) / w * 2 - 1, ny = (y + 0.5) / h * 2 - 1;
  PixelCone p;
  p.axis = glm::normalize(fw + nx * t * double(w) / h * u - ny * t * v);
  p.a = glm::normalize(glm::cross(p.axis, v));
  p.b = glm::cross(p.axis, p.a);
  p.radius = 2 * t / h / std::sqrt(kPi);
  return p;
}

// Mean of f over an n x n grid of the footprint disk (points outside the disk dropped).
template <class F>
double footprint_mean(const PixelCone& p, int n, F f) {
  double sum = 0;
  int count = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      double dx = (i + 0.5) / n * 2 - 1, dy = (j + 0.5) / n * 2 - 1;
      if (dx * dx + dy * dy > 1) continue;
      sum += f(glm::normalize(p.axis + p.radius * (dx * p.a + dy * p.b)));
      ++count;
    }
  }
  return sum / count;
}

// Distance along unit d from o to a sphere (centre c, radius r), if it is met.
std::optional<double> hit_sphere(glm::dvec3 o, glm::dvec3 d, glm::dvec3 c, double r) {
  glm::dvec3 oc = o - c;
  double b = glm::dot(oc, d), disc = b * b - (glm::dot(oc, oc) - r * r);
  if (disc < 0) return std::nullopt;
  double t = -b - std::sqrt(disc);
  if (t <= 0) return std::nullopt;
  return t;
}

float red(const render::Frame& f, uint32_t x, uint32_t y) { return f.colour[size_t(y) * f.width + x].r; }
float alpha(const render::Frame& f, uint32_t x, uint32_t y) { return f.colour[size_t(y) * f.width + x].a; }

// A diffuse grey sphere of radius 0.5 under one directional light of
// irradiance E, no ambient, no background, no specular lobe.
struct DiffuseSphere {
  test::SphereScene scene{0.5f};
  ReferenceSettings settings;
  glm::dvec3 light = glm::normalize(glm::dvec3(0.3, 0.5, 0.8));
  double irradiance = 2.0, albedo = 0.5;

  DiffuseSphere(uint32_t size, uint32_t spp) {
    settings.render.width = settings.render.height = size;
    settings.render.camera = test::looking_at_origin({0.3f, 0.4f, 3.0f}, 25.0f);
    settings.render.lights = {render::Light{false, glm::vec3(light), glm::vec3(float(irradiance)), 0.0f}};
    settings.render.ambient = glm::vec3(0);
    settings.render.background = glm::vec3(0);
    settings.render.specular = 0;
    settings.spp = spp;
  }
  render::Frame render() const { return render_reference(*scene_geometry(scene), settings); }

  struct Exact {
    double radiance = 0;  // mean over the footprint, uncovered directions counting 0
    double covered = 0;   // covered fraction of the footprint
    double min_cos = 1;   // smallest n . l over the covered part
    double min_view = 1;  // smallest n . v over the covered part (small near the limb)
  };
  Exact exact(uint32_t x, uint32_t y, int grid) const {
    const auto& s = settings.render;
    PixelCone p = pixel_cone(s.camera, s.width, s.height, x, y);
    glm::dvec3 eye(s.camera.eye);
    Exact e;
    e.radiance = footprint_mean(p, grid, [&](glm::dvec3 d) {
      auto t = hit_sphere(eye, d, glm::dvec3(0), 0.5);
      if (!t) return 0.0;
      glm::dvec3 n = glm::normalize(eye + *t * d);
      double cos = glm::dot(n, light);
      e.min_cos = std::min(e.min_cos, cos);
      e.min_view = std::min(e.min_view, -glm::dot(n, d));
      return albedo / kPi * irradiance * std::max(0.0, cos);
    });
    e.covered =
        footprint_mean(p, grid, [&](glm::dvec3 d) { return hit_sphere(eye, d, glm::dvec3(0), 0.5) ? 1.0 : 0.0; });
    return e;
  }
};

TEST(Reference, DiffuseSphereMatchesItsClosedFormPerPixel) {
  DiffuseSphere sphere(32, 256);
  render::Frame f = sphere.render();
  test::save_for_inspection(f, "reference-sphere");
  int interior = 0, centre = 0, terminator = 0, silhouette = 0, empty = 0;
  double worst_interior = 0, bias = 0, silhouette_sum = 0, silhouette_worst = 0;
  const double peak = sphere.albedo / kPi * sphere.irradiance;
  for (uint32_t y = 0; y < 32; ++y) {
    for (uint32_t x = 0; x < 32; ++x) {
      auto [radiance, covered, min_cos, min_view] = sphere.exact(x, y, 200);
      if (covered == 1.0) {
        // Fully covered: the colour is the footprint mean of a/pi E max(0, n.l).
        // Tight in the middle of the disk, where the integrand is smooth and
        // nearly linear over a pixel; looser towards the limb, where the
        // normal turns fast (stratified jitter still has 1e-3 noise at 256
        // spp there), and across the terminator's kink.
        EXPECT_EQ(alpha(f, x, y), 1.0f) << x << "," << y;
        if (min_cos > 0.05) {
          ++interior;
          const double relative = (red(f, x, y) - radiance) / radiance;
          worst_interior = std::max(worst_interior, std::abs(relative));
          bias += relative;
          if (min_view > 0.7) {
            ++centre;
            EXPECT_NEAR(red(f, x, y), radiance, 6e-4 * radiance) << "centre pixel " << x << "," << y;
          } else {
            EXPECT_NEAR(red(f, x, y), radiance, 4e-3 * radiance) << "pixel " << x << "," << y;
          }
        } else {
          ++terminator;
          EXPECT_NEAR(red(f, x, y), radiance, 2e-3 * peak) << "terminator pixel " << x << "," << y;
        }
      } else if (covered == 0.0) {
        ++empty;
        EXPECT_EQ(alpha(f, x, y), 0.0f) << x << "," << y;
        EXPECT_EQ(red(f, x, y), 0.0f) << x << "," << y;
      }
    }
  }
  // Silhouette pixels: the covered fraction against a finer grid of the disk.
  for (uint32_t y = 0; y < 32; ++y) {
    for (uint32_t x = 0; x < 32; ++x) {
      double covered = sphere.exact(x, y, 24).covered;
      if (covered == 0.0 || covered == 1.0) continue;
      covered = sphere.exact(x, y, 160).covered;
      ++silhouette;
      double error = std::abs(alpha(f, x, y) - covered);
      silhouette_sum += error;
      silhouette_worst = std::max(silhouette_worst, error);
      EXPECT_NEAR(alpha(f, x, y), covered, 0.04) << "silhouette pixel " << x << "," << y;
    }
  }
  ASSERT_GT(interior, 250);
  ASSERT_GT(centre, 100);
  ASSERT_GT(terminator, 5);
  EXPECT_LT(std::abs(bias / interior), 2e-4) << "mean relative error: a bias, not noise";
  ASSERT_GT(silhouette, 40);
  ASSERT_GT(empty, 200);
  std::printf(
      "sphere: %d lit interior pixels, worst relative error %.2e, mean %.2e; %d silhouette pixels, coverage "
      "error mean %.4f max %.4f\n",
      interior, worst_interior, bias / interior, silhouette, silhouette_sum / silhouette, silhouette_worst);
  EXPECT_LT(silhouette_sum / silhouette, 0.01);
}

TEST(Reference, StratifiedSamplesConvergeFasterThanRandomOnes) {
  // RMSE against the closed form over the whole image, silhouettes included:
  // stratified jitter falls about as N^-0.75 at edges and faster inside;
  // independent samples would only gain sqrt(16) = 4 from 4 to 64 spp.
  DiffuseSphere low(24, 4), high(24, 64);
  render::Frame f4 = low.render(), f64 = high.render();
  double e4 = 0, e64 = 0;
  for (uint32_t y = 0; y < 24; ++y) {
    for (uint32_t x = 0; x < 24; ++x) {
      auto [radiance, covered, min_cos, min_view] = low.exact(x, y, 64);
      e4 += std::pow(red(f4, x, y) - radiance, 2) + std::pow(alpha(f4, x, y) - covered, 2);
      e64 += std::pow(red(f64, x, y) - radiance, 2) + std::pow(alpha(f64, x, y) - covered, 2);
    }
  }
  e4 = std::sqrt(e4 / (24 * 24)), e64 = std::sqrt(e64 / (24 * 24));
  std::printf("RMSE 4 spp %.5f, 64 spp %.5f, ratio %.3f\n", e4, e64, e64 / e4);
  EXPECT_GT(e4, 0);
  EXPECT_LT(e64, 0.2 * e4);
}

TEST(Reference, SameSeedSameImageOtherSeedOtherJitter) {
  DiffuseSphere sphere(16, 4);
  render::Frame a = sphere.render(), b = sphere.render();
  sphere.settings.seed = 2;
  render::Frame c = sphere.render();
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_NE(a.colour, c.colour);
  EXPECT_EQ(a.covered_pixels, b.covered_pixels);
}

TEST(Reference, ConvexSphereShadowsItselfOnlyWhereTheLightSetsBelowTheHorizon) {
  // Shadow rays leave the surface above it: on a convex body they find it
  // again only when they point below the tangent plane. A point-sized light
  // changes nothing; one of angular radius 0.1 dims the pixels whose
  // footprint sees it less than 0.1 above the horizon, and only those.
  DiffuseSphere sphere(24, 16);
  render::Frame plain = sphere.render();
  sphere.settings.render.shadows = true;
  render::Frame hard = sphere.render();
  sphere.settings.render.lights[0].size = 0.1f;
  render::Frame soft = sphere.render();
  int dimmed = 0;
  for (uint32_t y = 0; y < 24; ++y) {
    for (uint32_t x = 0; x < 24; ++x) {
      const size_t i = size_t(y) * 24 + x;
      ASSERT_NEAR(plain.colour[i].r, hard.colour[i].r, 1e-6f) << "pixel " << x << "," << y;
      if (sphere.exact(x, y, 16).min_cos > std::sin(0.11)) {
        ASSERT_NEAR(plain.colour[i].r, soft.colour[i].r, 1e-6f) << "pixel " << x << "," << y;
      } else {
        EXPECT_LE(soft.colour[i].r, plain.colour[i].r + 1e-6f) << "pixel " << x << "," << y;
        dimmed += soft.colour[i].r < plain.colour[i].r - 1e-6f ? 1 : 0;
      }
    }
  }
  EXPECT_GT(dimmed, 3) << "the soft terminator";
}

// A sphere (centre (0, 0.3, 0), radius 0.2) floating over a plate whose top is y = 0.
class SphereOverPlate : public voxelizer::AnalyticScene {
 public:
  float distance(glm::vec3 p) const override {
    glm::vec3 q = glm::abs(p - glm::vec3(0, -0.05f, 0)) - glm::vec3(1.0f, 0.05f, 1.0f);
    float plate = glm::length(glm::max(q, glm::vec3(0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
    return std::min(plate, glm::length(p - glm::vec3(0, 0.3f, 0)) - 0.2f);
  }
  glm::vec3 colour(glm::vec3) const override { return glm::vec3(0.5f); }
  std::string name() const override { return "sphere-over-plate"; }
  voxelizer::Box bounds() const override { return {glm::vec3(-1, -0.1f, -1), glm::vec3(1, 0.5f, 1)}; }
};

TEST(Reference, HardShadowOfASphereOnAPlate) {
  SphereOverPlate scene;
  ReferenceSettings s;
  s.render.width = s.render.height = 32;
  s.render.camera = test::looking_at_origin({0.0f, 2.5f, 1.2f}, 40.0f);
  const glm::dvec3 light = glm::normalize(glm::dvec3(0.6, 1.0, 0.2));
  s.render.lights = {render::Light{false, glm::vec3(light), glm::vec3(2.0f), 0.0f}};
  s.render.ambient = glm::vec3(0);
  s.render.background = glm::vec3(0);
  s.render.specular = 0;
  s.render.shadows = true;
  s.spp = 64;
  render::Frame f = render_reference(*scene_geometry(scene), s);
  test::save_for_inspection(f, "reference-shadow");
  const glm::dvec3 eye(s.render.camera.eye), centre(0, 0.3, 0);
  int shadowed = 0, lit = 0;
  double sum_error = 0;
  for (uint32_t y = 0; y < 32; ++y) {
    for (uint32_t x = 0; x < 32; ++x) {
      PixelCone p = pixel_cone(s.render.camera, 32, 32, x, y);
      // Exact: the plate point's visibility of the light along `light`.
      double exact = footprint_mean(p, 24, [&](glm::dvec3 d) {
        if (auto t = hit_sphere(eye, d, centre, 0.2)) {
          glm::dvec3 n = glm::normalize(eye + *t * d - centre);
          return 0.5 / kPi * 2.0 * std::max(0.0, glm::dot(n, light));
        }
        if (d.y >= 0) return 0.0;
        glm::dvec3 q = eye + (-eye.y / d.y) * d;
        if (std::abs(q.x) > 1 || std::abs(q.z) > 1) return 0.0;
        bool blocked = hit_sphere(q, light, centre, 0.2).has_value();
        return blocked ? 0.0 : 0.5 / kPi * 2.0 * light.y;
      });
      sum_error += std::abs(red(f, x, y) - exact);
      // Pixels wholly in the shadow or wholly lit plate agree tightly.
      glm::dvec3 q = eye + (-eye.y / p.axis.y) * p.axis;
      glm::dvec3 to_centre = centre - q;
      double miss = glm::length(to_centre - glm::dot(to_centre, light) * light);  // shadow line to centre
      bool on_plate = !hit_sphere(eye, p.axis, centre, 0.24) && std::abs(q.x) < 0.9 && std::abs(q.z) < 0.9;
      if (on_plate && miss < 0.15) {
        ++shadowed;
        EXPECT_NEAR(red(f, x, y), 0.0f, 1e-6f) << "shadowed pixel " << x << "," << y;
      } else if (on_plate && miss > 0.26) {
        ++lit;
        EXPECT_NEAR(red(f, x, y), 0.5 / kPi * 2.0 * light.y, 1e-4) << "lit pixel " << x << "," << y;
      }
    }
  }
  EXPECT_GT(shadowed, 4);
  EXPECT_GT(lit, 200);
  std::printf("shadow: %d shadowed and %d lit plate pixels, mean absolute error %.2e\n", shadowed, lit,
              sum_error / (32 * 32));
  EXPECT_LT(sum_error / (32 * 32), 2e-3) << "mean absolute error against the exact shadowed image";
}

TEST(Reference, ThinLensBlursAStraightEdgeByTheLensDisk) {
  // A plate facing the camera at distance 3 with its edge on the optical
  // axis, the lens focused at 2: each pixel sees a disk of radius
  // A |t - f| / f = 0.01 on the plate (8 pixels here) around where its
  // pinhole ray meets it, so its coverage is the part of that disk on the
  // plate, (acos(x/R) - x/R sqrt(1 - (x/R)^2)) / pi at distance x from the edge.
  test::BoxScene plate({-1.0f, -1.0f, -0.01f}, {0.0f, 1.0f, 0.01f});
  ReferenceSettings s;
  s.render.width = 64;
  s.render.height = 4;
  const double pixel = 0.00125, t = 3.0;  // pixel side on the plate
  s.render.camera = test::looking_at_origin({0.0f, 0.0f, float(t + 0.01)}, 0.0f);
  s.render.camera.fov_deg = float(2 * std::atan(pixel * 4 / 2 / t) * 180 / kPi);
  s.render.camera.aperture = 0.02f;
  s.render.camera.focus = 2.0f;
  s.spp = 256;
  const double radius = 0.02 * (t - 2.0) / 2.0;
  render::Frame f = render_reference(*scene_geometry(plate), s);
  double worst = 0;
  for (uint32_t x = 0; x < 64; ++x) {
    double at = (x + 0.5 - 32) * pixel;  // signed distance of the pixel's pinhole point from the edge
    double u = std::clamp(std::abs(at) / radius, 0.0, 1.0);
    double beyond = (std::acos(u) - u * std::sqrt(1 - u * u)) / kPi;  // disk part across the edge
    double expected = at > 0 ? beyond : 1 - beyond;
    for (uint32_t y = 0; y < 4; ++y) worst = std::max(worst, std::abs(double(alpha(f, x, y)) - expected));
    EXPECT_NEAR(alpha(f, x, 1), expected, 0.03) << "column " << x;
  }
  std::printf("thin lens: worst coverage error %.4f across the blurred edge\n", worst);
  // Focused on the plate, the edge is as sharp as the pinhole's.
  s.render.camera.focus = float(t);
  render::Frame sharp = render_reference(*scene_geometry(plate), s);
  EXPECT_GT(alpha(sharp, 30, 1), 0.999f);
  EXPECT_LT(alpha(sharp, 33, 1), 0.001f);
}

// The cube [-0.5, 0.5]^3 as 12 outward-facing triangles (OFF).
std::string cube_off() {
  const int corners[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                             {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  const int triangles[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
  std::string s = "OFF\n8 12 0\n";
  for (auto& c : corners)
    s += std::to_string(0.5 * c[0]) + " " + std::to_string(0.5 * c[1]) + " " + std::to_string(0.5 * c[2]) + "\n";
  for (auto& t : triangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return s;
}

TEST(Reference, EmbreeMeshMatchesTheSphereTracedBox) {
  render::testing::TempDir dir;
  std::ofstream(dir / "cube.off") << cube_off();
  voxelizer::MeshOptions options;
  options.colour = glm::vec3(0.6f);
  options.sigma_rho = 0.1f;
  test::BoxScene box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f});
  box.set_sigma_rho2(0.01f);
  ReferenceSettings s;
  s.render.width = s.render.height = 32;
  s.render.camera = test::looking_at_origin({1.6f, 1.3f, 2.0f}, 40.0f);
  s.render.shadows = true;
  s.spp = 16;
  render::Frame analytic = render_reference(*scene_geometry(box), s);
  render::Frame mesh = render_reference(*mesh_geometry(voxelizer::read_mesh(dir / "cube.off", options)), s);
  test::save_for_inspection(mesh, "reference-mesh-cube");
  ASSERT_EQ(analytic.covered_pixels, mesh.covered_pixels);
  double sum = 0, worst = 0;
  for (size_t i = 0; i < mesh.colour.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      double d = std::abs(double(mesh.colour[i][c]) - double(analytic.colour[i][c]));
      sum += d;
      worst = std::max(worst, d);
    }
  }
  std::printf("mesh vs analytic box: mean %.2e, max %.2e\n", sum / (4.0 * mesh.colour.size()), worst);
  EXPECT_LT(sum / (4.0 * mesh.colour.size()), 1e-4);
  EXPECT_LT(worst, 0.02);
}

TEST(Reference, RefusesBadSettingsWithAMessage) {
  test::SphereScene sphere(0.5f);
  auto geometry = scene_geometry(sphere);
  ReferenceSettings s;
  s.render.width = 8;
  s.render.height = 8;
  s.spp = 0;
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
  s.spp = 1;
  s.render.width = 0;
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
  s.render.width = 8;
  s.render.lights.assign(render::kMaxLights + 1, render::Light{});
  EXPECT_THROW(render_reference(*geometry, s), std::invalid_argument);
  s.render.lights = {render::Light{}};
  s.render.camera.target = s.render.camera.eye;
  try {
    render_reference(*geometry, s);
    FAIL() << "a camera whose eye is its target was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("camera"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace svo::reference
