// The Beckmann NDF and its Smith masking: normalisation, the projected-area
// identity that makes G1 "matching" (Heitz 2014, Eq. 2 of "Understanding the
// masking-shadowing function"), reciprocity and energy conservation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "common/shared_math.h"

namespace {
using namespace svo::math;

// Integrates f(m) over the upper hemisphere in slope space: m = (-px, -py, 1)
// normalised, d omega = cos^3(theta_m) dp. Midpoint rule over +-extent.
template <class F>
double integrate_slopes(F f, double extent_x, double extent_y, int n) {
  double sum = 0, dx = 2 * extent_x / n, dy = 2 * extent_y / n;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      double px = -extent_x + (i + 0.5) * dx, py = -extent_y + (j + 0.5) * dy;
      double inv = 1.0 / std::sqrt(1 + px * px + py * py);
      vec3 m(float(-px * inv), float(-py * inv), float(inv));
      sum += f(m) * inv * inv * inv * dx * dy;
    }
  }
  return sum;
}

struct Roughness {
  float sx2, sy2;
};

class BeckmannTest : public ::testing::TestWithParam<Roughness> {};

TEST_P(BeckmannTest, NdfProjectsToUnitArea) {
  vec2 s2(GetParam().sx2, GetParam().sy2);
  double ex = 9 * std::sqrt(double(s2.x)), ey = 9 * std::sqrt(double(s2.y));
  double area = integrate_slopes([&](vec3 m) { return double(svo_beckmann_d(m, s2)) * m.z; }, ex, ey, 1200);
  EXPECT_NEAR(area, 1.0, 1e-3);
}

// int G1(v) <v.m> D(m) dm = v.z: the Smith G1 built from our Lambda is the
// one that matches this D. Fails if Lambda, the variance convention
// (alpha^2 = 2 sigma^2) or the projected-variance rule is wrong.
TEST_P(BeckmannTest, SmithG1MatchesTheNdfProjectedArea) {
  vec2 s2(GetParam().sx2, GetParam().sy2);
  double ex = 9 * std::sqrt(double(s2.x)), ey = 9 * std::sqrt(double(s2.y));
  for (float theta : {0.2f, 0.8f, 1.2f, 1.45f}) {
    for (float phi : {0.0f, 0.9f, 1.5708f}) {
      vec3 v(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      double projected = integrate_slopes(
          [&](vec3 m) { return double(svo_beckmann_d(m, s2)) * std::max(0.0f, dot(v, m)); }, ex, ey, 1200);
      double g1 = svo_smith_g1(svo_smith_lambda_dir(v, s2));
      EXPECT_NEAR(g1 * projected / v.z, 1.0, 2e-3) << "theta " << theta << " phi " << phi;
    }
  }
}

TEST_P(BeckmannTest, ReciprocalAndEnergyConserving) {
  vec2 s2(GetParam().sx2, GetParam().sy2);
  vec3 a = normalize(vec3(0.4f, -0.3f, 0.8f));
  vec3 b = normalize(vec3(-0.7f, 0.1f, 0.5f));
  EXPECT_FLOAT_EQ(svo_specular_brdf(a, b, s2), svo_specular_brdf(b, a, s2));
  // Directional albedo int f(v, l) l.z dl <= 1 (single scattering loses energy, never gains).
  for (float theta : {0.0f, 0.6f, 1.2f}) {
    vec3 v(std::sin(theta), 0.0f, std::cos(theta));
    double albedo = 0;
    const int n = 400;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < 2 * n; ++j) {
        double t = (i + 0.5) * (M_PI / 2) / n, p = (j + 0.5) * M_PI / n;
        vec3 l(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t)));
        albedo += svo_specular_brdf(v, l, s2) * l.z * std::sin(t) * (M_PI / 2 / n) * (M_PI / n);
      }
    }
    EXPECT_LE(albedo, 1.0 + 5e-3) << "theta " << theta;
    EXPECT_GT(albedo, 0.3) << "theta " << theta;
  }
}

std::string roughness_name(const ::testing::TestParamInfo<Roughness>& info) {
  auto digits = [](float s2) { return std::to_string(int(std::lround(s2 * 1000))); };
  return "var_x" + digits(info.param.sx2) + "e3_y" + digits(info.param.sy2) + "e3";
}

INSTANTIATE_TEST_SUITE_P(Isotropic, BeckmannTest,
                         ::testing::Values(Roughness{0.01f, 0.01f}, Roughness{0.1f, 0.1f}, Roughness{0.5f, 0.5f}),
                         roughness_name);
INSTANTIATE_TEST_SUITE_P(Anisotropic, BeckmannTest, ::testing::Values(Roughness{0.02f, 0.3f}), roughness_name);

TEST(Beckmann, VariancesAdd) {
  vec2 total = svo_total_slope_variance(vec2(0.02f, 0.05f), vec2(0.01f));
  EXPECT_FLOAT_EQ(total.x, 0.03f);
  EXPECT_FLOAT_EQ(total.y, 0.06f);
  EXPECT_EQ(svo_total_slope_variance(vec2(0.0f), vec2(0.0f)).x, SVO_MIN_SLOPE_VARIANCE);
  // Rougher lobe: lower peak, wider spread.
  vec3 n(0.0f, 0.0f, 1.0f);
  vec3 tilted = normalize(vec3(0.3f, 0.0f, 1.0f));
  EXPECT_GT(svo_beckmann_d(n, vec2(0.01f)), svo_beckmann_d(n, vec2(0.05f)));
  EXPECT_LT(svo_beckmann_d(tilted, vec2(0.01f)), svo_beckmann_d(tilted, vec2(0.05f)));
}

// Unit direction at polar angle theta, azimuth phi.
glm::dvec3 direction(double theta, double phi) {
  return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Monte Carlo over n Gaussian slopes of per-axis variances var: the mean of
// max(l.m, 0) max(v.m, 0) / (m.n), divided by v.n (no masking).
double lambert_over_slopes(glm::dvec3 v, glm::dvec3 l, glm::dvec2 var, int n, std::mt19937_64& rng) {
  std::normal_distribution<double> z(0.0, 1.0);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    glm::dvec3 m = glm::normalize(glm::dvec3(-std::sqrt(var.x) * z(rng), -std::sqrt(var.y) * z(rng), 1.0));
    sum += std::max(glm::dot(l, m), 0.0) * std::max(glm::dot(v, m), 0.0) / m.z;
  }
  return sum / n / v.z;
}

// svo_rough_lambert against Monte Carlo of the mean of (l.m)(v.m) / (m.n)
// over Gaussian slopes, divided by v.n (facets facing away from v or l
// contribute nothing): within 1% up to slope variance 0.05 per axis and
// 60 degrees, where the first-order form holds.
TEST(RoughLambert, MatchesTheMeanOverGaussianSlopes) {
  std::mt19937_64 rng(21);
  double worst = 0;
  for (glm::dvec2 var : {glm::dvec2(0.005, 0.005), glm::dvec2(0.02, 0.02), glm::dvec2(0.05, 0.01)}) {
    for (int c = 0; c < 6; ++c) {
      glm::dvec3 v = direction(0.2 * c, 0.9 * c), l = direction(1.05 - 0.15 * c, 2.0 + 0.7 * c);
      double mc = lambert_over_slopes(v, l, var, 400000, rng);
      double ours = svo::math::svo_rough_lambert(glm::vec3(v), glm::vec3(l), glm::vec2(var));
      worst = std::max(worst, std::abs(ours / mc - 1.0));
      EXPECT_NEAR(ours / mc, 1.0, 0.01) << "variance " << var.x << ", " << var.y << ", case " << c;
      // The macro-normal cosine is off by more where the slopes matter.
      if (var.x >= 0.02) {
        EXPECT_GT(std::abs(l.z / mc - 1.0), std::abs(ours / mc - 1.0)) << "case " << c;
      }
    }
  }
  std::printf("rough Lambert: worst relative difference %.4f\n", worst);
}

// Near and past the mean plane's terminator (light 80 to 100 degrees from
// the mean normal) the facets that still face the light keep the mean
// above zero; the clamped macro-normal cosine goes dark there.
TEST(RoughLambert, FollowsTheTruthAcrossTheTerminator) {
  std::mt19937_64 rng(23);
  for (double var : {0.01, 0.03, 0.1}) {
    for (double degrees : {80.0, 85.0, 90.0, 95.0, 100.0}) {
      glm::dvec3 v = direction(0.4, 1.0), l = direction(glm::radians(degrees), 2.5);
      double mc = lambert_over_slopes(v, l, glm::dvec2(var), 400000, rng);
      double ours = svo::math::svo_rough_lambert(glm::vec3(v), glm::vec3(l), glm::vec2(float(var)));
      // Within 8% of the truth, or 0.001 where it is that dark.
      EXPECT_NEAR(ours, mc, std::max(0.08 * mc, 0.001)) << "variance " << var << ", light at " << degrees;
    }
  }
}

// Beyond the cap (variance 0.1 per axis) the factor stays between the
// macro-normal cosine and the true mean, or within 4% of the truth.
TEST(RoughLambert, StaysNearTheTruthForLargeSlopes) {
  std::mt19937_64 rng(22);
  for (double var : {0.3, 1.0, 3.0}) {
    for (int c = 0; c < 4; ++c) {
      glm::dvec3 v = direction(0.25 * c, 0.3 + c), l = direction(1.2 - 0.25 * c, 2.0 - 0.5 * c);
      double mc = lambert_over_slopes(v, l, glm::dvec2(var), 200000, rng);
      double ours = svo::math::svo_rough_lambert(glm::vec3(v), glm::vec3(l), glm::vec2(float(var)));
      EXPECT_LE(std::abs(ours - mc), std::abs(l.z - mc) + 0.04 * mc) << "variance " << var << ", case " << c;
    }
  }
}

}  // namespace
