// The SG fit of measured BRDFs (fit_merl_sg, Tokuyoshi 2015 section 4.1):
// tables of analytic BRDFs whose half-vector profile is known, a
// Lambertian one, a Beckmann microfacet one, bad arguments.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "svo/render/merl.h"

namespace {

using namespace svo::render;

constexpr double kPi = 3.14159265358979323846;

// A lobe's integral over the sphere (over 2 pi: comparisons only).
double energy(const MerlSgLobe& l) { return double(l.amplitude) * (1 - std::exp(-2.0 * l.sharpness)) / l.sharpness; }

const MerlSgLobe& largest(const std::vector<MerlSgLobe>& lobes) {
  return *std::max_element(lobes.begin(), lobes.end(),
                           [](const MerlSgLobe& a, const MerlSgLobe& b) { return energy(a) < energy(b); });
}

void print(const char* name, const MerlBrdf& brdf, const std::vector<MerlSgLobe>& lobes) {
  std::printf("%s: %zu lobes, relative RMS error %.3g:", name, lobes.size(), merl_sg_fit_error(brdf, lobes));
  for (const MerlSgLobe& l : lobes) std::printf(" (sharpness %.4g, amplitude %.4g)", l.sharpness, l.amplitude);
  std::printf("\n");
}

void expect_valid(const std::vector<MerlSgLobe>& lobes) {
  for (size_t i = 0; i < lobes.size(); ++i) {
    EXPECT_TRUE(std::isfinite(lobes[i].sharpness) && std::isfinite(lobes[i].amplitude));
    EXPECT_GE(lobes[i].sharpness, 1e-2f);
    EXPECT_LE(lobes[i].sharpness, 1e5f);
    EXPECT_GT(lobes[i].amplitude, 0.0f);
    if (i > 0) {
      EXPECT_GT(lobes[i - 1].sharpness, lobes[i].sharpness);
    }
  }
}

// Half-vector profile exactly one SG of sharpness 200 (a Phong NDF of
// exponent 200 in SG form, no Fresnel, no geometry term) over Lambert 0.1/pi.
TEST(MerlSgFit, SingleLobeAndLambert) {
  const MerlBrdf brdf = tabulate_merl([](glm::dvec3 wi, glm::dvec3 wo) {
    const glm::dvec3 h = glm::normalize(wi + wo);
    return glm::dvec3(0.1 / kPi + 8.0 * std::exp(200.0 * (h.z - 1)));
  });
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<MerlSgLobe> lobes = fit_merl_sg(brdf);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("fit_merl_sg: %.1f ms\n", ms);
  print("SG 200 + Lambert", brdf, lobes);
  expect_valid(lobes);
  ASSERT_EQ(lobes.size(), 1u);
  EXPECT_NEAR(lobes[0].sharpness, 200.0, 0.05 * 200);
  EXPECT_NEAR(lobes[0].amplitude, 8.0, 0.05 * 8);
  EXPECT_LT(merl_sg_fit_error(brdf, lobes), 0.02);
  // The error measures something: a lobe of the wrong sharpness fits worse.
  EXPECT_GT(merl_sg_fit_error(brdf, {{100.0f, 8.0f}}), 0.1);
  // Deterministic.
  const std::vector<MerlSgLobe> again = fit_merl_sg(brdf);
  ASSERT_EQ(again.size(), lobes.size());
  EXPECT_EQ(again[0].sharpness, lobes[0].sharpness);
  EXPECT_EQ(again[0].amplitude, lobes[0].amplitude);
  // One lobe asked for: the same.
  const std::vector<MerlSgLobe> one = fit_merl_sg(brdf, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NEAR(one[0].sharpness, 200.0, 0.05 * 200);
}

// Two lobes of comparable energy (integrals 2 pi 1/30 and 2 pi 60/2000).
TEST(MerlSgFit, TwoLobes) {
  const MerlBrdf brdf = tabulate_merl([](glm::dvec3 wi, glm::dvec3 wo) {
    const glm::dvec3 h = glm::normalize(wi + wo);
    const double f = 0.05 / kPi + 1.0 * std::exp(30.0 * (h.z - 1)) + 60.0 * std::exp(2000.0 * (h.z - 1));
    return glm::dvec3(f, 0.8 * f, 0.6 * f);
  });
  const std::vector<MerlSgLobe> lobes = fit_merl_sg(brdf, 3);
  print("SG 30 + SG 2000", brdf, lobes);
  expect_valid(lobes);
  ASSERT_GE(lobes.size(), 2u);
  // Sorted by sharpness, descending.
  EXPECT_NEAR(lobes[0].sharpness, 2000.0, 0.1 * 2000);
  EXPECT_NEAR(lobes[1].sharpness, 30.0, 0.1 * 30);
  EXPECT_LT(merl_sg_fit_error(brdf, lobes), 0.02);
  // One lobe cannot fit both.
  const std::vector<MerlSgLobe> one = fit_merl_sg(brdf, 1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_GT(merl_sg_fit_error(brdf, one), 0.05);
}

TEST(MerlSgFit, LambertianHasNoLobe) {
  const MerlBrdf brdf =
      tabulate_merl([](glm::dvec3, glm::dvec3) { return glm::dvec3(0.6 / kPi, 0.3 / kPi, 0.2 / kPi); });
  const std::vector<MerlSgLobe> lobes = fit_merl_sg(brdf);
  print("Lambert", brdf, lobes);
  EXPECT_TRUE(lobes.empty());
  EXPECT_LT(merl_sg_fit_error(brdf, lobes), 1e-5);
  // Black (every sample reads as missing): none either, and no NaN.
  const MerlBrdf black{std::vector<float>(3 * size_t(kMerlSamples), 0.0f)};
  EXPECT_TRUE(fit_merl_sg(black).empty());
  EXPECT_EQ(merl_sg_fit_error(black, {}), 0.0);
}

// Cook-Torrance with the Beckmann NDF (alpha 0.2), Smith shadowing (Walter
// et al.'s rational fit), no Fresnel, over Lambert 0.2/pi.
TEST(MerlSgFit, Beckmann) {
  const double alpha = 0.2;
  const MerlBrdf brdf = tabulate_merl([alpha](glm::dvec3 wi, glm::dvec3 wo) {
    const glm::dvec3 h = glm::normalize(wi + wo);
    const double c2 = h.z * h.z, tan2 = (1 - c2) / c2;
    const double d = std::exp(-tan2 / (alpha * alpha)) / (kPi * alpha * alpha * c2 * c2);
    auto g1 = [alpha](double cos_theta) {
      const double a = cos_theta / (alpha * std::sqrt(1 - cos_theta * cos_theta));
      return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a);
    };
    return glm::dvec3(0.2 / kPi + d * g1(wi.z) * g1(wo.z) / (4 * wi.z * wo.z));
  });
  const std::vector<MerlSgLobe> lobes = fit_merl_sg(brdf);
  print("Beckmann 0.2", brdf, lobes);
  expect_valid(lobes);
  ASSERT_FALSE(lobes.empty());
  // 25 %: near theta_d = 0 the profile is exp(-tan^2 theta_h / alpha^2) /
  // (4 pi alpha^2 cos^6 theta_h) (D's 1 / cos^4 and the 1 / (4 cos^2) of the
  // microfacet BRDF, G about 1), not an SG: with x = 1 - cos theta_h,
  // tan^2 = 2x + 3x^2 + ..., so its log-slope at the peak is
  // 2 / alpha^2 - 6 = 44, not 50, and it steepens away from the peak; the
  // fit sees the whole lobe, and its largest lobe lies between.
  EXPECT_NEAR(largest(lobes).sharpness, 2 / (alpha * alpha), 0.25 * 2 / (alpha * alpha));
  EXPECT_LT(merl_sg_fit_error(brdf, lobes), 0.05);
}

TEST(MerlSgFit, BadArguments) {
  const MerlBrdf grey{std::vector<float>(3 * size_t(kMerlSamples), 0.1f)};
  EXPECT_THROW(fit_merl_sg(grey, 0), std::invalid_argument);
  EXPECT_THROW(fit_merl_sg(grey, 4), std::invalid_argument);
  EXPECT_THROW(fit_merl_sg(grey, -1), std::invalid_argument);
  EXPECT_NO_THROW(fit_merl_sg(grey, 3));
  EXPECT_THROW(fit_merl_sg(MerlBrdf{}), std::invalid_argument);
  EXPECT_THROW(merl_sg_fit_error(MerlBrdf{}, {}), std::invalid_argument);
}

}  // namespace
