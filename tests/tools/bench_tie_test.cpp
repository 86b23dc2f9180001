// The speed-up claims of svo bench speed-error (tools/bench_tie.h): a tie
// when errors are within their noise, a speed-up only beyond it (label: tools).
#include "bench_tie.h"

#include <gtest/gtest.h>

namespace {

using svo::tools::bench::claim_at_equal_error;
using svo::tools::bench::CostErrorPoint;
using svo::tools::bench::errors_tie;
using Kind = svo::tools::bench::EqualErrorClaim::Kind;

TEST(BenchTie, ErrorsWithinTheToleranceOfTheLargerTie) {
  EXPECT_TRUE(errors_tie(0.100, 0.104));   // 3.8% of the larger
  EXPECT_TRUE(errors_tie(0.104, 0.100));   // symmetric
  EXPECT_FALSE(errors_tie(0.100, 0.106));  // 5.7%
  EXPECT_TRUE(errors_tie(0.100, 0.106, 0.06));
  EXPECT_TRUE(errors_tie(0, 0));
  EXPECT_FALSE(errors_tie(0, 1e-9));
}

// The case of issue 21: every method within 3% relMSE, ours a little below
// 64 rays per pixel. It used to read "at least 29.8x"; it is a tie, against
// the cheapest marching it ties (1 ray per pixel).
TEST(BenchTie, AllMethodsWithinThreePercentIsATieNotAtLeast) {
  const std::vector<CostErrorPoint> march{{"raymarch-1", 1.1, 0.0300},
                                          {"raymarch-4", 4.3, 0.0297},
                                          {"raymarch-16", 17, 0.0295},
                                          {"raymarch-64", 68, 0.0294}};
  auto c = claim_at_equal_error(2.28, 0.0291, march);
  EXPECT_EQ(c.kind, Kind::Tie);
  EXPECT_EQ(c.against, "raymarch-1");
  EXPECT_NEAR(c.factor, 1.1 / 2.28, 1e-12);
  EXPECT_DOUBLE_EQ(c.against_error, 0.0300);
  // With a tolerance below the spread (1%) the claim comes back, against
  // the most accurate point: the old "at least" (68 / 2.28 = 29.8x).
  c = claim_at_equal_error(2.28, 0.0291, march, 0.009);
  EXPECT_EQ(c.kind, Kind::AtLeast);
  EXPECT_NEAR(c.factor, 68 / 2.28, 1e-9);
  EXPECT_EQ(c.against, "raymarch-64");
}

TEST(BenchTie, ClearlyBracketedErrorIsAnInterpolatedSpeedup) {
  // Errors well apart: ours between 4 and 16 rays, at the geometric middle
  // of their errors: the time is the geometric middle of theirs (log-log).
  const std::vector<CostErrorPoint> march{
      {"raymarch-16", 16, 0.01}, {"raymarch-1", 1, 0.16}, {"raymarch-4", 4, 0.04}, {"raymarch-64", 64, 0.0025}};
  auto c = claim_at_equal_error(1.0, 0.02, march);
  EXPECT_EQ(c.kind, Kind::Speedup);
  EXPECT_NEAR(c.factor, 8.0, 1e-9);
  // Ours within 5% of 4 rays: a tie with it, no interpolation.
  c = claim_at_equal_error(1.0, 0.041, march);
  EXPECT_EQ(c.kind, Kind::Tie);
  EXPECT_EQ(c.against, "raymarch-4");
  EXPECT_NEAR(c.factor, 4.0, 1e-12);
}

TEST(BenchTie, BeyondTheCurveIsALowerBoundOrWorse) {
  const std::vector<CostErrorPoint> march{{"raymarch-1", 1, 0.16}, {"raymarch-64", 64, 0.01}};
  auto c = claim_at_equal_error(2.0, 0.005, march);  // half the best error: beyond the noise
  EXPECT_EQ(c.kind, Kind::AtLeast);
  EXPECT_NEAR(c.factor, 32.0, 1e-12);
  c = claim_at_equal_error(2.0, 0.5, march);
  EXPECT_EQ(c.kind, Kind::Worse);
  c = claim_at_equal_error(2.0, 0.01, {});
  EXPECT_EQ(c.kind, Kind::Worse);
}

}  // namespace
