// Reliability round two (issue 22), inputs other than meshes: images given
// to `svo compare`, camera and camera-path files and octrees. A FIFO or a
// link to /dev/zero named as an input is refused before any library opens
// it (they hung, or grew past 800 MB, until killed); an image whose header
// declares more pixels than the budget is refused from that header. Each
// case: exit 1, one line naming the file and the problem, within seconds and
// a bounded memory (label: cli).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include "reliability/blank_png.h"
#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using svo::testing::Outcome;
using svo::testing::run_svo;
using svo::testing::TempDir;

constexpr double kSeconds = 5;  // a refusal takes about 1 s here (the executable's start)
// The bound on a run's peak memory: 150 MiB over the executable's start.
long peak_limit_kib() { return svo::testing::startup_peak_kib() + (150 << 10); }

// Runs `args`, killed after 30 s; expects exit 1 with the one line `line`
// (without "svo: " and the newline), within kSeconds and peak_limit_kib().
void expect_refused(const std::vector<std::string>& args, const std::string& line) {
  Outcome o = run_svo(args, {.seconds = 30});
  std::string all;
  for (const auto& a : args) all += " " + a;
  EXPECT_EQ(o.status, 1) << all << "\n" << o.err;
  EXPECT_EQ(o.err, "svo: " + line + "\n") << all;
  EXPECT_LT(o.seconds, kSeconds) << all;
  EXPECT_LT(o.peak_kib, peak_limit_kib()) << all;
}

struct Inputs {
  explicit Inputs(const TempDir& dir)
      : svo(dir / "in.svo"),
        png(dir / "a.png"),
        fifo(dir / "pipe"),
        zero_png(dir / "zero.png"),
        zero_json(dir / "zero.json") {
    if (run_svo({"voxelize", "--scene", "bumpy-sphere", "--resolution", "32", "-o", svo}).status != 0 ||
        run_svo({"render", svo, "-o", png, "--width", "32", "--height", "32", "--cpu"}).status != 0) {
      throw std::runtime_error("could not make the inputs");
    }
    if (::mkfifo(fifo.c_str(), 0644) != 0 || ::symlink("/dev/zero", zero_png.c_str()) != 0 ||
        ::symlink("/dev/zero", zero_json.c_str()) != 0) {
      throw std::runtime_error("could not make the FIFO and links");
    }
  }
  std::string svo, png, fifo, zero_png, zero_json;
};

TEST(ImageInput, CompareRefusesFifosAndDevices) {
  TempDir dir;
  Inputs in(dir);
  expect_refused({"compare", in.fifo, in.png}, in.fifo + ": is a FIFO, expected an image");
  expect_refused({"compare", in.png, in.zero_png}, in.zero_png + ": is a character device, expected an image");
  expect_refused({"compare", in.png, dir / "missing.png"}, dir / "missing.png" + ": does not exist");
}

// Two 8192 x 8192 PNGs of a few hundred KB: compare took 3.8 GB and 34 s.
TEST(ImageInput, CompareRefusesImagesOverItsPixelBudget) {
  TempDir dir;
  const std::string big = dir / "big.png", small = dir / "small.png";
  svo::testing::write_blank_png(big, 8192, 8192);
  svo::testing::write_blank_png(small, 64, 64);
  ASSERT_LT(fs::file_size(big), 1u << 20);
  expect_refused({"compare", big, big}, big + ": 8192x8192 pixels, more than the limit of 33554432 (--max-megapixels)");
  // Within the budget (and a raised budget) it is read.
  Outcome o = run_svo({"compare", small, small});
  EXPECT_EQ(o.status, 0) << o.err;
  o = run_svo({"compare", small, small, "--max-megapixels", "0.001"});
  EXPECT_EQ(o.status, 1);
  EXPECT_NE(o.err.find("64x64 pixels, more than the limit of 1048"), std::string::npos) << o.err;
}

TEST(ImageInput, CameraAndPathFilesMustBeRegular) {
  TempDir dir;
  Inputs in(dir);
  const std::vector<std::string> render{"render", in.svo,     "-o", dir / "x.png", "--width",
                                        "16",     "--height", "16", "--cpu"};
  auto with = [&](std::vector<std::string> args, std::initializer_list<std::string> more) {
    args.insert(args.end(), more);
    return args;
  };
  expect_refused(with(render, {"--camera-file", in.zero_json}),
                 in.zero_json + ": is a character device, expected a camera file (JSON)");
  expect_refused(with(render, {"--camera-file", in.fifo}), in.fifo + ": is a FIFO, expected a camera file (JSON)");
  expect_refused({"flythrough", in.svo, "-o", dir / "fly", "--path-file", in.zero_json},
                 in.zero_json + ": is a character device, expected a camera path file (JSON)");
  expect_refused({"info", in.fifo}, in.fifo + ": is a FIFO, expected a .svo file");
}

}  // namespace
