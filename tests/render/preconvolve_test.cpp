// The pre-convolved environment (render::preconvolve_environment): a
// constant map stays constant at every level, and each level matches the
// convolution of the full map by brute-force quadrature over all its texels.
#include <gtest/gtest.h>

#include <cmath>

#include "svo/render/shading.h"
#include "test_lighting.h"

namespace svo::render {
namespace {

glm::dvec3 direction(double u, double v) {
  const double phi = 2.0 * M_PI * u, theta = M_PI * v;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

// The map convolved with the normalised kernel k(cos) at d, over every texel.
template <class Kernel>
glm::dvec3 quadrature(const Environment& env, glm::dvec3 d, Kernel kernel) {
  glm::dvec3 sum(0);
  double total = 0;
  for (uint32_t y = 0; y < env.height; ++y)
    for (uint32_t x = 0; x < env.width; ++x) {
      const double v = (y + 0.5) / env.height;
      const double w = kernel(glm::dot(d, direction((x + 0.5) / env.width, v))) * std::sin(M_PI * v);
      const float* c = &env.rgb[(size_t(y) * env.width + x) * 3];
      sum += w * glm::dvec3(c[0], c[1], c[2]);
      total += w;
    }
  return sum / total;
}

// A level read bilinearly at (u, v), as environment.glsl does.
glm::dvec3 bilinear(const PreconvolvedEnvironment::Level& l, double u, double v) {
  const double fx = u * l.width - 0.5, fy = std::clamp(v * l.height - 0.5, 0.0, double(l.height - 1));
  const double x0f = std::floor(fx), tx = fx - x0f;
  const uint32_t y0 = uint32_t(fy), y1 = std::min(y0 + 1, l.height - 1);
  const double ty = fy - y0;
  const uint32_t x0 = uint32_t(int(x0f) + int(l.width)) % l.width, x1 = (x0 + 1) % l.width;
  auto at = [&](uint32_t x, uint32_t y) {
    const float* c = &l.rgb[(size_t(y) * l.width + x) * 3];
    return glm::dvec3(c[0], c[1], c[2]);
  };
  return glm::mix(glm::mix(at(x0, y0), at(x1, y0), tx), glm::mix(at(x0, y1), at(x1, y1), tx), ty);
}

TEST(Preconvolve, AConstantMapStaysConstantAtEveryLevel) {
  const PreconvolvedEnvironment pre =
      preconvolve_environment(constant_environment(glm::vec3(0.5f, 1.0f, 2.0f), 64, 32));
  ASSERT_GE(pre.levels.size(), 4u);
  EXPECT_EQ(pre.levels.front().sharpness, 1.0f);
  for (size_t k = 0; k + 1 < pre.levels.size(); ++k)
    EXPECT_EQ(pre.levels[k + 1].sharpness, 2 * pre.levels[k].sharpness);
  for (size_t k = 0; k <= pre.levels.size(); ++k) {
    const auto& l = k < pre.levels.size() ? pre.levels[k] : pre.irradiance;
    ASSERT_EQ(l.rgb.size(), size_t(l.width) * l.height * 3);
    for (size_t i = 0; i < l.rgb.size(); i += 3) {
      ASSERT_NEAR(l.rgb[i], 0.5f, 1e-5f) << "level " << k;
      ASSERT_NEAR(l.rgb[i + 1], 1.0f, 1e-5f) << "level " << k;
      ASSERT_NEAR(l.rgb[i + 2], 2.0f, 1e-5f) << "level " << k;
    }
  }
}

// The sky's sun (radiance 40 over 3x2 texels) and its horizon are the hard
// parts: each level against the quadrature over the full map, at
// directions between texels. A level is the map resampled to two texels
// per lobe deviation and convolved there, so it errs by a few percent of
// the largest value near the sun at most (1-3% RMS here).
TEST(Preconvolve, LevelsMatchQuadratureOfTheFullMap) {
  const Environment env = test::sky(128, 64);
  const PreconvolvedEnvironment pre = preconvolve_environment(env);
  double worst_relative = 0;
  for (size_t k = 0; k <= pre.levels.size(); ++k) {
    const auto& l = k < pre.levels.size() ? pre.levels[k] : pre.irradiance;
    double err2 = 0, ref2 = 0, worst = 0, peak = 0;
    for (int i = 0; i < 97; ++i) {
      const double u = std::fmod(0.137 + i * 0.618034, 1.0), v = 0.02 + 0.96 * std::fmod(0.31 + i * 0.3819, 1.0);
      const glm::dvec3 d = direction(u, v);
      const glm::dvec3 want = l.sharpness > 0
                                  ? quadrature(env, d, [&](double c) { return std::exp(l.sharpness * (c - 1.0)); })
                                  : quadrature(env, d, [](double c) { return std::max(c, 0.0); });
      const glm::dvec3 got = bilinear(l, u, v);
      ASSERT_TRUE(std::isfinite(got.x) && std::isfinite(got.y) && std::isfinite(got.z));
      err2 += glm::dot(got - want, got - want);
      ref2 += glm::dot(want, want);
      worst = std::max(worst, glm::length(got - want));
      peak = std::max(peak, glm::length(want));
    }
    const double rel = std::sqrt(err2 / ref2);
    std::printf("sharpness %6.0f (%ux%u): relative RMS error %.4f, worst %.4f of the peak %.3f\n", l.sharpness, l.width,
                l.height, rel, worst / peak, peak);
    worst_relative = std::max(worst_relative, rel);
    EXPECT_LT(rel, 0.04) << "sharpness " << l.sharpness;
  }
  EXPECT_GT(worst_relative, 0.0);
}

}  // namespace
}  // namespace svo::render
