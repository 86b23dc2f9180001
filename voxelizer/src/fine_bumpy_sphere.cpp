#include "svo/voxelizer/fine_bumpy_sphere.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <random>
#include <stdexcept>

#include "common/shared_math.h"

namespace svo::voxelizer {

FineBumpySphere::FineBumpySphere(const Options& o) : o_(o) {
  if (!(o.radius > 0) || !(o.sigma >= 0) || o.bumps < 1 || !(o.min_frequency > 0) ||
      !(o.max_frequency >= o.min_frequency)) {
    throw std::invalid_argument("fine-bumpy-sphere: radius > 0, sigma >= 0, bumps >= 1, 0 < min <= max frequency");
  }
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float amplitude = o.sigma * std::sqrt(2.0f / float(o.bumps));
  float max_slope = 0;
  for (int i = 0; i < o.bumps; ++i) {
    float z = 2 * u(rng) - 1, phi = 2 * float(M_PI) * u(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
    float f = o.min_frequency * std::pow(o.max_frequency / o.min_frequency, u(rng));
    bumps_.push_back({amplitude, glm::vec3(r * std::cos(phi), r * std::sin(phi), z) * f, 2 * float(M_PI) * u(rng)});
    max_slope += amplitude * f;
  }
  // |grad b| / r for r >= half the radius.
  lipschitz_ = std::sqrt(1.0f + max_slope * max_slope / (0.25f * o.radius * o.radius));
}

float FineBumpySphere::bump(glm::vec3 dir) const {
  float b = 0;
  for (const auto& k : bumps_) b += k.amplitude * std::sin(glm::dot(k.frequency, dir) + k.phase);
  return b;
}

float FineBumpySphere::distance(glm::vec3 p) const {
  float r = glm::length(p);
  if (r < 1e-6f) return -o_.radius;
  return r - (o_.radius + bump(p / r));
}

// grad f = u - (I - u u^T) grad b / r, u = p / r.
glm::vec4 FineBumpySphere::distance_gradient(glm::vec3 p) const {
  float r = glm::length(p);
  if (r < 1e-6f) return glm::vec4(0, 0, 1, -o_.radius);
  glm::vec3 u = p / r, gb(0);
  float b = 0;
  for (const auto& k : bumps_) {
    float phase = glm::dot(k.frequency, u) + k.phase;
    b += k.amplitude * std::sin(phase);
    gb += k.amplitude * std::cos(phase) * k.frequency;
  }
  glm::vec3 tangential = (gb - u * glm::dot(u, gb)) / r;
  return glm::vec4(u - tangential, r - (o_.radius + b));
}

glm::vec3 FineBumpySphere::colour(glm::vec3 q) const {
  float r = glm::length(q);
  float h = r > 0 ? bump(q / r) : 0.0f;
  return o_.abar + o_.a_s * svo::math::svo_height_sigmoid(h, o_.sigma);
}

Box FineBumpySphere::bounds() const {
  float r = o_.radius + 5 * o_.sigma;
  return {glm::vec3(-r), glm::vec3(r)};
}

}  // namespace svo::voxelizer
