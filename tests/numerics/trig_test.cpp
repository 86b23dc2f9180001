// svo_atan2 (shared math; the built-in atan is too loose on Vulkan) against std::atan2.
#include <gtest/gtest.h>

#include <cmath>

#include "common/shared_math.h"

namespace {
using namespace svo::math;

TEST(Trig, Atan2WithinThreeTenthsOfAMicroradian) {
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    double angle = -M_PI + 2.0 * M_PI * (i + 0.5) / 200000.0;
    for (double radius : {1e-30, 1e-3, 1.0, 1e20}) {
      float x = float(radius * std::cos(angle));
      float y = float(radius * std::sin(angle));
      double err = std::abs(double(svo_atan2(y, x)) - std::atan2(double(y), double(x)));
      worst = std::max(worst, err);
    }
  }
  EXPECT_LE(worst, 3e-7);
}

TEST(Trig, Atan2Axes) {
  EXPECT_EQ(svo_atan2(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(svo_atan2(0.0f, 1.0f), 0.0f);
  EXPECT_NEAR(svo_atan2(1.0f, 0.0f), M_PI / 2, 1e-7);
  EXPECT_NEAR(svo_atan2(-1.0f, 0.0f), -M_PI / 2, 1e-7);
  EXPECT_NEAR(svo_atan2(0.0f, -1.0f), M_PI, 3e-7);
  EXPECT_NEAR(svo_atan2(1.0f, 1.0f), M_PI / 4, 1e-7);
}

}  // namespace
