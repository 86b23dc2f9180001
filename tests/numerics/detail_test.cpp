// The detail octaves' shared math (shaders/common/detail.glsl): the noise's
// variance constants against Monte Carlo, its gradient against finite
// differences, the explicit/statistical split, and the colour-height fold
// against a direct regression over synthetic Gaussian heights.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/shared_math.h"

namespace {

using namespace svo::math;

TEST(Detail, NoiseVarianceConstantsMatchMonteCarlo) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-500.0, 500.0);
  const int n = 1 << 21;
  double sum = 0, sum2 = 0, slope2 = 0, max_value = 0, max_gradient = 0;
  for (int i = 0; i < n; ++i) {
    vec4 g = svo_gradient_noise(vec3(float(u(rng)), float(u(rng)), float(u(rng))), 17u);
    sum += g.w;
    sum2 += double(g.w) * g.w;
    slope2 += (double(g.x) * g.x + double(g.y) * g.y + double(g.z) * g.z) / 3.0;
    max_value = std::max(max_value, double(std::abs(g.w)));
    max_gradient = std::max(max_gradient, double(length(vec3(g))));
  }
  double mean = sum / n;
  EXPECT_NEAR(mean, 0.0, 0.002);
  EXPECT_NEAR(sum2 / n - mean * mean, SVO_NOISE_VARIANCE, 0.01 * SVO_NOISE_VARIANCE);
  EXPECT_NEAR(slope2 / n, SVO_NOISE_SLOPE_VARIANCE, 0.01 * SVO_NOISE_SLOPE_VARIANCE);
  EXPECT_LE(max_value, SVO_NOISE_MAX);
  EXPECT_LE(max_gradient, SVO_NOISE_MAX_GRADIENT);
}

TEST(Detail, NoiseGradientMatchesFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-6.0f, 6.0f);
  const float e = 1e-3f;
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 p(u(rng), u(rng), u(rng));
    vec4 g = svo_gradient_noise(p, 9u);
    for (int a = 0; a < 3; ++a) {
      vec3 q = p, r = p;
      q[a] += e;
      r[a] -= e;
      double fd = (double(svo_gradient_noise(q, 9u).w) - double(svo_gradient_noise(r, 9u).w)) / (2.0 * e);
      worst = std::max(worst, std::abs(fd - double(g[a])));
    }
  }
  EXPECT_LT(worst, 0.003);
}

// From SVO_DETAIL_DRAWN_FROM radii (F) on, whole from 2 F.
TEST(Detail, AnOctaveIsExplicitAboveTwiceTheRampStartAndStatisticalBelowIt) {
  const float f = SVO_DETAIL_DRAWN_FROM;
  EXPECT_EQ(svo_detail_weight(2.0f * f, 1.0f), 1.0f);
  EXPECT_EQ(svo_detail_weight(100.0f, 1.0f), 1.0f);
  EXPECT_EQ(svo_detail_weight(f, 1.0f), 0.0f);
  EXPECT_EQ(svo_detail_weight(1.0f, 1.0f), 0.0f);
  EXPECT_EQ(svo_detail_weight(1.0f, 0.0f), 1.0f);
  EXPECT_GT(svo_detail_weight(1.5f * f, 1.0f), 0.0f);
  EXPECT_LT(svo_detail_weight(1.5f * f, 1.0f), 1.0f);
  float previous = 0;
  for (float lambda = f; lambda <= 2.0f * f; lambda += 0.01f * f) {
    float w = svo_detail_weight(lambda, 1.0f);
    EXPECT_GE(w, previous);
    previous = w;
  }
}

SvoDetail test_detail() {
  SvoDetail d;
  d.octaves = 8;
  d.seed = 4;
  d.amplitude = 0.01f;
  d.wavelength = 0.1f;
  d.gain = 0.5f;
  return d;
}

TEST(Detail, MovedVariancesAddUpAcrossFootprints) {
  SvoDetail d = test_detail();
  const float stored = 0.01f;
  vec2 all = svo_detail_moved_variance(d, 0.0f, stored);
  vec2 a = svo_detail_moved_variance(d, 0.004f, stored);
  vec2 b = svo_detail_moved_variance(d, 0.0f, 0.004f);
  EXPECT_NEAR(all.x, a.x + b.x, 1e-6f * all.x);
  EXPECT_NEAR(all.y, a.y + b.y, 1e-6f * all.y);
  // From no detail drawn to all of it: every octave's whole variance.
  vec2 whole(0);
  for (uint k = 0; k < d.octaves; ++k) {
    float amp = svo_detail_amplitude(d, k), lambda = svo_detail_wavelength(d, k);
    whole += amp * amp * vec2(SVO_NOISE_VARIANCE, SVO_NOISE_SLOPE_VARIANCE / (lambda * lambda));
  }
  vec2 total = svo_detail_moved_variance(d, 0.0f, 1e30f);
  EXPECT_NEAR(total.x, whole.x, 1e-5f * whole.x);
  EXPECT_NEAR(total.y, whole.y, 1e-5f * whole.y);
}

TEST(Detail, DisplacementDrawsOnlyTheOctavesBetweenTwoFootprints) {
  SvoDetail d = test_detail();
  vec3 p(0.31f, -0.27f, 0.05f);
  // Octave k is whole at r <= lambda_k / 2F and absent at r >= lambda_k / F.
  const float f = SVO_DETAIL_DRAWN_FROM;
  vec4 octave0 = svo_detail_octave(d, 0u, p);
  vec4 drawn = svo_detail_displacement(d, p, 0.1f / (2.0f * f), 0.1f / f);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(drawn[i], octave0[i], 1e-6f);
  vec4 none = svo_detail_displacement(d, p, 0.02f, 0.02f);
  EXPECT_EQ(none, vec4(0.0f));
}

// The loop-free bounds hold over random points, and are not loose by more
// than the whole octaves they count.
TEST(Detail, BoundsHoldTheDrawnDisplacementAndSlope) {
  SvoDetail d = test_detail();
  const float stored = 0.01f;
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (float r : {0.009f, 0.004f, 0.001f, 0.0001f}) {
    vec2 bounds = svo_detail_bounds(d, r, stored);
    float value = 0, slope = 0;
    for (int i = 0; i < 20000; ++i) {
      vec4 g = svo_detail_displacement(d, vec3(u(rng), u(rng), u(rng)), r, stored);
      value = std::max(value, std::abs(g.w));
      slope = std::max(slope, length(vec3(g)));
    }
    EXPECT_LE(value, bounds.x) << "r " << r;
    EXPECT_LE(slope, bounds.y) << "r " << r;
    if (value > 0) {
      EXPECT_LT(bounds.x, 8.0f * value) << "r " << r;
    }
  }
  // Nothing is drawn at footprints of a wavelength / F and more.
  EXPECT_EQ(svo_detail_bounds(d, 0.1f / SVO_DETAIL_DRAWN_FROM, stored), vec2(0.0f));
}

// The noise's second derivative along random directions (finite differences
// of its gradient) stays within the curvature bound the step bounds use.
TEST(Detail, NoiseCurvatureStaysWithinItsBound) {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-500.0, 500.0);
  std::normal_distribution<double> z(0.0, 1.0);
  const double e = 1e-3;
  double worst = 0;
  for (int i = 0; i < (1 << 20); ++i) {
    vec3 q(float(u(rng)), float(u(rng)), float(u(rng)));
    vec3 dir = normalize(vec3(float(z(rng)), float(z(rng)), float(z(rng))));
    vec4 a = svo_gradient_noise(q + float(e) * dir, 17u), b = svo_gradient_noise(q - float(e) * dir, 17u);
    worst = std::max(worst, std::abs(double(dot(vec3(a) - vec3(b), dir))) / (2 * e));
  }
  std::printf("largest second directional derivative: %.3f (bound %.1f)\n", worst, double(SVO_NOISE_MAX_CURVATURE));
  EXPECT_LE(worst, SVO_NOISE_MAX_CURVATURE);
  EXPECT_GT(worst, 0.5 * SVO_NOISE_MAX_CURVATURE);  // the bound is not loose
}

// How far the drawn displacement moves along a ray: the bounds hold at and
// before each of the four distances, and for the short ones they are well
// below the Lipschitz bound (the sum of the octaves' slope bounds), which
// is what lets a ray through the shell step farther.
TEST(Detail, ChangeAlongARayStaysWithinItsBounds) {
  SvoDetail d = test_detail();
  const float stored = 0.01f;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::normal_distribution<float> z(0.0f, 1.0f);
  const vec4 s(0.1f, 0.01f, 0.001f, 0.0001f);
  for (float r : {0.004f, 0.0005f, 0.0001f}) {
    const float lipschitz = svo_detail_bounds(d, r, stored).y;
    vec4 mean_change(0.0f);
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      vec3 p(u(rng), u(rng), u(rng));
      vec3 dir = normalize(vec3(z(rng), z(rng), z(rng)));
      SvoDetailSample at = svo_detail_displacement_along(d, p, r, stored, dir, s, 0.5f * s);
      ASSERT_EQ(at.change2, svo_detail_displacement_along(d, p, r, stored, dir, 0.5f * s, s).change);
      EXPECT_EQ(at.displacement, svo_detail_displacement(d, p, r, stored));
      mean_change += at.change / float(n);
      for (int k = 0; k < 4; ++k) {
        for (float f : {0.1f, 0.5f, 1.0f}) {
          float moved = svo_detail_displacement(d, p + f * s[k] * dir, r, stored).w - at.displacement.w;
          ASSERT_LE(std::abs(moved), at.change[k] * 1.0001f + 1e-9f) << "r " << r << ", s " << s[k] << " x " << f;
        }
        ASSERT_LE(at.change[k], lipschitz * s[k] * 1.0001f) << "r " << r << ", s " << s[k];
      }
    }
    std::printf("r %g: mean change / Lipschitz bound at s = %g: %.3f\n", r, s[3], mean_change[3] / (lipschitz * s[3]));
    if (lipschitz > 0) {
      EXPECT_LT(mean_change[3], 0.5f * lipschitz * s[3]) << "r " << r;
    }
  }
}

// Colour linear in two independent Gaussian heights: the fold of the second
// into the first's a_s must equal the regression over both (the statistic
// the voxelizer computes, statistics.h).
TEST(Detail, ColourFoldMatchesTheRegressionOverBothHeights) {
  const double s1 = 0.003, s2 = 0.002;
  const vec3 k1(20.0f, -5.0f, 3.0f), k2(40.0f, 10.0f, -30.0f);
  const int n = 1 << 20;
  auto regress = [&](double sigma, bool both) {
    double sxx = 0;
    dvec3 sxa(0);
    std::mt19937_64 local(11);
    std::normal_distribution<double> z(0.0, 1.0);
    for (int i = 0; i < n; ++i) {
      double h1 = s1 * z(local), h2 = s2 * z(local);
      double h = both ? h1 + h2 : h1;
      dvec3 a = dvec3(k1) * h1 + (both ? dvec3(k2) * h2 : dvec3(0));
      double s = std::erf(h / (std::sqrt(2.0) * sigma));
      sxx += s * s;
      sxa += s * a;
    }
    return vec3(sxa / sxx);
  };
  vec3 a1 = regress(s1, false);
  vec3 both = regress(std::sqrt(s1 * s1 + s2 * s2), true);
  vec3 folded = svo_detail_fold_a_s(a1, float(s1 * s1), float(s2 * s2), k2);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(folded[c], both[c], 0.01 * std::abs(both[c]) + 1e-4) << c;
  // And back: removing the second height's variance restores the first's.
  vec3 unfolded = svo_detail_fold_a_s(both, float(s1 * s1 + s2 * s2), -float(s2 * s2), k2);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(unfolded[c], a1[c], 0.01 * std::abs(a1[c]) + 1e-4) << c;
}

}  // namespace
