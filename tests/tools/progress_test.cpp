// The progress bar's line (tools/progress.h): durations, rates, the time
// left, and whether it is drawn at all (label: tools).
#include "progress.h"

#include <gtest/gtest.h>
#include <stdlib.h>

namespace {

using svo::tools::format_duration;
using svo::tools::format_progress_line;
using svo::tools::format_rate;
using svo::tools::ProgressLine;

TEST(Progress, DurationsAreMinutesSecondsThenHours) {
  EXPECT_EQ(format_duration(0), "0:00");
  EXPECT_EQ(format_duration(7.4), "0:07");
  EXPECT_EQ(format_duration(59.6), "1:00");
  EXPECT_EQ(format_duration(272), "4:32");
  EXPECT_EQ(format_duration(3599), "59:59");
  EXPECT_EQ(format_duration(3723), "1:02:03");
  EXPECT_EQ(format_duration(-1), "?");
  EXPECT_EQ(format_duration(std::numeric_limits<double>::infinity()), "?");
  EXPECT_EQ(format_duration(std::nan("")), "?");
}

TEST(Progress, RatesAreItemsPerSecondOrSecondsPerItem) {
  EXPECT_EQ(format_rate(1.523, "frames"), "1.52 frames/s");
  EXPECT_EQ(format_rate(12.34, "rows"), "12.3 rows/s");
  EXPECT_EQ(format_rate(4567.8, "bricks"), "4568 bricks/s");
  // A slow frame: seconds per frame, the unit singular.
  EXPECT_EQ(format_rate(1.0 / 4.5, "frames"), "4.50 s/frame");
  EXPECT_EQ(format_rate(1.0 / 130, "frames"), "130 s/frame");
  EXPECT_EQ(format_rate(0, "frames"), "");
  EXPECT_EQ(format_rate(-2, "frames"), "");
}

TEST(Progress, LineShowsStageCountRateElapsedAndLeft) {
  ProgressLine p;
  p.title = "flythrough";
  p.stage = "rendering";
  p.done = 20;
  p.total = 60;
  p.fraction = 20.0 / 60.0;
  p.rate = 1.52;
  p.unit = "frames";
  p.elapsed = 13.2;
  p.left = 26.3;
  EXPECT_EQ(format_progress_line(p),
            "flythrough [#######             ]  33% rendering 20/60  1.52 frames/s  0:13 elapsed, 0:26 left");
}

TEST(Progress, UncountedLineHasNoRateAndUnknownTimeLeftIsOmitted) {
  ProgressLine p;
  p.title = "voxelize";
  p.stage = "distance field";
  p.fraction = 0;
  p.elapsed = 42;
  EXPECT_EQ(format_progress_line(p), "voxelize [                    ]   0% distance field  0:42 elapsed");
  p.fraction = 1.0;
  p.left = 0;
  p.stage = "done";
  EXPECT_EQ(format_progress_line(p), "voxelize [####################] 100% done  0:42 elapsed");
  p.fraction = 7;  // clamped
  EXPECT_NE(format_progress_line(p).find("100%"), std::string::npos);
}

// Quiet when stderr is not a terminal (under ctest it is a pipe or a file),
// unless SVO_PROGRESS=1 forces it; SVO_PROGRESS=0 silences it anywhere.
TEST(Progress, DrawnOnATerminalOrWhenForced) {
  ::unsetenv("SVO_PROGRESS");
  EXPECT_EQ(svo::tools::progress_enabled(), ::isatty(STDERR_FILENO) == 1);
  ::setenv("SVO_PROGRESS", "1", 1);
  EXPECT_TRUE(svo::tools::progress_enabled());
  ::setenv("SVO_PROGRESS", "0", 1);
  EXPECT_FALSE(svo::tools::progress_enabled());
  ::unsetenv("SVO_PROGRESS");
}

// The bar itself, forced on, writes carriage-return lines with the rate and
// the time left to stderr; off, nothing.
TEST(Progress, BarWritesRateAndTimeLeft) {
  ::setenv("SVO_PROGRESS", "1", 1);
  ::testing::internal::CaptureStderr();
  {
    svo::tools::ProgressBar bar("test");
    bar.update("rendering", 0, 10, "frames");
    ::usleep(150000);
    bar.update("rendering", 3, 10, "frames");
  }
  std::string drawn = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(drawn.find("\rtest ["), std::string::npos) << drawn;
  EXPECT_NE(drawn.find("rendering 3/10"), std::string::npos) << drawn;
  EXPECT_NE(drawn.find("frames/s"), std::string::npos) << drawn;
  EXPECT_NE(drawn.find(" left"), std::string::npos) << drawn;
  EXPECT_EQ(drawn.back(), '\n');
  ::setenv("SVO_PROGRESS", "0", 1);
  ::testing::internal::CaptureStderr();
  {
    svo::tools::ProgressBar bar("test");
    bar.update("rendering", 3, 10, "frames");
    bar.update("other", 0.5);
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ::unsetenv("SVO_PROGRESS");
}

}  // namespace
