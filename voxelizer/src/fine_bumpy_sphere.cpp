#include "svo/voxelizer/fine_bumpy_sphere.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <random>
#include <stdexcept>

#include "common/shared_math.h"

namespace svo::voxelizer {

namespace {

FineBumpySphere::Options checked(const FineBumpySphere::Options& o) {
  if (!(o.radius > 0) || !(o.sigma >= 0) || o.bumps < 1 || !(o.min_frequency > 0) ||
      !(o.max_frequency >= o.min_frequency)) {
    throw std::invalid_argument("fine-bumpy-sphere: radius > 0, sigma >= 0, bumps >= 1, 0 < min <= max frequency");
  }
  return o;
}

}  // namespace

// Frequencies log-uniform between the two bounds.
FineBumpySphere::FineBumpySphere(const Options& o)
    : o_(checked(o)), bumps_(o.sigma, o.bumps, o.seed, [&o](float u) {
        return o.min_frequency * std::pow(o.max_frequency / o.min_frequency, u);
      }) {
  // |grad b| / r for r >= half the radius.
  lipschitz_ = std::sqrt(1.0f + bumps_.max_slope() * bumps_.max_slope() / (0.25f * o.radius * o.radius));
}

float FineBumpySphere::bump(glm::vec3 dir) const { return bumps_.height(dir); }

float FineBumpySphere::distance(glm::vec3 p) const { return bumps_.sphere_distance(p, o_.radius); }

glm::vec4 FineBumpySphere::distance_gradient(glm::vec3 p) const { return bumps_.sphere_distance_gradient(p, o_.radius); }

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
