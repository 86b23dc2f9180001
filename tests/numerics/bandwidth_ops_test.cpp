// The bandwidth operators of Bagher et al. 2013 (shaders/common/
// bandwidth_ops.glsl, issue 17): each operator of Fig. 4 against its closed
// form, the bounding rectangle of the spectrum's rectangle mapped by the
// operator's matrix (computed here from the matrix and the four corners);
// Eq. 3-4 as the product of the operators; Eq. 6 and 11; the slope
// band-limit against the 95% energy quantile of a Gaussian lobe's spectrum.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/mat2x2.hpp>
#include <vector>

#include "common/shared_math.h"

namespace {

using namespace svo::math;

// The half-sides of the bounding rectangle of M applied to the rectangle
// [-nu_s, nu_s] x [-nu_a, nu_a], from its four corners.
glm::dvec2 bound(glm::dmat2 m, glm::dvec2 nu) {
  glm::dvec2 r(0);
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const glm::dvec2 c = m * glm::dvec2(sx * nu.x, sy * nu.y);
      r = glm::max(r, glm::abs(c));
    }
  return r;
}

// glm matrices are column-major: rows (a b; c d) are dmat2(a, c, b, d).
glm::dmat2 rows(double a, double b, double c, double d) { return glm::dmat2(a, c, b, d); }

void expect_near(glm::vec2 got, glm::dvec2 want) {
  EXPECT_NEAR(got.x, want.x, 1e-5 * (1 + std::abs(want.x)));
  EXPECT_NEAR(got.y, want.y, 1e-5 * (1 + std::abs(want.y)));
}

const glm::dvec2 kNus[] = {{0, 3}, {2, 0}, {1.5, 7.25}, {40, 0.5}};

TEST(BandwidthOps, TransportIsTheShearTd) {
  for (glm::dvec2 nu : kNus)
    for (double d : {0.0, 0.3, 2.0, 17.0}) {
      expect_near(svo_bw_transport(glm::vec2(nu), float(d)), bound(rows(1, 0, -d, 1), nu));
    }
}

TEST(BandwidthOps, DistantLightStaysDistantOverAnyDistance) {
  const glm::vec2 r = svo_bw_transport(glm::vec2(0, 5), std::numeric_limits<float>::infinity());
  EXPECT_EQ(r.x, 0.0f);
  EXPECT_EQ(r.y, 5.0f);
  EXPECT_TRUE(std::isfinite(svo_bw_transport(glm::vec2(1, 5), 1e30f).y));
}

TEST(BandwidthOps, CurvatureIsTheShearCc) {
  for (glm::dvec2 nu : kNus)
    for (double c : {-4.0, -0.5, 0.0, 0.5, 4.0}) {
      expect_near(svo_bw_curvature(glm::vec2(nu), float(c)), bound(rows(1, c, 0, 1), nu));
    }
}

TEST(BandwidthOps, ReparametrisationsAreTheScalesPiPx) {
  for (glm::dvec2 nu : kNus)
    for (double theta : {0.0, 0.4, 1.0, 1.5}) {
      const double c = std::cos(theta);
      expect_near(svo_bw_incident(glm::vec2(nu), float(c)), bound(rows(c, 0, 0, 1), nu));
      expect_near(svo_bw_outgoing(glm::vec2(nu), float(c)), bound(rows(1 / c, 0, 0, 1), nu));
    }
  // Grazing: the division stops at SVO_BW_MIN_COS.
  EXPECT_FLOAT_EQ(svo_bw_outgoing(glm::vec2(1, 0), 0.0f).x, 1.0f / SVO_BW_MIN_COS);
}

TEST(BandwidthOps, MirrorIsS) {
  for (glm::dvec2 nu : kNus) expect_near(svo_bw_mirror(glm::vec2(nu)), bound(rows(1, 0, 0, -1), nu));
}

TEST(BandwidthOps, BandLimitAddsTheTextureAndCutsTheAngle) {
  expect_near(svo_bw_band_limit(glm::vec2(2, 10), 3, 4), {5, 4});
  expect_near(svo_bw_band_limit(glm::vec2(2, 1), 0, 4), {2, 1});
}

// Eq. 3 on the spectrum's support, point by point: points of the
// rectangle through P_i and C_c, those the BRDF's window |nu_a| <= rho
// keeps, then the texture's convolution (nu_s widened by t), S, C_{-c},
// P_x; the largest |coordinates| are the bandwidth.
glm::dvec2 reflect_support(glm::dvec2 nu, double c, double ci, double cx, double t, double rho) {
  glm::dvec2 r(0);
  const int n = 200;
  std::vector<double> ys;
  for (int j = -n; j <= n; ++j) ys.push_back(nu.y * j / n);
  // The window's edges, where they cross the rectangle: vertices of the cut support.
  if (rho < nu.y) ys.insert(ys.end(), {-rho, rho});
  for (int i = -n; i <= n; ++i)
    for (double y : ys) {
      glm::dvec2 p(nu.x * i / n, y);
      p = rows(1, c, 0, 1) * (rows(ci, 0, 0, 1) * p);
      if (std::abs(p.y) > rho) continue;
      for (int s : {-1, 1}) {
        glm::dvec2 q(p.x + s * t, p.y);
        q = rows(1 / cx, 0, 0, 1) * (rows(1, -c, 0, 1) * (rows(1, 0, 0, -1) * q));
        r = glm::max(r, glm::abs(q));
      }
    }
  return r;
}

TEST(BandwidthOps, ReflectionIsEq3OnTheSupport) {
  for (glm::dvec2 nu : kNus)
    for (double c : {0.0, 0.7, 3.0})
      for (double ti : {0.2, 1.1})
        for (double rho : {0.5, 5.0, 100.0}) {
          const double ci = std::cos(ti), cx = std::cos(0.6), t = 0.25;
          const glm::dvec2 want = reflect_support(nu, c, ci, cx, t, rho);
          const glm::vec2 got = svo_bw_reflect(glm::vec2(nu), float(c), float(ci), float(cx), float(t), float(rho));
          EXPECT_NEAR(got.x, want.x, 0.02 * (1 + want.x)) << nu.x << " " << nu.y << " c " << c << " rho " << rho;
          EXPECT_NEAR(got.y, want.y, 0.02 * (1 + want.y)) << nu.x << " " << nu.y << " c " << c << " rho " << rho;
          // Eq. 4 around it: T_{d'} R T_d.
          const double d = 2, de = 9;
          const glm::dvec2 in = nu.x > 0 ? bound(rows(1, 0, -d, 1), nu) : nu;
          const glm::dvec2 e = bound(rows(1, 0, -de, 1), reflect_support(in, c, ci, cx, t, rho));
          const glm::vec2 all = svo_bw_one_bounce(glm::vec2(nu), float(d), float(de), float(c), float(ci), float(cx),
                                                  float(t), float(rho));
          EXPECT_NEAR(all.y, e.y, 0.02 * (1 + e.y));
        }
}

// A directional light (unbounded angular bandwidth) on a curved surface:
// the BRDF's cut bounds what curvature turns into spatial frequency.
TEST(BandwidthOps, UnboundedLightIsBoundedByTheBrdf) {
  const glm::vec2 r = svo_bw_reflect({0, SVO_BW_INFINITE}, 10, 0.8f, 0.9f, 0, 2);
  EXPECT_NEAR(r.x, 2 * 10 * 2 / 0.9f, 1e-3);
  EXPECT_FLOAT_EQ(r.y, 2);
}

// A flat mirror shows the environment as it is: the angular bandwidth at the
// eye is the light's, whatever the distance; a curved one magnifies it by
// 1 + 2 c d' / cos theta_x (the spatial shear of the curvature, twice, then
// transport to the eye).
TEST(BandwidthOps, MirrorsFlatAndCurved) {
  const float nu_env = 8, de = 5, cx = 0.8f;
  const glm::vec2 flat = svo_bw_one_bounce({0, nu_env}, 1e30f, de, 0, 0.9f, cx, 0, SVO_BW_INFINITE);
  EXPECT_FLOAT_EQ(flat.y, nu_env);
  EXPECT_FLOAT_EQ(flat.x, 0);
  const float c = 0.5f;
  const glm::vec2 curved = svo_bw_one_bounce({0, nu_env}, 1e30f, de, c, 0.9f, cx, 0, SVO_BW_INFINITE);
  EXPECT_NEAR(curved.y, nu_env * (1 + 2 * c * de / cx), 1e-4 * curved.y);
  // A diffuse-like band-limit keeps the bandwidth at the BRDF's.
  const glm::vec2 rough = svo_bw_one_bounce({0, nu_env}, 1e30f, de, 0, 0.9f, cx, 0, 0.2f);
  EXPECT_FLOAT_EQ(rough.y, 0.2f);
}

TEST(BandwidthOps, ImageBandwidthAndLevel) {
  EXPECT_FLOAT_EQ(svo_bw_image(100, 0.002f), 0.2f);
  EXPECT_EQ(svo_bw_level(0.5f, 7), 1u);  // Nyquist: half a cycle per pixel, every other pixel
  EXPECT_EQ(svo_bw_level(0.49f, 7), 1u);
  EXPECT_EQ(svo_bw_level(0.24f, 7), 2u);
  EXPECT_EQ(svo_bw_level(1.0f, 7), 0u);
  EXPECT_EQ(svo_bw_level(3.0f, 7), 0u);
  EXPECT_EQ(svo_bw_level(1e-6f, 7), 7u);
  EXPECT_EQ(svo_bw_level(0.0f, 5), 5u);
  EXPECT_EQ(svo_bw_level(std::nanf(""), 5), 5u);
  // Eq. 11 is floor(log2(1 / b_p)).
  for (float b : {0.9f, 0.3f, 0.07f, 0.011f}) EXPECT_EQ(svo_bw_level(b, 9), uint32_t(std::floor(std::log2(1.0 / b))));
}

// The slope band-limit: the reflected directions of slopes of variance
// sigma2 spread as a Gaussian of deviation 2 sigma; the frequency below
// which 95% of its power spectrum's energy lies, by quadrature.
TEST(BandwidthOps, SlopeLimitIsTheGaussianLobes95thPercentile) {
  for (double sigma : {0.01, 0.05, 0.2}) {
    const double s = 2 * sigma;
    // Power spectrum of exp(-x^2 / (2 s^2)): exp(-4 pi^2 s^2 f^2); its
    // energy over |f| < F by the trapezoid rule.
    auto energy = [&](double F) {
      const int n = 20000;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double f = F * i / n;
        sum += (i == 0 || i == n ? 0.5 : 1.0) * std::exp(-4 * M_PI * M_PI * s * s * f * f);
      }
      return sum * F / n;
    };
    const double total = energy(50 / s);
    const double limit = svo_bw_slope_limit(float(sigma * sigma));
    EXPECT_NEAR(energy(limit) / total, 0.95, 2e-3) << "sigma " << sigma;
  }
  EXPECT_EQ(svo_bw_slope_limit(0), SVO_BW_INFINITE);
}

// The band-limit of a map pre-convolved with a normalised SG of sharpness
// kappa (Eq. 10's filtered illumination): the SG's own profile
// exp(kappa (cos theta - 1)) along a great circle, its spectrum by
// quadrature; 95% of the power below svo_bw_sg_limit within 3% (the
// profile is a Gaussian near the axis only).
TEST(BandwidthOps, SgLimitIsTheKernels95thPercentile) {
  for (double kappa : {16.0, 256.0, 4096.0}) {
    auto spectrum = [&](double f) {
      const int n = 4000;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double theta = M_PI * i / n;
        sum +=
            (i == 0 || i == n ? 0.5 : 1.0) * std::exp(kappa * (std::cos(theta) - 1)) * std::cos(2 * M_PI * f * theta);
      }
      return sum * M_PI / n;
    };
    auto energy = [&](double F) {
      const int n = 2000;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double v = spectrum(F * i / n);
        sum += (i == 0 || i == n ? 0.5 : 1.0) * v * v;
      }
      return sum * F / n;
    };
    const double limit = svo_bw_sg_limit(float(kappa));
    const double total = energy(2 * std::sqrt(kappa));
    EXPECT_NEAR(energy(limit) / total, 0.95, 0.03) << "kappa " << kappa;
  }
  EXPECT_EQ(svo_bw_sg_limit(0), SVO_BW_INFINITE);
  // The slope limit is the kernel of the reflected directions' spread.
  EXPECT_FLOAT_EQ(svo_bw_slope_limit(0.01f), svo_bw_sg_limit(25.0f));
}

TEST(BandwidthOps, VarianceTermOfEq9) {
  EXPECT_FLOAT_EQ(svo_bw_variance_term(3, 1, 2), 16.0f);
  EXPECT_TRUE(std::isfinite(svo_bw_variance_term(SVO_BW_INFINITE, SVO_BW_INFINITE, 1e3f)));
}

}  // namespace
