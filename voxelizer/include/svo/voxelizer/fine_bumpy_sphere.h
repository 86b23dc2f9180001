// A sphere with fine bumps for the paper's Figs. 11 and 12 as bench cases
// (svo bench fig11, fig12): the built-in bumpy sphere's construction with
// wavelengths a few times shorter, so that the bumps fall below a pixel at
// moderate distances while a 256^3 or 512^3 octree still resolves them.
// Colour follows the bump height, a(h) = abar + a_s erf(h / (sqrt(2) sigma)).
#pragma once

#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "svo/voxelizer/scenes.h"
#include "svo/voxelizer/sine_bumps.h"

namespace svo::voxelizer {

class FineBumpySphere : public AnalyticScene {
 public:
  struct Options {
    float radius = 0.7f;
    float sigma = 0.0025f;         // deviation of the bump height, scene units
    int bumps = 32;                // sines of random directions on the unit sphere
    float min_frequency = 120.0f;  // per radian of arc: wavelength 2 pi radius / frequency
    float max_frequency = 200.0f;
    unsigned seed = 7;
    glm::vec3 abar{0.45f, 0.4f, 0.08f};  // yellow on average ...
    glm::vec3 a_s{-0.35f, 0.3f, 0.03f};  // ... red in the valleys, green on the crests (paper Fig. 11)
  };
  explicit FineBumpySphere(const Options& options);

  // Bump height at unit direction u.
  float bump(glm::vec3 u) const;
  float radius() const { return o_.radius; }
  float sigma() const { return o_.sigma; }

  float distance(glm::vec3 p) const override;
  glm::vec4 distance_gradient(glm::vec3 p) const override;
  float lipschitz() const override { return lipschitz_; }
  glm::vec3 colour(glm::vec3 surface_point) const override;
  Box bounds() const override;
  std::string name() const override { return "fine-bumpy-sphere"; }

 private:
  Options o_;
  SineBumps bumps_;
  float lipschitz_ = 1;
};

}  // namespace svo::voxelizer
