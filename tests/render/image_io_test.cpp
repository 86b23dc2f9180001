// Frames to PNG and EXR and back, the G-buffer's channels, and atomic
// replacement of output files (render/image_io.h).
#include "svo/render/image_io.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>

#include "temp_dir.h"

namespace svo::render {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;
using testing::FileSizeLimit;
using testing::names_in;


std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A frame whose every value differs: colour ramps in [0, 1.5], coverage in
// [0, 1], a G-buffer with a distinct value per channel and pixel.
Frame test_frame(uint32_t width, uint32_t height) {
  Frame f;
  f.width = width;
  f.height = height;
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      float u = float(x) / float(width), v = float(y) / float(height);
      f.colour.emplace_back(1.5f * u, v, 0.25f * u + 0.5f * v, (u + v) / 2);
      GBufferTexel t;
      t.depth = 1 + u;
      t.position = {u, v, -u};
      t.normal = {0.1f * u, 0.2f * v, 0.9f};
      t.tangent = {0.9f, -0.1f * u, 0.05f * v};
      t.slope_cov = {0.01f * (1 + u * v), 0.02f * u, -0.003f * v};
      t.sigma_rho2 = 0.004f + 0.001f * u;
      t.abar = {0.3f, u, v};
      t.a_s = {-0.2f * u, 0.1f * v, 0.7f};
      t.coverage = (u + v) / 2;
      t.material = x % 3;
      t.material2 = y % 5;
      t.material_mix = 1 - u * v;
      f.gbuffer.push_back(t);
      f.steps.push_back(x * 1000 + y * 7 + 3);
    }
  }
  return f;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Srgb, TransferRoundTripsAndClamps) {
  for (float x = 0; x <= 1.0f; x += 0.01f) EXPECT_NEAR(srgb_to_linear(linear_to_srgb(x)), x, 1e-5f);
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.735357f, 1e-5f);  // IEC 61966-2-1
  EXPECT_EQ(linear_to_srgb(-1.0f), 0.0f);
  EXPECT_EQ(linear_to_srgb(7.0f), 1.0f);
}

TEST(ImageIo, PngRoundTripWithinQuantisation) {
  TempDir dir;
  Frame f = test_frame(37, 23);
  write_colour(dir / "a.png", f);
  Image image = read_image(dir / "a.png");
  ASSERT_EQ(image.width, 37);
  ASSERT_EQ(image.height, 23);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  double worst = 0;
  for (int y = 0; y < 23; ++y) {
    for (int x = 0; x < 37; ++x) {
      for (int c = 0; c < 3; ++c) {
        float expected = linear_to_srgb(f.colour[size_t(y * 37 + x)][c]);  // clamped at 1
        worst = std::max(worst, double(std::abs(linear_to_srgb(image.at(x, y, c)) - expected)));
      }
    }
  }
  // Half an 8-bit step in the encoded values.
  EXPECT_LE(worst, 0.5 / 255 + 1e-6);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a.png"});  // no temporary left
}

TEST(ImageIo, PngClampsOutOfRangeAndNaN) {
  TempDir dir;
  Frame f;
  f.width = 3, f.height = 1;
  f.colour = {{-1, 0, 5, 1}, {std::nanf(""), 1, 0.5f, 1}, {1e30f, -0.0f, 0.0031308f, 0}};
  write_colour(dir / "c.PNG", f);  // extension case does not matter
  Image image = read_image(dir / "c.PNG");
  EXPECT_EQ(image.at(0, 0, 0), 0.0f);
  EXPECT_EQ(image.at(0, 0, 2), 1.0f);
  EXPECT_EQ(image.at(1, 0, 0), 0.0f);
  EXPECT_EQ(image.at(2, 0, 0), 1.0f);
}

TEST(ImageIo, ExrRoundTripIsExact) {
  TempDir dir;
  Frame f = test_frame(19, 11);
  write_colour(dir / "a.exr", f);
  Image image = read_image(dir / "a.exr");
  ASSERT_EQ(image.width, 19);
  ASSERT_EQ(image.height, 11);
  const int r = image.channel("R"), g = image.channel("G"), b = image.channel("B"), a = image.channel("A");
  ASSERT_TRUE(r >= 0 && g >= 0 && b >= 0 && a >= 0) << image.channels.size();
  for (int y = 0; y < 11; ++y) {
    for (int x = 0; x < 19; ++x) {
      const glm::vec4& e = f.colour[size_t(y * 19 + x)];
      ASSERT_EQ(image.at(x, y, r), e.r);  // linear, values above 1 kept
      ASSERT_EQ(image.at(x, y, g), e.g);
      ASSERT_EQ(image.at(x, y, b), e.b);
      ASSERT_EQ(image.at(x, y, a), e.a);  // coverage
    }
  }
}

TEST(ImageIo, GBufferHasEveryChannelExactly) {
  TempDir dir;
  Frame f = test_frame(13, 9);
  write_gbuffer(dir / "g.exr", f);
  Image image = read_image(dir / "g.exr");
  ASSERT_EQ(image.channels.size(), kGBufferChannels.size());
  int index[kGBufferChannels.size()];
  for (size_t c = 0; c < kGBufferChannels.size(); ++c) {
    index[c] = image.channel(kGBufferChannels[c]);
    ASSERT_GE(index[c], 0) << "missing channel " << kGBufferChannels[c];
  }
  for (int y = 0; y < 9; ++y) {
    for (int x = 0; x < 13; ++x) {
      const GBufferTexel& t = f.gbuffer[size_t(y * 13 + x)];
      const float expected[] = {t.depth,       t.position.x, t.position.y, t.position.z, t.normal.x,   t.normal.y,
                                t.normal.z,    t.tangent.x,  t.tangent.y,  t.tangent.z,  t.slope_cov.x, t.slope_cov.y,
                                t.slope_cov.z, t.sigma_rho2, t.abar.x,     t.abar.y,     t.abar.z,     t.a_s.x,
                                t.a_s.y,       t.a_s.z,      t.coverage,   float(t.material), float(t.material2),
                                t.material_mix};
      static_assert(std::size(expected) == kGBufferChannels.size());
      for (size_t c = 0; c < kGBufferChannels.size(); ++c) {
        ASSERT_EQ(image.at(x, y, index[c]), expected[c]) << kGBufferChannels[c] << " at " << x << "," << y;
      }
    }
  }
}

TEST(ImageIo, StepsImageHoldsEveryPixelsCount) {
  TempDir dir;
  Frame f = test_frame(13, 9);
  write_steps(dir / "s.exr", f);
  Image image = read_image(dir / "s.exr");
  ASSERT_EQ(image.channels, std::vector<std::string>{"steps"});
  for (int y = 0; y < 9; ++y) {
    for (int x = 0; x < 13; ++x) ASSERT_EQ(image.at(x, y, 0), float(f.steps[size_t(y * 13 + x)])) << x << "," << y;
  }
  EXPECT_EQ(error_of([&] { write_steps(dir / "s.png", f); }),
            (dir / "s.png") + ": the steps image is written as OpenEXR only (use .exr)");
  f.steps.clear();
  EXPECT_EQ(error_of([&] { write_steps(dir / "t.exr", f); }),
            (dir / "t.exr") + ": cannot write: the frame's steps image holds 0 pixels, not 13 x 9");
}

TEST(ImageIo, ErrorsNameThePath) {
  TempDir dir;
  Frame f = test_frame(4, 4);
  EXPECT_EQ(error_of([&] { write_colour(dir / "a.jpg", f); }),
            (dir / "a.jpg") + ": unsupported image extension '.jpg' (use .png or .exr)");
  EXPECT_EQ(error_of([&] { write_colour(dir / "noext", f); }),
            (dir / "noext") + ": unsupported image extension '' (use .png or .exr)");
  EXPECT_EQ(error_of([&] { write_gbuffer(dir / "g.png", f); }),
            (dir / "g.png") + ": the G-buffer is written as OpenEXR only (use .exr)");
  Frame no_gbuffer = f;
  no_gbuffer.gbuffer.clear();
  EXPECT_EQ(error_of([&] { write_gbuffer(dir / "g.exr", no_gbuffer); }),
            (dir / "g.exr") + ": cannot write: the frame's G-buffer holds 0 pixels, not 4 x 4");
  EXPECT_EQ(error_of([&] { read_image(dir / "missing.png"); }), (dir / "missing.png") + ": does not exist");
  std::ofstream(dir / "junk.png") << "not a png";
  std::string junk = error_of([&] { read_image(dir / "junk.png"); });
  EXPECT_EQ(junk.rfind((dir / "junk.png") + ": cannot read: ", 0), 0u) << junk;
  EXPECT_EQ(junk.find('\n'), std::string::npos) << junk;
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"junk.png"});
}

TEST(CheckWritableOutput, RefusesMissingDirectoriesFilesAndDirectories) {
  TempDir dir;
  EXPECT_NO_THROW(check_writable_output(dir / "a.png"));
  EXPECT_EQ(error_of([&] { check_writable_output(dir / "no/such/a.png"); }),
            (dir / "no/such/a.png") + ": directory " + (dir / "no/such") + " does not exist");
  std::ofstream(dir / "file") << "x";
  EXPECT_EQ(error_of([&] { check_writable_output(dir / "file/a.png"); }),
            (dir / "file/a.png") + ": " + (dir / "file") + " is not a directory");
  fs::create_directory(dir / "d.png");
  EXPECT_EQ(error_of([&] { check_writable_output(dir / "d.png"); }),
            (dir / "d.png") + ": is a directory; outputs replace only regular files");
}

// A write into a directory that does not allow it (mode 0555, as a user
// without root's override) fails before anything is created, and the file
// already there stays. Runs in a child process so that root can drop to
// an unprivileged user for it.
TEST(AtomicWrite, UnwritableDirectoryKeepsExistingFile) {
  TempDir dir;
  Frame f = test_frame(8, 8);
  write_colour(dir / "a.png", f);
  const std::string old_bytes = read_text(dir / "a.png");
  ASSERT_EQ(::chmod(dir.path().c_str(), 0555), 0);
  pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) ::_exit(10);
    Frame other = test_frame(8, 8);
    other.colour.assign(other.colour.size(), glm::vec4(1));
    std::string check = error_of([&] { check_writable_output(dir / "a.png"); });
    if (check != (dir / "a.png") + ": directory " + dir.path().string() + " is not writable") ::_exit(11);
    std::string write = error_of([&] { write_colour(dir / "a.png", other); });
    if (write != check) ::_exit(12);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "10: cannot drop root, 11: check_writable_output, 12: write_colour";
  ::chmod(dir.path().c_str(), 0755);
  EXPECT_EQ(read_text(dir / "a.png"), old_bytes);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a.png"});
}

// A write that fails half way (the file size limit, as a full disk would)
// keeps the old file byte for byte and removes the temporary.
TEST(AtomicWrite, FailedWriteKeepsExistingFile) {
  TempDir dir;
  write_colour(dir / "a.exr", test_frame(4, 4));
  const std::string old_bytes = read_text(dir / "a.exr");
  Frame big = test_frame(256, 256);
  for (size_t i = 0; i < big.colour.size(); ++i) big.colour[i].x = float((i * 2654435761u) % 1000003) / 7.0f;

  std::string message, gbuffer_message;
  {
    FileSizeLimit limit(4096);  // write() then fails with EFBIG
    message = error_of([&] { write_colour(dir / "a.exr", big); });
    gbuffer_message = error_of([&] { write_gbuffer(dir / "g.exr", big); });
  }

  EXPECT_EQ(message.rfind((dir / "a.exr") + ": cannot write: ", 0), 0u) << message;
  EXPECT_EQ(gbuffer_message.rfind((dir / "g.exr") + ": cannot write: ", 0), 0u) << gbuffer_message;
  EXPECT_EQ(read_text(dir / "a.exr"), old_bytes);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a.exr"});
}

// A directory where the file should go is refused before anything is
// written (it used to fail at the rename): the directory stays as it was and
// no temporary is left.
TEST(AtomicWrite, DirectoryAtTheNameIsRefused) {
  TempDir dir;
  fs::create_directory(dir / "a.png");
  std::ofstream(dir / "a.png/keep") << "keep";
  std::string message = error_of([&] { write_colour(dir / "a.png", test_frame(4, 4)); });
  EXPECT_EQ(message, (dir / "a.png") + ": is a directory; outputs replace only regular files");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a.png"});
  EXPECT_EQ(read_text(dir / "a.png/keep"), "keep");
}

}  // namespace
}  // namespace svo::render
