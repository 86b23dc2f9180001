// svo_erf / svo_erfc against std::erf / std::erfc (DESIGN section 5: GLSL has
// no erf; ours must be within 2e-7 absolute in float).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "common/shared_math.h"

namespace {
using namespace svo::math;

// Every float in [-12, 12] on a fine grid plus both sides of each branch edge.
std::vector<float> erf_arguments() {
  std::vector<float> xs;
  const int n = 2000000;
  for (int i = 0; i <= n; ++i) xs.push_back(float(-12.0 + 24.0 * double(i) / n));
  for (float edge : {SVO_ERF_SPLIT, 10.0f, 0.0f, 1e-30f, 1e-40f}) {
    for (float s : {1.0f, -1.0f}) {
      float x = s * edge;
      xs.push_back(x);
      xs.push_back(std::nextafter(x, 100.0f));
      xs.push_back(std::nextafter(x, -100.0f));
    }
  }
  return xs;
}

TEST(Erf, AbsoluteErrorWithin2e7OnMinus12To12) {
  double worst_erf = 0, worst_erfc = 0;
  float at_erf = 0, at_erfc = 0;
  for (float x : erf_arguments()) {
    double e1 = std::abs(double(svo_erf(x)) - std::erf(double(x)));
    double e2 = std::abs(double(svo_erfc(x)) - std::erfc(double(x)));
    if (e1 > worst_erf) worst_erf = e1, at_erf = x;
    if (e2 > worst_erfc) worst_erfc = e2, at_erfc = x;
  }
  RecordProperty("max_abs_error_erf", std::to_string(worst_erf));
  RecordProperty("max_abs_error_erfc", std::to_string(worst_erfc));
  EXPECT_LE(worst_erf, 2e-7) << "at x = " << at_erf;
  EXPECT_LE(worst_erfc, 2e-7) << "at x = " << at_erfc;
  std::printf("max |erf error| %.3g at %.9g, max |erfc error| %.3g at %.9g\n", worst_erf, at_erf, worst_erfc, at_erfc);
}

// Smith Lambda subtracts erfc from a nearby term: erfc must be accurate
// relative to its own size for x >= 0, not only in absolute terms.
TEST(Erf, ErfcRelativeErrorBelow1e6ForPositiveArguments) {
  double worst = 0;
  float at = 0;
  for (int i = 0; i <= 400000; ++i) {
    float x = float(10.0 * i / 400000.0);
    double ref = std::erfc(double(x));
    if (ref < 1e-37) continue;  // float's normal range
    double rel = std::abs(double(svo_erfc(x)) - ref) / ref;
    if (rel > worst) worst = rel, at = x;
  }
  EXPECT_LE(worst, 1e-6) << "at x = " << at;
}

TEST(Erf, ErfcxMatchesScaledErfc) {
  for (float x = SVO_ERF_SPLIT; x < 12.0f; x += 0.01f) {
    double ref = std::exp(double(x) * x) * std::erfc(double(x));
    EXPECT_NEAR(svo_erfcx_large(x) / ref, 1.0, 1e-6) << "x = " << x;
  }
}

TEST(Erf, SymmetriesAndLimits) {
  for (float x : {0.1f, 0.5f, 0.84375f, 1.0f, 2.5f, 6.0f}) {
    EXPECT_EQ(svo_erf(-x), -svo_erf(x)) << x;
    EXPECT_NEAR(svo_erfc(-x) + svo_erfc(x), 2.0f, 2.4e-7f) << x;
  }
  EXPECT_EQ(svo_erf(0.0f), 0.0f);
  EXPECT_EQ(svo_erfc(0.0f), 1.0f);
  EXPECT_EQ(svo_erfc(30.0f), 0.0f);
  EXPECT_EQ(svo_erfc(-30.0f), 2.0f);
  EXPECT_EQ(svo_erf(1e30f), 1.0f);
  EXPECT_TRUE(std::isnan(svo_erfc(std::nanf(""))));
}

}  // namespace
