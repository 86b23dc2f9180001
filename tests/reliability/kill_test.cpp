// Nothing lost (issue 7): `svo voxelize` and `svo render` killed with SIGKILL
// in the middle of writing, or stopped by a full disk, leave the earlier
// file of the same name byte-identical and no partial file under that name
// (label: cli). The `svo` executable is SVO_EXE.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using svo::testing::bytes_of;
using svo::testing::Child;
using svo::testing::entries;
using svo::testing::Limits;
using svo::testing::start;
using svo::testing::wait_for;

// Waits for the child; returns its exit status, or 128 + signal; its stderr in `seen`.
int finished(Child& c, std::string& seen) {
  svo::testing::Outcome o = svo::testing::finish(c, seen);
  seen = o.err;
  return o.status;
}

int run(const std::vector<std::string>& args, std::string& seen, const Limits& limits = {}) {
  Child c = start(args, limits);
  return finished(c, seen);
}

std::vector<std::string> voxelize(const std::string& scene, const std::string& out) {
  return {"voxelize", "--scene", scene, "--resolution", "32", "-o", out};
}

// Killed after the temporary holds the payload and before its header and
// rename (the test hook): out.svo is the earlier file, byte for byte; the
// temporary was partly written, so the kill did land mid-write.
TEST(Kill, VoxelizeKilledMidWriteKeepsTheEarlierFile) {
  svo::testing::TempDir dir;
  const std::string out = dir / "out.svo";
  std::string log;
  ASSERT_EQ(run(voxelize("bumpy-sphere", out), log), 0) << log;
  const auto before = bytes_of(out);
  ASSERT_GT(before.size(), 1000u);

  Child c = start(voxelize("grooved-cylinder", out), {.stall = true});
  std::string seen;
  const bool stalled = wait_for(c, "stalled writing", seen, 120);
  ::kill(c.pid, SIGKILL);
  EXPECT_EQ(finished(c, seen), 128 + SIGKILL) << seen;
  ASSERT_TRUE(stalled) << seen;
  EXPECT_EQ(bytes_of(out), before) << "the earlier out.svo changed";
  auto names = entries(dir.path(), "out.svo");
  ASSERT_EQ(names.size(), 2u) << "expected out.svo and the killed run's temporary";
  EXPECT_EQ(names[0], "out.svo");
  EXPECT_EQ(names[1].rfind("out.svo.tmp-", 0), 0u) << names[1];
  EXPECT_GT(fs::file_size(dir.path() / names[1]), 1000u) << "the temporary was not partly written: the kill came early";
  // The earlier file still loads.
  std::string info;
  EXPECT_EQ(run({"info", out}, info), 0) << info;
}

TEST(Kill, RenderKilledMidWriteKeepsTheEarlierImages) {
  svo::testing::TempDir dir;
  const std::string svo = dir / "in.svo";
  std::string log;
  ASSERT_EQ(run(voxelize("bumpy-sphere", svo), log), 0) << log;
  for (const std::string ext : {".png", ".exr"}) {
    const std::string image = dir / ("frame" + ext);
    std::vector<std::string> args{"render", svo, "-o", image, "--width", "32", "--height", "24", "--cpu"};
    ASSERT_EQ(run(args, log), 0) << log;
    const auto before = bytes_of(image);
    ASSERT_GT(before.size(), 100u);
    args.insert(args.end(), {"--view", "close"});
    Child c = start(args, {.stall = true});
    std::string seen;
    const bool stalled = wait_for(c, "stalled writing", seen, 120);
    ::kill(c.pid, SIGKILL);
    EXPECT_EQ(finished(c, seen), 128 + SIGKILL) << seen;
    ASSERT_TRUE(stalled) << seen;
    EXPECT_EQ(bytes_of(image), before) << image << " changed";
    auto names = entries(dir.path(), "frame" + ext);
    ASSERT_EQ(names.size(), 2u);
    EXPECT_EQ(names[1].rfind("frame" + ext + ".tmp-", 0), 0u) << names[1];
    EXPECT_GT(fs::file_size(dir.path() / names[1]), 0u);
  }
}

// No test hook: killed at random moments through several runs, out.svo is
// always either the earlier file or the complete new one, never a mix. Weak
// alone (the write is a few milliseconds of a run): checked by hand, this
// test still passed with write_svo writing in place, while the hook test
// above failed, as it must.
TEST(Kill, VoxelizeKilledAtRandomTimesIsOldOrNew) {
  svo::testing::TempDir dir;
  const std::string old_path = dir / "old.svo", new_path = dir / "new.svo", out = dir / "out.svo";
  std::string log;
  ASSERT_EQ(run(voxelize("bumpy-sphere", old_path), log), 0) << log;
  auto t0 = Clock::now();
  ASSERT_EQ(run(voxelize("grooved-cylinder", new_path), log), 0) << log;
  const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto old_bytes = bytes_of(old_path), new_bytes = bytes_of(new_path);
  ASSERT_NE(old_bytes, new_bytes);
  std::mt19937 random(7);
  int old_kept = 0, new_complete = 0;
  for (int trial = 0; trial < 8; ++trial) {
    fs::copy_file(old_path, out, fs::copy_options::overwrite_existing);
    Child c = start(voxelize("grooved-cylinder", out));
    // Kill times spread over the whole run (a little past it, too).
    std::this_thread::sleep_for(std::chrono::duration<double>(
        seconds * 1.1 * (trial + std::uniform_real_distribution<double>(0, 1)(random)) / 8));
    ::kill(c.pid, SIGKILL);
    std::string seen;
    finished(c, seen);
    const auto now = bytes_of(out);
    if (now == old_bytes) {
      ++old_kept;
    } else {
      EXPECT_EQ(now, new_bytes) << "trial " << trial << ": out.svo is neither the earlier file nor the new one";
      ++new_complete;
    }
    for (const auto& name : entries(dir.path(), "out.svo.tmp-")) fs::remove(dir.path() / name);
  }
  std::printf("killed runs: %d left the earlier file, %d the complete new one\n", old_kept, new_complete);
  EXPECT_GT(old_kept, 0) << "no kill landed before the rename: the check did not run";
}

// A full disk (a file size limit: writes fail with EFBIG) is an error naming
// the file and the cause, and the earlier file stays as it was.
TEST(FullDisk, VoxelizeAndRenderFailCleanlyAndKeepTheEarlierFile) {
  svo::testing::TempDir dir;
  const std::string out = dir / "out.svo", image = dir / "frame.exr";
  std::string log;
  ASSERT_EQ(run(voxelize("bumpy-sphere", out), log), 0) << log;
  ASSERT_EQ(run({"render", out, "-o", image, "--width", "32", "--height", "24", "--cpu"}, log), 0) << log;
  const auto svo_before = bytes_of(out), image_before = bytes_of(image);

  std::string seen;
  EXPECT_EQ(run(voxelize("grooved-cylinder", out), seen, {.file_size = 4096}), 1) << seen;
  EXPECT_NE(seen.find(out + ": cannot write: writing "), std::string::npos) << seen;
  EXPECT_NE(seen.find("File too large"), std::string::npos) << seen;
  EXPECT_EQ(std::count(seen.begin(), seen.end(), '\n'), 1) << "one line: " << seen;
  EXPECT_EQ(bytes_of(out), svo_before);
  EXPECT_EQ(entries(dir.path(), "out.svo"), std::vector<std::string>{"out.svo"}) << "a temporary was left behind";

  seen.clear();
  EXPECT_EQ(run({"render", out, "-o", image, "--width", "64", "--height", "48", "--cpu", "--view", "close"}, seen,
                {.file_size = 1024}),
            1)
      << seen;
  EXPECT_NE(seen.find(image + ": cannot write"), std::string::npos) << seen;
  EXPECT_EQ(std::count(seen.begin(), seen.end(), '\n'), 1) << "one line: " << seen;
  EXPECT_EQ(bytes_of(image), image_before);
  EXPECT_EQ(entries(dir.path(), "frame.exr"), std::vector<std::string>{"frame.exr"}) << "a temporary was left behind";
}

}  // namespace
