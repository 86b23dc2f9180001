// Smith Lambda (Heitz & Neyret Eq. 6) against a long double reference.
#include <gtest/gtest.h>

#include <cmath>

#include "common/shared_math.h"
#include "numerics/reference.h"

namespace {
using namespace svo::math;
using svo::test::lambda_ref;

// Relative error of Lambda(a) where the reference exceeds 1e-30 (below that
// float cannot hold the value with 1e-4 relative accuracy anyway) and is
// below the saturation value.
TEST(Smith, LambdaOfAWithin1e4Relative) {
  double worst = 0;
  float at = 0;
  int checked = 0;
  for (int i = 0; i <= 400000; ++i) {
    float a = float(std::pow(10.0, -8.0 + 9.0 * i / 400000.0));  // 1e-8 .. 10
    long double ref = lambda_ref((long double)a);
    float got = svo_smith_lambda_a(a);
    ASSERT_GE(got, 0.0f) << "a = " << a;
    if (ref <= 1e-30L || ref >= SVO_LAMBDA_MAX) continue;
    double rel = double(std::abs((long double)got - ref) / ref);
    ++checked;
    if (rel > worst) worst = rel, at = a;
  }
  EXPECT_GT(checked, 300000);
  EXPECT_LE(worst, 1e-4) << "at a = " << at;
  std::printf("max relative error of Lambda(a): %.3g at a = %.9g\n", worst, at);
}

TEST(Smith, LambdaOfMuSigmaWithin1e4Relative) {
  double worst = 0;
  for (int i = 0; i <= 600; ++i) {
    float mu = float(std::pow(10.0, -6.0 + 10.0 * i / 600.0));
    for (int j = 0; j <= 600; ++j) {
      float sigma = float(std::pow(10.0, -6.0 + 7.0 * j / 600.0));
      long double ref = lambda_ref((long double)mu, (long double)sigma);
      float got = svo_smith_lambda(mu, sigma);
      ASSERT_GE(got, 0.0f);
      if (ref <= 1e-30L || ref >= SVO_LAMBDA_MAX) continue;
      worst = std::max(worst, double(std::abs((long double)got - ref) / ref));
    }
  }
  EXPECT_LE(worst, 1e-4);
}

// The direction forms agree with the reference for the direction they are
// given: cos(theta) as a float, or a vector.
TEST(Smith, DirectionFormsMatchTheReference) {
  for (float theta = 0.001f; theta < 1.5707f; theta += 0.0013f) {
    for (float sigma : {0.01f, 0.1f, 0.5f, 2.0f}) {
      float c = std::cos(theta);
      long double cl = c;
      long double ref = lambda_ref(cl / std::sqrt((1 - cl) * (1 + cl)), (long double)sigma);
      if (ref > 1e-30L && ref < SVO_LAMBDA_MAX) {
        EXPECT_NEAR(svo_smith_lambda_cos(c, sigma) / double(ref), 1.0, 1e-4) << theta << " " << sigma;
      }
      for (float phi : {0.0f, 0.7f, 2.0f}) {
        vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), c);
        long double wx = w.x, wy = w.y, wz = w.z;
        long double ref_w = lambda_ref(wz / std::sqrt(wx * wx + wy * wy), (long double)sigma);
        if (ref_w > 1e-30L && ref_w < SVO_LAMBDA_MAX) {
          EXPECT_NEAR(svo_smith_lambda_dir(w, vec2(sigma * sigma)) / double(ref_w), 1.0, 1e-4)
              << theta << " " << sigma << " " << phi;
        }
      }
    }
  }
}

// Anisotropy: the slope variance seen by a direction is the variance along its azimuth.
TEST(Smith, AnisotropicLambdaUsesProjectedVariance) {
  vec3 along_x = normalize(vec3(1.0f, 0.0f, 0.5f));
  vec3 along_y = normalize(vec3(0.0f, 1.0f, 0.5f));
  vec2 s2(0.04f, 0.36f);
  EXPECT_NEAR(svo_smith_lambda_dir(along_x, s2) / svo_smith_lambda(0.5f, 0.2f), 1.0, 1e-5);
  EXPECT_NEAR(svo_smith_lambda_dir(along_y, s2) / svo_smith_lambda(0.5f, 0.6f), 1.0, 1e-5);
  EXPECT_GT(svo_smith_lambda_dir(along_y, s2), 10.0f * svo_smith_lambda_dir(along_x, s2));
}

TEST(Smith, LambdaDecreasesWithA) {
  float previous = SVO_LAMBDA_MAX;
  for (int i = 0; i <= 100000; ++i) {
    float a = float(1e-6 + 9.0 * i / 100000.0);
    float l = svo_smith_lambda_a(a);
    ASSERT_LE(l, previous * (1.0f + 1e-6f)) << "a = " << a;
    previous = l;
  }
}

TEST(Smith, HeightCdfAndSigmoid) {
  for (float h = -6.0f; h <= 6.0f; h += 0.01f) {
    for (float sigma_h : {0.1f, 1.0f, 3.0f}) {
      double x = double(h) / (std::sqrt(2.0) * sigma_h);
      EXPECT_NEAR(svo_height_cdf(h, sigma_h), 0.5 * std::erfc(-x), 2e-7);
      EXPECT_NEAR(svo_height_sigmoid(h, sigma_h), std::erf(x), 2e-7);
    }
  }
  // The lower tail keeps relative accuracy: g(h) = erfc(-x)/2, no 1 - (1 - tiny).
  EXPECT_NEAR(svo_height_cdf(-8.0f, 1.0f) / (0.5 * std::erfc(8.0 / std::sqrt(2.0))), 1.0, 1e-5);
}

}  // namespace
