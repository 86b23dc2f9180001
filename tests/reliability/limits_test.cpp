// Reliability round two (issue 22): limits cases through the svo executable.
// Each input is written here: an octree from `svo voxelize`, its header then
// edited and resealed (the header checksum recomputed, so that the value
// itself, not the checksum, must be refused), and camera or path text. Each
// case asserts exit status 1, one line on stderr naming the input and the
// problem, and a bound on time and peak memory.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <memory>

#define XXH_INLINE_ALL  // this test links no library: the header checksum is XXH64 of bytes [0, 120)
#include <xxhash.h>

#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using svo::testing::Limits;
using svo::testing::Outcome;
using svo::testing::run_svo;
using svo::testing::TempDir;

// Header fields (octree/include/svo/octree/svo_file.h; frozen by tests/octree/svo_file_golden_test.cpp).
constexpr off_t kOrigin = 24, kSize = 36, kFileBytes = 104, kHeaderChecksum = 120;

constexpr double kSeconds = 5;  // each refusal: well under, whatever the input states
// The bound on a run's peak memory: 150 MiB over the executable's start.
long peak_limit_kib() { return svo::testing::startup_peak_kib() + 150 * 1024; }
const Limits kLimits{.seconds = 60};  // a run past this is killed (and fails the time bound)

// Rewrites header bytes [at, at + n) of `path` with `value` and reseals the
// header checksum; the rest of the file is untouched (a sparse file stays so).
void edit_header(const std::string& path, off_t at, const void* value, size_t n) {
  const int fd = ::open(path.c_str(), O_RDWR);
  ASSERT_GE(fd, 0) << path;
  uint8_t header[128];
  ASSERT_EQ(::pread(fd, header, sizeof header, 0), ssize_t(sizeof header));
  std::memcpy(header + at, value, n);
  const uint64_t sum = XXH64(header, size_t(kHeaderChecksum), 0);
  std::memcpy(header + kHeaderChecksum, &sum, 8);
  ASSERT_EQ(::pwrite(fd, header, sizeof header, 0), ssize_t(sizeof header));
  ASSERT_EQ(::close(fd), 0);
}
template <typename T>
void edit_header(const std::string& path, off_t at, T value) {
  edit_header(path, at, &value, sizeof value);
}

// The one line of a refusal: "svo: " + what.
void expect_refused(const Outcome& o, const std::string& what) {
  EXPECT_EQ(o.status, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_EQ(o.err, "svo: " + what + "\n");
  EXPECT_LT(o.seconds, kSeconds) << o.err;
  EXPECT_LT(o.peak_kib, peak_limit_kib()) << o.err;
}
class Limits22 : public ::testing::Test {
 protected:
  // One voxelized sphere for the suite (32^3: 707 KB, six channels).
  static void SetUpTestSuite() {
    dir_ = std::make_unique<TempDir>();
    Outcome o = run_svo({"voxelize", "--scene", "bumpy-sphere", "--resolution", "32", "-o", *dir_ / "sphere.svo"});
    ASSERT_EQ(o.status, 0) << o.err;
  }
  static void TearDownTestSuite() { dir_.reset(); }

  // A copy of the sphere in this test's directory.
  std::string sphere_copy(const std::string& name) {
    const std::string path = here_ / name;
    fs::copy_file(*dir_ / "sphere.svo", path);
    return path;
  }
  std::vector<std::string> render(const std::string& svo, std::vector<std::string> more = {}) {
    std::vector<std::string> args{"render", svo,        "-o", here_ / "out.png", "--width",
                                  "16",     "--height", "16", "--device",        "native"};
    args.insert(args.end(), more.begin(), more.end());
    return args;
  }

  static std::unique_ptr<TempDir> dir_;
  TempDir here_;
};
std::unique_ptr<TempDir> Limits22::dir_;

// Case 7: the header states 16 GiB and the file is 16 GiB, all of it a hole
// past the 707 KB the sections need. Before: `svo info` hashed it all, 52 s
// and 16.9 GB resident, then "corrupt data: checksum". Now the stated size
// is checked against the end of the last section before any byte past the
// tables is read or hashed.
TEST_F(Limits22, SparseFileStating16GiBIsRefusedBeforeHashing) {
  const std::string path = sphere_copy("sparse.svo");
  const uint64_t needed = fs::file_size(path), stated = uint64_t(16) << 30;
  edit_header(path, kFileBytes, stated);
  fs::resize_file(path, stated);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  ASSERT_LT(uint64_t(st.st_blocks) * 512, uint64_t(64) << 20) << "the file system made no hole";
  const std::string what = path + ": header records " + std::to_string(stated) + " bytes but the sections end at " +
                           std::to_string(needed) + " (" + std::to_string(stated - needed) +
                           " bytes after the last section)";
  expect_refused(run_svo({"info", path}, kLimits), what);
  expect_refused(run_svo(render(path), kLimits), what);
}

// Case 7, the other half: a stated size larger than the file on disk.
TEST_F(Limits22, StatedSizeBeyondTheFileIsRefused) {
  const std::string path = sphere_copy("short.svo");
  const uint64_t size = fs::file_size(path), stated = uint64_t(16) << 30;
  edit_header(path, kFileBytes, stated);
  expect_refused(run_svo({"info", path}, kLimits), path + ": truncated: header records " + std::to_string(stated) +
                                                       " bytes, file has " + std::to_string(size));
}

// Case 11: a domain of size 1e-45 (a denormal) passed `svo info` and failed
// in `svo render` ("camera eye and target coincide", naming no file). The
// loader refuses it, so both commands say the same.
TEST_F(Limits22, DenormalDomainSizeIsRefusedByInfoAndRender) {
  const std::string path = sphere_copy("tiny.svo");
  edit_header(path, kSize, 1e-45f);
  const std::string what = path +
                           ": size 1.4013e-45 is too small to render: the finest voxel (size / 32 = 0) must "
                           "be at least 8.67362e-19 and at least 2^-23 of the domain's largest coordinate " +
                           "1.01333 (float precision)";
  expect_refused(run_svo({"info", path}, kLimits), what);
  expect_refused(run_svo(render(path), kLimits), what);
}

// Case 11: origin + size overflowing to infinity was printed as bounds
// "[3e+38, ...] to [inf, ...]" by `svo info`. Refused at load.
TEST_F(Limits22, DomainOverflowingToInfinityIsRefused) {
  const std::string path = sphere_copy("inf.svo");
  const float origin[3] = {3e38f, 3e38f, 3e38f};
  edit_header(path, kOrigin, origin, sizeof origin);
  edit_header(path, kSize, 1e38f);
  const std::string what = path +
                           ": the domain [origin, origin + size] spans [3e+38, inf] on axis 0 (origin and "
                           "origin + size must be within +-1e+17)";
  const Outcome o = run_svo({"info", path}, kLimits);
  expect_refused(o, what);
  EXPECT_EQ(o.err.find("inf, inf"), std::string::npos);
  expect_refused(run_svo(render(path), kLimits), what);
}

// Case 11: an eye at 1e30 was called "eye and target are the same point"
// (the float square of its distance overflowed). Now the message says that
// the eye is too far out, and how far from the target.
TEST_F(Limits22, EyeFarOutIsCalledFarOut) {
  const std::string path = sphere_copy("sphere.svo");
  const std::string camera = "1e30,0,0,0,0,0,0,1,0,40";
  expect_refused(run_svo(render(path, {"--camera", camera}), kLimits),
                 "--camera '" + camera +
                     "': eye (1e+30, 0, 0) is too far out (1e+30 from the target): coordinates "
                     "must be within +-1e+18, beyond which float arithmetic overflows");
  EXPECT_FALSE(fs::exists(here_ / "out.png"));
}

// Case 9: a path file asking for 1,000,000 frames (--frames stops at
// 100000). Before: the flythrough started, 5,500 frames in its first minute
// at 16x16. Now the path loader refuses it before the octree is read.
TEST_F(Limits22, PathFileBeyondTheFrameLimitIsRefused) {
  const std::string path = sphere_copy("sphere.svo"), json = here_ / "path.json", out = here_ / "fly";
  std::ofstream(json) << R"({"frames": 1000000, "keys": [)"
                      << R"({"eye": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40},)"
                      << R"({"eye": [0, 0, 2], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40}]})";
  expect_refused(run_svo({"flythrough", path, "--path-file", json, "-o", out, "--width", "16", "--height", "16",
                          "--device", "native"},
                         kLimits),
                 json + ": \"frames\" is 1000000, above the limit of 100000 frames");
  EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));
}

}  // namespace
