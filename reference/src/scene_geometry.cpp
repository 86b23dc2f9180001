// Sphere tracing of the procedural scenes' own distance functions (Hart
// 1996): ground truth for the scenes without any lattice in between.
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "svo/reference/geometry.h"

namespace svo::reference {

namespace {

// [t0, t1] where the ray o + t d crosses the box, or t0 > t1 when it misses.
void clip_to_box(glm::dvec3 o, glm::dvec3 d, glm::dvec3 lo, glm::dvec3 hi, double& t0, double& t1) {
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) {
      if (o[axis] < lo[axis] || o[axis] > hi[axis]) t0 = std::numeric_limits<double>::infinity();
      continue;
    }
    double a = (lo[axis] - o[axis]) / d[axis], b = (hi[axis] - o[axis]) / d[axis];
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
}

class SceneGeometry : public Geometry {
 public:
  explicit SceneGeometry(const voxelizer::AnalyticScene& scene) : scene_(scene) {
    voxelizer::Box b = scene.bounds();
    glm::dvec3 lo(b.lo), hi(b.hi);
    extent_ = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9});
    lo_ = lo - 0.02 * extent_;
    hi_ = hi + 0.02 * extent_;
    epsilon_ = 1e-6 * extent_;
  }

  std::optional<SurfaceHit> intersect(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const override {
    const std::optional<double> first = march(o, d, t_min, t_max);
    if (!first) return std::nullopt;
    const double t = refine(o, d, *first);
    SurfaceHit hit;
    hit.t = t;
    hit.position = o + t * d;
    const glm::vec3 p(hit.position);
    hit.normal = scene_.normal(p);
    if (glm::dot(glm::dvec3(hit.normal), d) > 0) hit.normal = -hit.normal;  // grazing hits of a noisy gradient
    hit.colour = scene_.colour(p);
    hit.material = scene_.material(p);
    return hit;
  }

  bool occluded(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const override {
    return march(o, d, t_min, t_max).has_value();
  }

  float sigma_rho2() const override { return scene_.sigma_rho2(); }
  voxelizer::Box bounds() const override { return scene_.bounds(); }
  std::vector<std::string> materials() const override { return scene_.materials(); }
  double shadow_offset() const override { return 20 * epsilon_; }

 private:
  // Where the ray first comes within epsilon of the surface, if it does.
  // Sphere tracing with over-relaxation (Keinert et al. 2014, "Enhanced
  // Sphere Tracing"): no sphere of radius |f| / L around a point holds a
  // surface point (|f(p) - f(q)| <= L |p - q|), so a step longer than
  // |f| / L is kept only when the sphere around its end overlaps the one it
  // started from; otherwise the march goes back and takes the safe step.
  std::optional<double> march(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const {
    double t0 = t_min, t1 = t_max;
    clip_to_box(o, d, lo_, hi_, t0, t1);
    if (!(t0 <= t1)) return std::nullopt;
    double t = t0, radius = 0, step = 0;
    bool relaxed = false;  // whether the step that led to t was longer than safe
    for (int i = 0; i < kMaxSteps; ++i) {
      if (t > t1) {
        // Past the end: only the safe step from the last point proves the rest empty.
        if (!relaxed || radius >= t1 - (t - step)) return std::nullopt;
        t += radius - step;
        step = radius;
        relaxed = false;
        continue;
      }
      const glm::dvec2 bound = scene_.distance_bound(glm::vec3(o + t * d));
      const double f = bound.x, r = bound.y;
      if (relaxed && radius + r < step) {
        // The two spheres leave a gap: back to the safe step from the last point.
        t += radius - step;
        step = radius;
        relaxed = false;
        continue;
      }
      if (f < epsilon_) return t;
      radius = r;
      step = kRelaxation * r;
      relaxed = true;
      t += step;
    }
    return std::nullopt;
  }

  // Newton steps along the ray onto f = 0, taken only while the ray clearly
  // enters the surface (a grazing ray keeps the sphere-traced point, within
  // epsilon of the surface) and by at most a few epsilon each.
  double refine(glm::dvec3 o, glm::dvec3 d, double t) const {
    for (int i = 0; i < 4; ++i) {
      const glm::vec4 fg = scene_.distance_gradient(glm::vec3(o + t * d));
      const glm::dvec3 g(fg);
      const double along = glm::dot(g, d), f = fg.w;
      if (!(along < -0.1 * glm::length(g))) break;
      const double dt = std::clamp(-f / along, -4 * epsilon_, 4 * epsilon_);
      t += dt;
      if (std::abs(dt) < 1e-3 * epsilon_) break;
    }
    return t;
  }

  static constexpr int kMaxSteps = 1 << 20;
  static constexpr double kRelaxation = 1.6;
  const voxelizer::AnalyticScene& scene_;
  glm::dvec3 lo_, hi_;
  double extent_ = 1, epsilon_ = 1e-6;
};

}  // namespace

std::unique_ptr<Geometry> scene_geometry(const voxelizer::AnalyticScene& scene) {
  return std::make_unique<SceneGeometry>(scene);
}

}  // namespace svo::reference
