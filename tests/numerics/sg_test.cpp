// Spherical Gaussians (shaders/common/sg.glsl, issue 19) in float against
// quadrature on the sphere in double: the exact product integral and the
// normalised weight of Eq. 11 within 1e-4 relative for sharpness 1e-3 to
// 1e4; Eq. 12 against the same where Iwasaki's approximation holds, the
// normal-aware weight it reduces to for diffuse lobes, symmetry, identical
// lobes, and no NaN or Inf anywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <vector>

#include "common/shared_math.h"

namespace {

using svo::math::SvoSG;

constexpr double kPi = 3.14159265358979323846;

// A unit vector at angle `theta` from +z, in the xz plane turned by `phi`.
glm::dvec3 direction(double theta, double phi = 0.3) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The integral over the sphere of f(w), f concentrated near the unit vector
// `centre`: w = (1 - x) centre + sqrt(x (2 - x)) (cos p t + sin p b), x = 1 -
// cos(angle to centre) taken on a log scale (x = e^y) by Simpson's rule,
// the azimuth by the trapezoid rule (exact for what is smooth and periodic).
template <typename F>
double sphere_integral(glm::dvec3 centre, F f, int np = 16) {
  glm::dvec3 t = std::abs(centre.z) < 0.9 ? glm::normalize(glm::cross(centre, glm::dvec3(0, 0, 1)))
                                          : glm::normalize(glm::cross(centre, glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(centre, t);
  const int ny = 4000;
  const double y0 = std::log(1e-16), y1 = std::log(2.0), h = (y1 - y0) / ny;
  double sum = 0;
  for (int i = 0; i <= ny; ++i) {
    const double x = std::exp(y0 + i * h);
    const double r = std::sqrt(std::max(0.0, x * (2 - x)));
    double ring = 0;
    for (int k = 0; k < np; ++k) {
      const double p = 2 * kPi * (k + 0.5) / np;
      ring += f((1 - x) * centre + r * (std::cos(p) * t + std::sin(p) * b));
    }
    ring *= 2 * kPi / np;
    const double w = (i == 0 || i == ny) ? 1 : (i % 2 ? 4 : 2);
    sum += w * ring * x;  // dx = x dy
  }
  return sum * h / 3;
}

struct Lobe {
  glm::dvec3 axis;
  double sharpness, amplitude;
  double operator()(glm::dvec3 w) const { return amplitude * std::exp(sharpness * (glm::dot(w, axis) - 1)); }
  SvoSG sg() const { return svo::math::svo_sg(glm::vec3(axis), float(sharpness), float(amplitude)); }
};

// The exact product integral by quadrature.
double product_quadrature(const Lobe& a, const Lobe& b) {
  glm::dvec3 u = a.sharpness * a.axis + b.sharpness * b.axis;
  const glm::dvec3 centre = glm::length(u) > 1e-12 ? glm::normalize(u) : a.axis;
  return sphere_integral(centre, [&](glm::dvec3 w) { return a(w) * b(w); });
}

// Pairs of lobes: sharpness from 1e-3 to 1e4, axes apart by angles whose
// product is not negligible (the exponent l1 l2 / (l1 + l2) (1 - cos) <= 30).
std::vector<std::pair<Lobe, Lobe>> lobe_pairs() {
  std::vector<std::pair<Lobe, Lobe>> out;
  const double sharpness[] = {1e-3, 0.1, 1, 10, 88, 100, 1e3, 1e4};
  for (double la : sharpness) {
    for (double lb : sharpness) {
      const double l = la * lb / (la + lb);
      for (double f : {0.0, 0.3, 1.0}) {
        const double angle = f == 0 ? 0 : std::min(2.5, std::acos(std::max(-1.0, 1 - f * 30 / l)));
        out.push_back({{direction(0.4), la, 0.7}, {direction(0.4 + angle), lb, 1.3}});
      }
    }
  }
  return out;
}

TEST(SphericalGaussians, ExactProductIntegralMatchesQuadratureInFloat) {
  double worst = 0;
  for (const auto& [a, b] : lobe_pairs()) {
    const double truth = product_quadrature(a, b);
    const float ours = svo::math::svo_sg_product_integral(a.sg(), b.sg());
    ASSERT_TRUE(std::isfinite(ours));
    const double e = std::abs(double(ours) - truth) / truth;
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-4) << "sharpness " << a.sharpness << ", " << b.sharpness << ", cos " << glm::dot(a.axis, b.axis)
                       << ": " << ours << " against " << truth;
  }
  std::printf("exact product integral: worst relative error %.2e\n", worst);
}

TEST(SphericalGaussians, ProductIsAnSgAndIntegralsAgree) {
  for (const auto& [a, b] : lobe_pairs()) {
    const SvoSG p = svo::math::svo_sg_product(a.sg(), b.sg());
    const glm::dvec3 w = glm::normalize(a.axis + 0.5 * b.axis);
    const double truth = a(w) * b(w);
    if (truth < 1e-30) continue;
    // A sharp lobe evaluated in float: an error of an ulp in w . axis moves the
    // value by about sharpness x 6e-8 relative.
    EXPECT_NEAR(svo::math::svo_sg_eval(p, glm::vec3(w)) / truth, 1.0, 1e-5 + 2e-7 * p.sharpness)
        << a.sharpness << " " << b.sharpness;
    const double integral = svo::math::svo_sg_integral(p);
    EXPECT_NEAR(integral / svo::math::svo_sg_product_integral(a.sg(), b.sg()), 1.0, 1e-5);
  }
  // One lobe's integral: 2 pi mu (1 - e^(-2 l)) / l, 4 pi mu at l = 0.
  for (double l : {0.0, 1e-6, 1e-3, 0.029, 0.031, 1.0, 88.0, 1e4}) {
    const Lobe g{direction(0.2), l, 1.5};
    const double truth = l == 0 ? 4 * kPi * 1.5 : 2 * kPi * 1.5 * -std::expm1(-2 * l) / l;
    EXPECT_NEAR(svo::math::svo_sg_integral(g.sg()) / truth, 1.0, 1e-6) << l;
  }
}

TEST(SphericalGaussians, Eq11WeightMatchesQuadrature) {
  double worst = 0;
  for (const auto& [a, b] : lobe_pairs()) {
    const double ab = product_quadrature(a, b), aa = product_quadrature(a, a), bb = product_quadrature(b, b);
    const double truth = ab / std::sqrt(aa * bb);
    const float ours = svo::math::svo_sg_similarity(a.sg(), b.sg());
    ASSERT_TRUE(std::isfinite(ours));
    if (truth < 1e-30) continue;
    const double e = std::abs(double(ours) - truth) / truth;
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-4) << "sharpness " << a.sharpness << ", " << b.sharpness;
    // beta: a power of the same.
    if (std::pow(truth, 4.0) > 1e-30) {
      EXPECT_NEAR(svo::math::svo_weight_eq11(a.sg(), b.sg(), 4.0f), std::pow(truth, 4.0), 4e-4 * std::pow(truth, 4.0));
    }
  }
  std::printf("Eq. 11 weight: worst relative error %.2e\n", worst);
}

// Eq. 12 is Eq. 11 with Iwasaki's approximate integral: close where both
// lobes are sharp, as the paper's Fig. 4 shows (weights within 5e-4 of
// Eq. 11's from sharpness 10, within 1e-4 from 100); the worst difference
// per sharpness is printed.
TEST(SphericalGaussians, Eq12ApproachesQuadratureForSharpLobes) {
  double worst[3] = {0, 0, 0};  // min sharpness < 10, >= 10, >= 100
  for (const auto& [a, b] : lobe_pairs()) {
    const double truth = product_quadrature(a, b) / std::sqrt(product_quadrature(a, a) * product_quadrature(b, b));
    const float ours = svo::math::svo_weight_eq12(a.sg(), b.sg(), 1.0f);
    ASSERT_TRUE(std::isfinite(ours));
    const double e = std::abs(double(ours) - truth), l = std::min(a.sharpness, b.sharpness);
    worst[l >= 100 ? 2 : l >= 10 ? 1 : 0] = std::max(worst[l >= 100 ? 2 : l >= 10 ? 1 : 0], e);
    if (l >= 10) {
      EXPECT_LT(e, 5e-4) << a.sharpness << " " << b.sharpness;
    }
    if (l >= 100) {
      EXPECT_LT(e, 1e-4) << a.sharpness << " " << b.sharpness;
    }
  }
  std::printf("Eq. 12 against quadrature, largest difference: %.4f below sharpness 10, %.5f from 10, %.6f from 100\n",
              worst[0], worst[1], worst[2]);
}

TEST(SphericalGaussians, WeightsAreSymmetricOneForIdenticalLobesAndNormalAwareForDiffuse) {
  for (const auto& [a, b] : lobe_pairs()) {
    for (float beta : {0.5f, 1.0f, 20.0f}) {
      EXPECT_FLOAT_EQ(svo::math::svo_weight_eq12(a.sg(), b.sg(), beta),
                      svo::math::svo_weight_eq12(b.sg(), a.sg(), beta));
      EXPECT_FLOAT_EQ(svo::math::svo_weight_eq11(a.sg(), b.sg(), beta),
                      svo::math::svo_weight_eq11(b.sg(), a.sg(), beta));
      EXPECT_FLOAT_EQ(svo::math::svo_weight_eq12(a.sg(), a.sg(), beta), 1.0f);
      EXPECT_FLOAT_EQ(svo::math::svo_weight_eq11(a.sg(), a.sg(), beta), 1.0f);
    }
  }
  // Two diffuse lobes: equal sharpness, axes the normals; Eq. 12 is then the
  // normal-aware weight of sigma_n^2 = 2 / (beta l).
  for (float l : {1.0f, 2.13f, 10.0f}) {
    for (float beta : {1.0f, 7.0f, 50.0f}) {
      for (double angle : {0.0, 0.05, 0.3, 1.0, 3.0}) {
        const SvoSG a = svo::math::svo_sg(glm::vec3(direction(0.2)), l, 1.0f);
        const SvoSG b = svo::math::svo_sg(glm::vec3(direction(0.2 + angle, 2.0)), l, 1.0f);
        const float normal = svo::math::svo_weight_normal(a.axis, b.axis, 2.0f / (beta * l));
        EXPECT_NEAR(svo::math::svo_weight_eq12(a, b, beta), normal, 1e-5f * normal);
      }
    }
  }
}

TEST(SphericalGaussians, NeverNanOrInfOnHardCases) {
  const float values[] = {0.0f, 1e-30f, 1e-7f, 0.03f, 88.0f, 89.0f, 1e4f, 1e7f, 1e30f, 3e38f};
  const glm::vec3 axes[] = {{0, 0, 1}, {0, 0, -1}, {0, 1e-7f, 1}, {1, 0, 0}};
  for (float la : values) {
    for (float lb : values) {
      for (const glm::vec3& x : axes) {
        const SvoSG a = svo::math::svo_sg(glm::vec3(0, 0, 1), la, 1.0f);
        const SvoSG b = svo::math::svo_sg(glm::normalize(x), lb, 1.0f);
        const float values_of[] = {svo::math::svo_sg_product_integral(a, b),
                                   svo::math::svo_sg_product_integral_approx(a, b),
                                   svo::math::svo_sg_similarity(a, b),
                                   svo::math::svo_weight_eq11(a, b, 20.0f),
                                   svo::math::svo_weight_eq12(a, b, 20.0f),
                                   svo::math::svo_sg_integral(a),
                                   svo::math::svo_sg_smooth(a, 100.0f).sharpness,
                                   svo::math::svo_sg_smooth(a, 100.0f).amplitude,
                                   svo::math::svo_sg_product(a, b).amplitude,
                                   svo::math::svo_sg_product(a, b).sharpness};
        for (int k = 0; k < 10; ++k) {
          const float v = values_of[k];
          EXPECT_TRUE(std::isfinite(v)) << "value " << k << ": " << la << " " << lb << " " << x.x << "," << x.y << ","
                                        << x.z;
          EXPECT_GE(v, 0.0f) << "value " << k;
        }
      }
    }
  }
}

// Eq. 10: the lobe convolved with the kernel G(., ., kappa), against
// quadrature of the convolution at a few directions (sharp lobes, where
// Iwasaki's approximation holds).
TEST(SphericalGaussians, SmoothingKernelMatchesTheConvolution) {
  for (double l : {50.0, 500.0}) {
    for (double kappa : {100.0, 1000.0}) {
      const Lobe g{direction(0.3), l, 1.0};
      const SvoSG s = svo::math::svo_sg_smooth(g.sg(), float(kappa));
      for (double angle : {0.0, 0.02, 0.06}) {
        const glm::dvec3 w = direction(0.3 + angle, 0.3);
        const Lobe kernel{w, kappa, 1.0};
        const double truth = product_quadrature(g, kernel);
        EXPECT_NEAR(svo::math::svo_sg_eval(s, glm::vec3(w)) / truth, 1.0, 0.03) << l << " " << kappa << " " << angle;
      }
    }
  }
  const SvoSG g = svo::math::svo_sg(glm::vec3(0, 0, 1), 30.0f, 2.0f);
  EXPECT_EQ(svo::math::svo_sg_smooth(g, INFINITY).sharpness, 30.0f);
}

}  // namespace

namespace {

using svo::math::SvoASG;

struct AsgLobe {
  glm::dvec3 x, y, z;
  double lx, ly;
  double operator()(glm::dvec3 w) const {
    const double u = glm::dot(w, x), v = glm::dot(w, y);
    return std::max(glm::dot(w, z), 0.0) * std::exp(-lx * u * u - ly * v * v);
  }
  SvoASG asg() const {
    return svo::math::svo_asg(glm::vec3(x), glm::vec3(y), glm::vec3(z), float(lx), float(ly), 1.0f);
  }
};

// The frame of axis z = direction(theta, phi) turned by `spin` about it.
AsgLobe asg_lobe(double theta, double phi, double spin, double lx, double ly) {
  const glm::dvec3 z = direction(theta, phi);
  const glm::dvec3 t = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), z)), b = glm::cross(z, t);
  return {std::cos(spin) * t + std::sin(spin) * b, -std::sin(spin) * t + std::cos(spin) * b, z, lx, ly};
}

// The product integral by quadrature, centred where the product peaks on a
// 256 x 512 latitude-longitude search.
double asg_quadrature(const AsgLobe& a, const AsgLobe& b) {
  auto f = [&](glm::dvec3 w) { return a(w) * b(w); };
  glm::dvec3 best(0, 0, 1);
  double peak = -1;
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 512; ++j) {
      const glm::dvec3 w = direction(kPi * (i + 0.5) / 256, 2 * kPi * j / 512);
      if (const double v = f(w); v > peak) peak = v, best = w;
    }
  }
  return sphere_integral(best, f, 512);  // anisotropic: the azimuth needs many samples
}

// Non-low-frequency lobes (bandwidths >= 10), anisotropy up to 100:1, the
// second lobe turned and tilted: within 2% of quadrature.
TEST(AnisotropicSphericalGaussians, ProductIntegralMatchesQuadrature) {
  double worst = 0;
  for (double lx : {10.0, 100.0, 1000.0}) {
    for (double ratio : {1.0, 10.0, 100.0}) {
      if (lx / ratio < 10) continue;
      for (double tilt : {0.0, 0.05, 0.15}) {
        for (double spin : {0.0, 0.7}) {
          const AsgLobe a = asg_lobe(0.3, 0.2, 0.0, lx, lx / ratio);
          const AsgLobe b = asg_lobe(0.3 + tilt, 0.2, spin, 0.5 * lx, 0.5 * lx / ratio);
          const double truth = asg_quadrature(a, b);
          if (truth < 1e-8 * asg_quadrature(a, a)) continue;
          const float ours = svo::math::svo_asg_product_integral(a.asg(), b.asg());
          const double e = std::abs(double(ours) - truth) / truth;
          worst = std::max(worst, e);
          EXPECT_LT(e, 0.02) << "lx " << lx << ", 1:" << ratio << ", tilt " << tilt << ", spin " << spin << ": " << ours
                             << " against " << truth;
        }
      }
    }
  }
  std::printf("ASG product integral: worst relative error %.4f\n", worst);
}

// Along a sweep of one lobe's angle the integral follows quadrature with no
// jumps (the banding Cardano's formula gives in float, the paper's Fig. 19).
TEST(AnisotropicSphericalGaussians, SmoothAlongASweepOfLobeAngle) {
  double previous = 0, worst_step = 0, worst = 0;
  for (int k = 0; k <= 60; ++k) {
    const double spin = 1.5 * k / 60.0;
    const AsgLobe a = asg_lobe(0.3, 0.2, 0.0, 1000.0, 10.0);
    const AsgLobe b = asg_lobe(0.33, 0.25, spin, 800.0, 12.0);
    const double ratio = double(svo::math::svo_asg_product_integral(a.asg(), b.asg())) / asg_quadrature(a, b);
    if (k > 0) worst_step = std::max(worst_step, std::abs(ratio - previous));
    worst = std::max(worst, std::abs(ratio - 1));
    previous = ratio;
  }
  std::printf("ASG sweep: worst error %.4f, worst change between neighbours %.5f\n", worst, worst_step);
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(worst_step, 0.002);
}

// The eigen-solver keeps float's relative accuracy on the matrices of
// sharp, thin lobes (the smallest eigenvalue near 0 beside 1e4).
TEST(AnisotropicSphericalGaussians, EigenSolverIsAccurateInFloat) {
  for (double spin : {0.0, 0.3, 1.1}) {
    const AsgLobe a = asg_lobe(0.3, 0.2, 0.0, 1e4, 100.0), b = asg_lobe(0.31, 0.2, spin, 5e3, 1e3);
    glm::dmat3 m = a.lx * glm::outerProduct(a.x, a.x) + a.ly * glm::outerProduct(a.y, a.y) +
                   b.lx * glm::outerProduct(b.x, b.x) + b.ly * glm::outerProduct(b.y, b.y);
    const svo::math::SvoEigen3 e = svo::math::svo_eigen_symmetric3(glm::mat3(m));
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 v(e.vectors[k]);
      EXPECT_NEAR(glm::length(v), 1.0, 1e-5);
      // A v = e v, relative to the largest eigenvalue.
      EXPECT_LT(glm::length(m * v - double(e.values[k]) * v), 1e-5 * double(e.values.z)) << spin << " " << k;
    }
    EXPECT_LE(e.values.x, e.values.y);
    EXPECT_LE(e.values.y, e.values.z);
  }
}

// The case the paper names: axes more than 90 degrees apart, equal
// bandwidths (the smallest eigenvector lies across the bisector, where one
// cosine is negative). The product is small and, at low frequency, spread
// over two humps that Laplace's method cannot see; what the filter uses is
// the normalised similarity of Eq. 13: within 0.01 of quadrature's
// (absolute, on a scale of 0 to 1) from bandwidth 10, within 0.08 at the
// low frequencies below (measured: 0.075 at bandwidth 2, 0.07 at 5). Errors
// of the integral itself are printed.
TEST(AnisotropicSphericalGaussians, AxesMoreThanARightAngleApart) {
  for (double l : {2.0, 5.0, 20.0, 100.0}) {
    for (double angle : {1.6, 2.0, 2.4}) {
      const AsgLobe a = asg_lobe(0.3, 0.2, 0.0, l, l), b = asg_lobe(0.3 + angle, 0.2, 0.0, l, 0.5 * l);
      const double truth = asg_quadrature(a, b);
      const float ours = svo::math::svo_asg_product_integral(a.asg(), b.asg());
      const double q = truth / std::sqrt(asg_quadrature(a, a) * asg_quadrature(b, b));
      const float weight = svo::math::svo_weight_eq13(a.asg(), b.asg(), 1.0f);
      std::printf("ASG axes %.1f rad apart, bandwidth %.0f: integral %.4g against %.4g, Eq. 13 %.5f against %.5f\n",
                  angle, l, ours, truth, weight, q);
      ASSERT_TRUE(std::isfinite(ours));
      EXPECT_GE(ours, 0.0f);
      EXPECT_NEAR(weight, q, l >= 10 ? 0.01 : 0.08) << l << " " << angle;
    }
  }
}

TEST(AnisotropicSphericalGaussians, Eq13IsOneForIdenticalLobesAndSymmetric) {
  const AsgLobe a = asg_lobe(0.3, 0.2, 0.0, 300, 30), b = asg_lobe(0.4, 0.1, 0.5, 100, 60);
  EXPECT_NEAR(svo::math::svo_weight_eq13(a.asg(), a.asg(), 10.0f), 1.0f, 1e-5f);
  EXPECT_FLOAT_EQ(svo::math::svo_weight_eq13(a.asg(), b.asg(), 3.0f),
                  svo::math::svo_weight_eq13(b.asg(), a.asg(), 3.0f));
  EXPECT_LT(svo::math::svo_weight_eq13(a.asg(), b.asg(), 3.0f), 0.5f);
  // Smoothing widens both: closer lobes.
  EXPECT_GT(svo::math::svo_weight_eq13(svo::math::svo_asg_smooth(a.asg(), 30.0f),
                                       svo::math::svo_asg_smooth(b.asg(), 30.0f), 3.0f),
            svo::math::svo_weight_eq13(a.asg(), b.asg(), 3.0f));
}

}  // namespace

namespace {

// The reflection lobe of a Beckmann NDF, as an SG, against the true lobe
// D(h(l)) / (4 |h . v|) over outgoing directions l: their normalised
// similarity (Eq. 8 with beta 1) by quadrature is close to 1 where the lobe
// is not grazing, and the SG's width follows the roughness and the voxel's
// slope variance.
TEST(SphericalGaussians, ReflectionLobeFollowsTheBeckmannLobe) {
  for (double alpha : {0.05, 0.1, 0.3}) {
    for (double view : {0.0, 0.5, 1.0}) {
      const glm::dvec3 n(0, 0, 1), v = direction(view, 0.0);
      const float lh = svo::math::svo_ndf_sharpness(1u, float(alpha * alpha), 0.0f, 0.0f);
      const SvoSG sg = svo::math::svo_reflection_lobe(glm::vec3(n), glm::vec3(v), lh);
      auto lobe = [&](glm::dvec3 l) {
        if (l.z <= 0) return 0.0;
        const glm::dvec3 h = glm::normalize(l + v);
        const double t2 = (1 - h.z * h.z) / (h.z * h.z);
        return std::exp(-t2 / (alpha * alpha)) / (std::pow(h.z, 4) * 4 * std::abs(glm::dot(h, v)));
      };
      const Lobe g{glm::dvec3(sg.axis), double(sg.sharpness), 1.0};
      const glm::dvec3 c = glm::dvec3(sg.axis);
      const double ab = sphere_integral(
          c, [&](glm::dvec3 w) { return lobe(w) * g(w); }, 256);
      const double aa = sphere_integral(
          c, [&](glm::dvec3 w) { return lobe(w) * lobe(w); }, 256);
      const double bb = sphere_integral(
          c, [&](glm::dvec3 w) { return g(w) * g(w); }, 256);
      const double q = ab / std::sqrt(aa * bb);
      std::printf("Beckmann alpha %.2f, view %.1f rad: similarity of the SG reflection lobe %.4f\n", alpha, view, q);
      EXPECT_GT(q, 0.9) << alpha << " " << view;
    }
  }
  // Variances add: a voxel slope variance equal to the NDF's halves the sharpness.
  EXPECT_NEAR(svo::math::svo_ndf_sharpness(1u, 0.02f, 0.0f, 0.01f), 0.5f * 2.0f / 0.02f, 1e-3f);
  EXPECT_NEAR(svo::math::svo_ndf_sharpness(3u, 0.0f, 400.0f, 0.0f), 400.0f, 1e-3f);
  // Two diffuse lobes give Eq. 12 = the normal-aware weight (see above).
  const SvoSG d = svo::math::svo_diffuse_lobe(glm::vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(svo::math::svo_weight_eq12(d, d, 5.0f), 1.0f);
}

}  // namespace
