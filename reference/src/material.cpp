#include "svo/reference/material.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/shared_math.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"

namespace svo::reference {

render::RenderSettings material_view(float degrees, uint32_t height, const MaterialOptions& o) {
  const float t = glm::radians(degrees);
  render::RenderSettings s;
  s.width = std::max(1u, uint32_t(std::lround(double(height) * std::cos(t))));
  s.height = height;
  s.camera.eye = o.distance * glm::vec3(std::sin(t), 0.0f, std::cos(t));
  s.camera.target = glm::vec3(0);
  s.camera.up = glm::vec3(0, 1, 0);
  s.camera.fov_deg = glm::degrees(2.0f * std::atan(0.5f * o.patch / o.distance));
  s.lights.clear();
  s.ambient = glm::vec3(1);
  s.specular = 0;
  s.background = glm::vec3(0);
  return s;
}

std::vector<MaterialPoint> material_curve(const voxelizer::HeightfieldScene& field, const MaterialOptions& o) {
  MaterialStatistics s;
  s.slope_variance = field.slope_variance();
  s.abar = field.abar();
  s.a_s = field.a_s();
  return material_curve(field, s, o);
}

std::vector<MaterialPoint> material_curve(const voxelizer::AnalyticScene& field, const MaterialStatistics& stats,
                                          const MaterialOptions& o) {
  for (float d : o.degrees) {
    if (!(d >= 0 && d < 90)) throw std::invalid_argument("material: angle " + std::to_string(d) + " outside [0, 90)");
  }
  if (!(o.patch > 0 && o.patch <= 1.9f)) {
    throw std::invalid_argument("material: a patch of " + std::to_string(o.patch) + " does not fit the field [-1, 1]^2");
  }
  auto geometry = scene_geometry(field);
  const glm::vec2 sigma2 = stats.slope_variance;
  std::vector<MaterialPoint> points;
  for (size_t i = 0; i < o.degrees.size(); ++i) {
    MaterialPoint p;
    p.degrees = o.degrees[i];
    ReferenceSettings rs;
    rs.render = material_view(p.degrees, o.size, o);
    rs.spp = o.spp;
    render::Frame f = render_reference(*geometry, rs);
    glm::dvec3 sum(0);
    double covered = 0;
    for (const auto& c : f.colour) sum += glm::dvec3(c.r, c.g, c.b), covered += c.a;
    if (!(covered > 0)) throw std::runtime_error("material: the reference at " + std::to_string(p.degrees) + " degrees sees nothing");
    // The background is black: the mean over the surface seen.
    p.truth = glm::vec3(sum / covered);
    const float t = glm::radians(p.degrees);
    const glm::vec3 v(std::sin(t), 0.0f, std::cos(t));  // towards the eye, in the field's frame (normal +z)
    const float lambda = svo::math::svo_smith_lambda_dir(v, sigma2);
    p.eq17 = svo::math::svo_attribute_vl3(stats.abar, stats.a_s, lambda);
    p.mip = stats.abar;
    points.push_back(p);
    if (o.progress) o.progress(double(i + 1) / double(o.degrees.size()));
  }
  return points;
}

}  // namespace svo::reference
