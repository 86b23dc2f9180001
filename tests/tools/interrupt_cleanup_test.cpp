// The table of live temporaries that SIGINT, SIGTERM and SIGHUP remove
// (octree/src/files.cpp): what the handler removes, in-process; the signals
// themselves are sent to `svo` in tests/reliability/kill_test.cpp (label: tools).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "render/temp_dir.h"
#include "svo/octree/files.h"

namespace {

namespace fs = std::filesystem;

TEST(InterruptCleanup, RemovesLiveTemporariesAndStagingDirectoriesOnly) {
  svo::testing::TempDir dir;
  svo::files::write_file(dir / "kept.txt", "earlier");
  const size_t before = svo::files::live_temporaries();
  {
    svo::files::OutputFile out(dir / "kept.txt");
    out.write("new", 3);
    svo::files::StagingDirectory stage(dir.path(), ".stage-tmp-");
    for (int i = 0; i < 300; ++i) std::ofstream(stage.path() / ("frame_" + std::to_string(i) + ".png")) << i;
    svo::files::OutputFile inside((stage.path() / "frames.csv").string());
    EXPECT_EQ(svo::files::live_temporaries(), before + 3);
    ASSERT_TRUE(fs::exists(out.temporary()));
    svo::files::remove_live_temporaries_for_test();
    EXPECT_FALSE(fs::exists(out.temporary()));
    EXPECT_FALSE(fs::exists(stage.path())) << "the staging directory and its 300 files";
  }
  EXPECT_EQ(svo::files::live_temporaries(), before);
  // The committed file is not a temporary: never touched.
  {
    svo::files::OutputFile out(dir / "new.txt");
    out.write("x", 1);
    out.commit();
    EXPECT_EQ(svo::files::live_temporaries(), before);
  }
  svo::files::remove_live_temporaries_for_test();
  EXPECT_TRUE(fs::exists(dir / "new.txt"));
  std::ifstream kept(dir / "kept.txt");
  std::string text;
  kept >> text;
  EXPECT_EQ(text, "earlier");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"kept.txt", "new.txt"}));
}

}  // namespace
