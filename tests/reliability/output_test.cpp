// Reliability round two (issue 22), outputs: every file the engine writes
// goes through svo::files::OutputFile. A full disk fails cleanly and keeps
// the earlier file; a link planted at the temporary's name is never written
// through; read-only and non-regular outputs are refused before any work; a
// symbolic link is written through keeping its target's mode; temporaries of
// killed runs are removed by the next write; a flythrough replaces its set
// of files together (label: cli).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>

#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using svo::testing::bytes_of;
using svo::testing::entries;
using svo::testing::Limits;
using svo::testing::Outcome;
using svo::testing::run_svo;
using svo::testing::TempDir;

std::vector<std::string> render_args(const std::string& svo, const std::string& out, int size = 32) {
  return {"render", svo, "-o", out, "--width", std::to_string(size), "--height", std::to_string(size), "--cpu"};
}

// A small octree in `dir`, and a PNG and an EXR rendered from it.
struct Scene {
  explicit Scene(const TempDir& dir) : svo(dir / "in.svo"), png(dir / "keep.png"), exr(dir / "keep.exr") {
    Outcome o = run_svo({"voxelize", "--scene", "bumpy-sphere", "--resolution", "32", "-o", svo});
    if (o.status != 0) throw std::runtime_error("voxelize failed: " + o.err);
    for (const std::string& out : {png, exr}) {
      o = run_svo(render_args(svo, out, 48));
      if (o.status != 0) throw std::runtime_error("render failed: " + o.err);
    }
  }
  std::string svo, png, exr;
};

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// The PID of a process that has exited and been reaped.
pid_t dead_pid() {
  pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

std::string mode_of(const std::string& path) {
  struct stat st {};
  ::stat(path.c_str(), &st);
  char text[8];
  std::snprintf(text, sizeof text, "%03o", st.st_mode & 0777);
  return text;
}

// Item 1: the PNG writer ignored failed writes; a full disk (here a file
// size limit, SIGXFSZ ignored: writes fail with EFBIG) left a truncated PNG
// that replaced the earlier image with exit 0. The same writer serves
// compare --diff.
TEST(Output, FullDiskKeepsTheEarlierPng) {
  TempDir dir;
  Scene scene(dir);
  const auto before = bytes_of(scene.png);
  Outcome o = run_svo(render_args(scene.svo, scene.png, 512), {.file_size = 8192});
  EXPECT_EQ(o.status, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_NE(o.err.find(scene.png + ": cannot write: writing "), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("File too large"), std::string::npos) << o.err;
  EXPECT_EQ(bytes_of(scene.png), before);
  EXPECT_EQ(entries(dir.path(), "keep.png"), std::vector<std::string>{"keep.png"}) << "a temporary was left";

  // compare --diff: the same writer.
  const std::string diff = dir / "diff.png";
  ASSERT_EQ(run_svo({"compare", scene.png, scene.png, "--diff", diff}).status, 0);
  const auto diff_before = bytes_of(diff);
  Outcome c = run_svo({"compare", scene.png, scene.exr, "--diff", diff}, {.file_size = 64});
  EXPECT_EQ(c.status, 1) << c.err;
  EXPECT_NE(c.err.find(diff + ": cannot write"), std::string::npos) << c.err;
  EXPECT_EQ(bytes_of(diff), diff_before);
}

// Item 2: a link planted at the exact name of the temporary (same PID: the
// harness plants it after fork, before exec) is skipped, never written
// through: its target is unchanged and the output is a regular file.
TEST(Output, PlantedLinkAtTheTemporaryIsNotFollowed) {
  TempDir dir;
  Scene scene(dir);
  const std::string victim = dir / "victim.txt";
  write_text(victim, "precious\n");
  struct Case {
    std::string out;
    std::vector<std::string> args;
  };
  const std::string png = dir / "new.png", exr = dir / "new.exr", svo = dir / "new.svo", cam = dir / "cam.json";
  std::vector<Case> cases{
      {png, render_args(scene.svo, png)},
      {exr, render_args(scene.svo, exr)},
      {svo, {"voxelize", "--scene", "bumpy-sphere", "--resolution", "32", "-o", svo}},
      {cam,
       {"render", scene.svo, "-o", dir / "c.png", "--width", "16", "--height", "16", "--cpu", "--save-camera", cam}},
  };
  for (const Case& c : cases) {
    Limits limits;
    limits.before_exec = [&] {
      for (int n = 0; n < 4; ++n) {
        const std::string name = c.out + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n);
        if (::symlink(victim.c_str(), name.c_str()) != 0) ::_exit(99);
      }
    };
    Outcome o = run_svo(c.args, limits);
    EXPECT_EQ(o.status, 0) << c.out << ": " << o.err;
    EXPECT_EQ(bytes_of(victim), std::vector<char>({'p', 'r', 'e', 'c', 'i', 'o', 'u', 's', '\n'})) << c.out;
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(c.out))) << c.out << " is not a regular file";
    EXPECT_GT(fs::file_size(c.out), 0u) << c.out;
  }
}

// Item 2, --video: ffmpeg (a stand-in script on PATH that records its
// arguments) writes into the exclusively created temporary, named with the
// container, never onto a fixed name with -y.
TEST(Output, VideoIsWrittenThroughAnExclusiveTemporary) {
  TempDir dir;
  Scene scene(dir);
  const fs::path bin = dir.path() / "bin";
  fs::create_directory(bin);
  // The stand-in records its arguments and where its output descriptor
  // leads, then writes through it.
  write_text(bin / "ffmpeg", "#!/bin/sh\necho \"$@\" > \"" + (dir / "ffmpeg-args") +
                                 "\"\nfor last; do :; done\nreadlink \"$last\" > \"" + (dir / "ffmpeg-output") +
                                 "\"\n[ -f \"$last\" ] || exit 3\nprintf video > \"$last\"\n");
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const std::string victim = dir / "victim.txt", video = dir / "fly.mp4";
  write_text(victim, "precious\n");
  // The fixed name of the old code, planted.
  ASSERT_EQ(::symlink(victim.c_str(), (dir / ".fly.tmp.mp4").c_str()), 0);
  Limits limits;
  limits.env = {{"PATH", bin.string() + ":/usr/bin:/bin"}};
  Outcome o = run_svo({"flythrough", scene.svo, "-o", dir / "fly", "--frames", "3", "--width", "32", "--height", "24",
                       "--strip", "0", "--video", video},
                      limits);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(bytes_of(video), std::vector<char>({'v', 'i', 'd', 'e', 'o'}));
  EXPECT_EQ(bytes_of(victim).size(), 9u) << "the planted link was written through";
  std::ifstream args_file(dir / "ffmpeg-args");
  std::string args((std::istreambuf_iterator<char>(args_file)), std::istreambuf_iterator<char>());
  // ffmpeg is given a descriptor of the exclusive temporary, not its name.
  EXPECT_NE(args.find("-f mp4 /dev/fd/"), std::string::npos) << args;
  std::ifstream output_file(dir / "ffmpeg-output");
  std::string output((std::istreambuf_iterator<char>(output_file)), std::istreambuf_iterator<char>());
  EXPECT_EQ(output.rfind(video + ".tmp-", 0), 0u) << output;
  EXPECT_EQ(entries(dir.path(), "fly.mp4"), std::vector<std::string>{"fly.mp4"});
}

// Item 11: a read-only file is refused, before any work, even for root; a
// FIFO or a directory as the output is refused; the files stay as they were.
TEST(Output, ReadOnlyAndNonRegularOutputsAreRefusedFirst) {
  TempDir dir;
  Scene scene(dir);
  const auto before = bytes_of(scene.png);
  ::chmod(scene.png.c_str(), 0444);
  Outcome o = run_svo(render_args(scene.svo, scene.png));
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.err, "svo: " + scene.png + ": is read-only; make it writable (chmod u+w) or remove it to replace it\n");
  EXPECT_EQ(bytes_of(scene.png), before);
  EXPECT_EQ(mode_of(scene.png), "444");

  const std::string fifo = dir / "pipe.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  o = run_svo(render_args(scene.svo, fifo), {.seconds = 20});
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.err, "svo: " + fifo + ": is a FIFO; outputs replace only regular files\n");

  // voxelize into a directory: refused before the work (it used to voxelize
  // first and fail at the rename).
  const std::string sub = dir / "sub.svo";  // named as an octree, so that the extension check passes
  fs::create_directory(sub);
  o = run_svo({"voxelize", "--scene", "bumpy-sphere", "--resolution", "256", "-o", sub});
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.err, "svo: " + sub + ": is a directory; outputs replace only regular files\n");
  EXPECT_LT(o.seconds, 5.0) << "the voxelization ran before the output was checked";
}

// Item 11: a symbolic link as the output is written through to its target
// (the link stays a link) and an existing file keeps its mode.
TEST(Output, LinkWrittenThroughAndModeKept) {
  TempDir dir;
  Scene scene(dir);
  const std::string target = dir / "real.png", link = dir / "link.png";
  fs::copy_file(scene.png, target);
  ::chmod(target.c_str(), 0640);
  ASSERT_EQ(::symlink(target.c_str(), link.c_str()), 0);
  const auto before = bytes_of(target);
  Outcome o = run_svo(render_args(scene.svo, link, 24));
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link), target);
  EXPECT_NE(bytes_of(target), before) << "the target was not rewritten";
  EXPECT_EQ(mode_of(target), "640");

  ::chmod(scene.svo.c_str(), 0600);
  o = run_svo({"voxelize", "--scene", "grooved-cylinder", "--resolution", "32", "-o", scene.svo});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(mode_of(scene.svo), "600");

  // A dangling link is refused.
  const std::string dangling = dir / "dangling.png";
  ASSERT_EQ(::symlink((dir.path() / "missing" / "x.png").c_str(), dangling.c_str()), 0);
  o = run_svo(render_args(scene.svo, dangling));
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_NE(o.err.find(dangling + ": a symbolic link to a missing file"), std::string::npos) << o.err;
}

// Item 8: temporaries of killed runs (their PID gone) are removed by the
// next write of the same name; a live process's temporary is left alone.
TEST(Output, StaleTemporariesOfDeadRunsAreRemoved) {
  TempDir dir;
  Scene scene(dir);
  const pid_t dead = dead_pid();
  const std::string stale = scene.png + ".tmp-" + std::to_string(dead) + "-0";
  const std::string live = scene.png + ".tmp-" + std::to_string(::getpid()) + "-0";
  const std::string stale_svo = scene.svo + ".tmp-" + std::to_string(dead) + "-3";
  write_text(stale, "partial");
  write_text(live, "in progress");
  write_text(stale_svo, "partial");
  ASSERT_EQ(run_svo(render_args(scene.svo, scene.png)).status, 0);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  ASSERT_EQ(run_svo({"voxelize", "--scene", "bumpy-sphere", "--resolution", "32", "-o", scene.svo}).status, 0);
  EXPECT_FALSE(fs::exists(stale_svo));
}

// Item 8: a flythrough killed mid-run leaves the earlier run's frames, CSV
// and path as they were (its files were staged inside DIR); the next run
// removes the killed run's staging directory and replaces the set, the
// earlier run's extra frames included.
TEST(Output, FlythroughReplacesItsSetTogether) {
  TempDir dir;
  Scene scene(dir);
  const std::string out = dir / "fly";
  auto fly = [&](int frames) {
    return std::vector<std::string>{"flythrough",           scene.svo, "-o", out,        "--frames",
                                    std::to_string(frames), "--width", "32", "--height", "24"};
  };
  ASSERT_EQ(run_svo(fly(5)).status, 0);
  const auto names = entries(out, "");
  ASSERT_EQ(names.size(), 8u) << "5 frames, frames.csv, path.json, strip.png";
  const auto csv = bytes_of(fs::path(out) / "frames.csv");

  svo::testing::Child c = svo::testing::start(fly(3), {.stall = true});
  std::string seen;
  const bool stalled = svo::testing::wait_for(c, "stalled writing", seen, 60);
  ::kill(c.pid, SIGKILL);
  svo::testing::finish(c, seen);
  ASSERT_TRUE(stalled) << seen;
  auto after_kill = entries(out, "");
  ASSERT_EQ(after_kill.size(), 9u) << "the earlier set and the killed run's staging directory";
  EXPECT_EQ(after_kill[0].rfind(".flythrough-tmp-", 0), 0u) << after_kill[0];
  EXPECT_EQ(bytes_of(fs::path(out) / "frames.csv"), csv);

  ASSERT_EQ(run_svo(fly(3)).status, 0);
  EXPECT_EQ(entries(out, ""), (std::vector<std::string>{"frame_0000.png", "frame_0001.png", "frame_0002.png",
                                                        "frames.csv", "path.json", "strip.png"}));
  // A run without a strip does not leave the earlier run's.
  auto no_strip = fly(2);
  no_strip.insert(no_strip.end(), {"--strip", "0"});
  ASSERT_EQ(run_svo(no_strip).status, 0);
  EXPECT_EQ(entries(out, ""),
            (std::vector<std::string>{"frame_0000.png", "frame_0001.png", "frames.csv", "path.json"}));
}

// A dead run's staging directory holding a set's manifest is completed by
// the next run into DIR (Interrupt.Publish*), but only for names of a
// run's outputs inside DIR: a manifest planted there naming "../x" or
// another file moves nothing out of DIR, and removes nothing of it.
TEST(Output, PlantedManifestMovesNothingOutOfDir) {
  TempDir dir;
  Scene scene(dir);
  const fs::path out = dir.path() / "fly";
  fs::create_directories(out);
  write_text((out / "keep.txt").string(), "not a frame");
  const fs::path stage = out / (".flythrough-tmp-" + std::to_string(dead_pid()) + "-0");
  fs::create_directories(stage);
  write_text((stage / "frame_0007.png").string(), "planted");
  write_text((stage / ".set").string(), "../keep.txt\nkeep.txt\n../../frame_0000.png\nframe_0007.png\n");
  ASSERT_EQ(run_svo({"flythrough", scene.svo, "-o", out.string(), "--frames", "2", "--width", "32", "--height",
                     "24", "--strip", "0"})
                .status,
            0);
  EXPECT_TRUE(fs::exists(out / "keep.txt"));
  EXPECT_FALSE(fs::exists(dir.path() / "keep.txt"));
  EXPECT_EQ(entries(out, ""),
            (std::vector<std::string>{"frame_0000.png", "frame_0001.png", "frames.csv", "keep.txt", "path.json"}));
}

}  // namespace
