#pragma once
// Bumps on a sphere, b(u) = sum_k A_k sin(f_k w_k . u + phi_k) for unit
// directions u: random directions w_k, equal amplitudes A_k = sigma
// sqrt(2 / count) (so that b has deviation sigma), frequencies f_k per
// radian of arc. The built-in bumpy sphere and the fine bumpy sphere of the
// figure benches are both a sphere of radius R displaced by such bumps.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace svo::voxelizer {

class SineBumps {
 public:
  // `frequency` maps a uniform draw in [0, 1) to f_k; the draws come from
  // std::mt19937(seed) in a fixed order, so a seed names one surface.
  template <class Frequency>
  SineBumps(float sigma, int count, unsigned seed, Frequency frequency) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float amplitude = sigma * std::sqrt(2.0f / float(count));
    for (int i = 0; i < count; ++i) {
      float z = 2 * u(rng) - 1, phi = 2 * float(M_PI) * u(rng), r = std::sqrt(std::max(0.0f, 1 - z * z));
      float f = frequency(u(rng));
      bumps_.push_back({amplitude, glm::vec3(r * std::cos(phi), r * std::sin(phi), z) * f, 2 * float(M_PI) * u(rng)});
      max_slope_ += amplitude * f;
    }
  }

  // b(u) at unit direction u.
  float height(glm::vec3 u) const {
    float b = 0;
    for (const auto& k : bumps_) b += k.amplitude * std::sin(glm::dot(k.frequency, u) + k.phase);
    return b;
  }

  // Bound on |grad b| over the unit sphere (sum of A_k f_k).
  float max_slope() const { return max_slope_; }

  // f(p) = |p| - (radius + b(p / |p|)).
  float sphere_distance(glm::vec3 p, float radius) const {
    float r = glm::length(p);
    if (r < 1e-6f) return -radius;
    return r - (radius + height(p / r));
  }

  // (grad f, f): grad f = u - (I - u u^T) grad b / r, u = p / r.
  glm::vec4 sphere_distance_gradient(glm::vec3 p, float radius) const {
    float r = glm::length(p);
    if (r < 1e-6f) return glm::vec4(0, 0, 1, -radius);
    glm::vec3 u = p / r, gb(0);
    float b = 0;
    for (const auto& k : bumps_) {
      float phase = glm::dot(k.frequency, u) + k.phase;
      b += k.amplitude * std::sin(phase);
      gb += k.amplitude * std::cos(phase) * k.frequency;
    }
    glm::vec3 tangential = (gb - u * glm::dot(u, gb)) / r;
    return glm::vec4(u - tangential, r - (radius + b));
  }

 private:
  struct Bump {
    float amplitude;
    glm::vec3 frequency;
    float phase;
  };
  std::vector<Bump> bumps_;
  float max_slope_ = 0;
};

}  // namespace svo::voxelizer
