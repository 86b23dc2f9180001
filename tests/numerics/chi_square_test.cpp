// The chi-square helper (chi_square.h) itself: its p-values against closed
// forms, samplers that match their pdf pass, and samplers that do not are
// rejected.
#include "numerics/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using svo::test::chi_square_p_value;
using svo::test::chi_square_test;
using svo::test::ChiSquareOptions;
using svo::test::ChiSquareResult;

constexpr double kPi = 3.14159265358979323846;

TEST(ChiSquare, PValueMatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 2.0, 3.7, 10.0, 40.0, 120.0}) {
    // dof 2: exp(-x/2); dof 1: erfc(sqrt(x/2)); dof 4: exp(-x/2) (1 + x/2).
    EXPECT_NEAR(chi_square_p_value(x, 2) / std::exp(-x / 2), 1.0, 1e-10) << x;
    EXPECT_NEAR(chi_square_p_value(x, 1) / std::erfc(std::sqrt(x / 2)), 1.0, 1e-9) << x;
    EXPECT_NEAR(chi_square_p_value(x, 4) / (std::exp(-x / 2) * (1 + x / 2)), 1.0, 1e-10) << x;
  }
  EXPECT_EQ(chi_square_p_value(0, 10), 1.0);
  // Large dof: the median of chi2(k) is about k (1 - 2/(9k))^3.
  EXPECT_NEAR(chi_square_p_value(1000 * std::pow(1 - 2.0 / 9000, 3), 1000), 0.5, 1e-3);
}

std::optional<glm::dvec3> uniform_sphere(glm::dvec2 u) {
  const double z = 1 - 2 * u.x, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * u.y;
  return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
}

// Phong lobe about +z: pdf (n + 1) / (2 pi) cos^n.
std::optional<glm::dvec3> phong(glm::dvec2 u, double n) {
  const double z = std::pow(1 - u.x, 1 / (n + 1)), r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * u.y;
  return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
}
double phong_pdf(glm::dvec3 d, double n) { return d.z > 0 ? (n + 1) / (2 * kPi) * std::pow(d.z, n) : 0.0; }

TEST(ChiSquare, MatchingSamplersPass) {
  const double alpha = svo::test::sidak_significance(0.01, 3);
  ChiSquareResult r = chi_square_test(uniform_sphere, [](glm::dvec3) { return 1 / (4 * kPi); });
  EXPECT_TRUE(r.passed(alpha)) << r.summary();
  EXPECT_NEAR(r.pdf_integral, 1.0, 1e-4);  // the midpoint rule's error
  EXPECT_GT(r.dof, 3000);
  for (double n : {1.0, 40.0}) {
    r = chi_square_test([&](glm::dvec2 u) { return phong(u, n); }, [&](glm::dvec3 d) { return phong_pdf(d, n); });
    EXPECT_TRUE(r.passed(alpha)) << "n " << n << ": " << r.summary();
    EXPECT_NEAR(r.pdf_integral, 1.0, 5e-3) << n;
  }
}

TEST(ChiSquare, MismatchedSamplersFail) {
  ChiSquareOptions options;
  options.samples = 200000;
  // A Phong exponent 10% off.
  ChiSquareResult r = chi_square_test([](glm::dvec2 u) { return phong(u, 10.0); },
                                      [](glm::dvec3 d) { return phong_pdf(d, 11.0); }, options);
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_LT(r.p_value, 1e-6) << r.summary();
  // Uniform in theta instead of cos(theta) (the Jacobian forgotten).
  r = chi_square_test(
      [](glm::dvec2 u) {
        const double t = kPi * u.x, phi = 2 * kPi * u.y;
        return std::optional<glm::dvec3>(
            glm::dvec3(std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), std::cos(t)));
      },
      [](glm::dvec3) { return 1 / (4 * kPi); }, options);
  EXPECT_LT(r.p_value, 1e-6) << r.summary();
  // Samples where the pdf is 0: an error whatever the statistic.
  r = chi_square_test(
      uniform_sphere, [](glm::dvec3 d) { return d.z > 0 ? 1 / (2 * kPi) : 0.0; }, options);
  EXPECT_FALSE(r.error.empty()) << r.summary();
  EXPECT_FALSE(r.passed(0.0));
  // A NaN pdf.
  r = chi_square_test(
      uniform_sphere, [](glm::dvec3 d) { return d.z > 0.9 ? std::nan("") : 1 / (4 * kPi); }, options);
  EXPECT_FALSE(r.error.empty());
}

// A sampler that gives up half the time: its pdf integrates to 1/2 and the
// test still passes (the lost samples are counted, not binned).
TEST(ChiSquare, PartialSamplerPasses) {
  ChiSquareOptions options;
  options.samples = 400000;
  ChiSquareResult r =
      chi_square_test([](glm::dvec2 u) { return u.x < 0.5 ? uniform_sphere(glm::dvec2(2 * u.x, u.y)) : std::nullopt; },
                      [](glm::dvec3) { return 0.5 / (4 * kPi); }, options);
  EXPECT_TRUE(r.passed(0.01)) << r.summary();
  EXPECT_NEAR(r.pdf_integral, 0.5, 1e-4);
  EXPECT_NEAR(double(r.no_sample) / double(options.samples), 0.5, 0.01);
}

}  // namespace
