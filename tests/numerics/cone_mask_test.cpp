// Cone-element masks (Heitz & Neyret section 5.4): the (theta, v) test must
// decide each footprint ray exactly as intersecting the element's two ends
// with the plane does, and the analytic coverage must match counting.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "common/shared_math.h"

namespace {
using namespace svo::math;

// Brute force: ray through footprint point w (unit disk) of an element of
// radius r and half-length l is covered iff one of its ends
// (r wx, r wy, +-l) lies on or below the plane x nx + y ny + z nz + hbar = 0.
bool covered_brute_force(vec2 w, vec3 n, float hbar, float r, float l) {
  auto below = [&](float z) { return r * w.x * n.x + r * w.y * n.y + z * n.z + hbar <= 0.0f; };
  return below(l) || below(-l);
}

TEST(ConeMask, ParametersReproduceTheRayPlaneTest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int agree = 0, total = 0;
  for (int plane = 0; plane < 2000; ++plane) {
    vec3 n = normalize(vec3(u(rng), u(rng), u(rng)));
    float r = 0.2f + std::abs(u(rng)), l = r;
    float hbar = 1.5f * u(rng);
    SvoMaskParams p = svo_cone_mask_params(n, hbar, r, l);
    for (int k = 0; k < 64; ++k) {
      vec2 w(u(rng), u(rng));
      if (dot(w, w) > 1.0f) continue;
      float margin = std::abs(w.x * n.x + w.y * n.y - (std::abs(n.z) * l - hbar) / r);
      if (margin < 1e-4f) continue;  // on the edge, rounding decides
      ++total;
      agree += svo_mask_covers(w, p) == covered_brute_force(w, n, hbar, r, l);
    }
  }
  EXPECT_EQ(agree, total);
  EXPECT_GT(total, 50000);
}

TEST(ConeMask, CoverageMatchesCountingAndIsMonotonic) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<vec2> points;
  while (points.size() < 400000) {
    vec2 w(u(rng), u(rng));
    if (dot(w, w) <= 1.0f) points.push_back(w);
  }
  float previous = 0.0f;
  for (float v = -1.0f; v <= 1.0f; v += 0.05f) {
    SvoMaskParams p;
    p.theta = 0.7f;
    p.v = v;
    int inside = 0;
    for (vec2 w : points) inside += svo_mask_covers(w, p);
    float c = svo_mask_coverage(v);
    EXPECT_NEAR(c, double(inside) / points.size(), 3e-3) << "v = " << v;
    EXPECT_GE(c, previous);
    previous = c;
  }
  EXPECT_NEAR(svo_mask_coverage(0.0f), 0.5f, 1e-7f);
}

TEST(ConeMask, CoverageAccurateNearTheRim) {
  // Thin segments: f(v) ~ (2/3)(2(1+v))^(3/2) / pi near v = -1; no cancellation to zero.
  for (float e : {1e-2f, 1e-4f, 1e-6f}) {
    float vf = -1.0f + e;
    double v = vf;
    double phi = std::acos(-v);
    double exact = (phi + v * std::sqrt(1 - v * v)) / M_PI;
    float got = svo_mask_coverage(vf);
    EXPECT_NEAR(got / exact, 1.0, 1e-3) << "e = " << e;
  }
}

}  // namespace

// A cone element grazing a sphere of radius 1 (the cone along z, its
// element centred at (0, y0, zc), radius r, half-length l): the exact
// covered fraction of the footprint counts the rays through a fine grid of
// the disk that meet the ball within the element. The mean plane there
// (the distance |c| - 1 and the normal c / |c| at the centre c) covers too
// much of a convex silhouette; bent by the curvature along the axis,
// d^2 f / dz^2 = (1 - n_z^2) / |c|, the half-plane moves to the silhouette:
// within 0.02 of the exact fraction (what is left is the ball's curvature
// across the disk), where the plane is off by up to 0.064.
TEST(ConeMask, CurvatureAlongTheAxisFollowsAConvexSilhouette) {
  const float r = 0.15f, l = 0.15f;
  int cases = 0;
  double worst_plane = 0;
  for (float y0 : {0.9f, 0.97f, 1.0f, 1.03f, 1.08f}) {
    for (float zc : {-0.15f, 0.0f, 0.1f, 0.15f}) {
      const vec3 c(0.0f, y0, zc);
      const float dist = length(c);
      const vec3 n = c / dist;
      const float hbar = dist - 1.0f, kappa = (1.0f - n.z * n.z) / dist;
      double covered = 0, count = 0;
      for (int i = -200; i <= 200; ++i) {
        for (int j = -200; j <= 200; ++j) {
          const double wx = i / 200.0, wy = j / 200.0;
          if (wx * wx + wy * wy > 1.0) continue;
          const double x = r * wx, y = y0 + r * wy;
          const double zmin = std::clamp(0.0, double(zc - l), double(zc + l));  // closest to the centre
          count += 1;
          covered += x * x + y * y + zmin * zmin <= 1.0 ? 1.0 : 0.0;
        }
      }
      const double exact = covered / count;
      const double flat = svo_mask_coverage(svo_cone_mask_params(n, hbar, r, l).v);
      const double curved = svo_mask_coverage(svo_cone_mask_params_curved(n, hbar, r, l, kappa).v);
      std::printf("y0 %.2f zc %+.2f: exact %.3f, plane %.3f, curved %.3f\n", y0, zc, exact, flat, curved);
      EXPECT_LE(std::abs(curved - exact), std::abs(flat - exact) + 1e-3) << y0 << ", " << zc;
      EXPECT_NEAR(curved, exact, 0.02) << y0 << ", " << zc;
      worst_plane = std::max(worst_plane, std::abs(flat - exact));
      ++cases;
    }
  }
  EXPECT_EQ(cases, 20);
  EXPECT_GT(worst_plane, 0.05);  // the plane alone is off by more (0.064 measured)
}
