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
#include <limits>
#include <vector>

#include "temp_dir.h"

namespace svo::render {
namespace {

namespace fs = std::filesystem;
using testing::FileSizeLimit;
using testing::names_in;
using testing::TempDir;

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
      const float expected[] = {
          t.depth,       t.position.x, t.position.y, t.position.z,      t.normal.x,         t.normal.y,
          t.normal.z,    t.tangent.x,  t.tangent.y,  t.tangent.z,       t.slope_cov.x,      t.slope_cov.y,
          t.slope_cov.z, t.sigma_rho2, t.abar.x,     t.abar.y,          t.abar.z,           t.a_s.x,
          t.a_s.y,       t.a_s.z,      t.coverage,   float(t.material), float(t.material2), t.material_mix};
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
  EXPECT_EQ(error_of([&] { write_colour(dir / "a.bmp", f); }),
            (dir / "a.bmp") + ": unsupported image extension '.bmp' (use .png, .jpg or .exr)");
  EXPECT_EQ(error_of([&] { write_colour(dir / "noext", f); }),
            (dir / "noext") + ": unsupported image extension '' (use .png, .jpg or .exr)");
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

// --- Film (issue 21): exposure and tone map of 8-bit outputs; JPEG; --colour.

// A frame of one row whose pixels hold `values` (grey), alpha 1.
Frame grey_row(const std::vector<float>& values) {
  Frame f;
  f.width = uint32_t(values.size());
  f.height = 1;
  for (float v : values) f.colour.emplace_back(v, v, v, 1.0f);
  return f;
}

// Exposure +1 doubles the linear value before the sRGB encoding: the PNG
// read back (decoded to linear) holds twice the radiance, within 8 bits.
TEST(Film, ExposurePlusOneDoublesLinearValues) {
  TempDir dir;
  const std::vector<float> values{0.01f, 0.05f, 0.1f, 0.2f, 0.3f, 0.4f};
  write_colour(dir / "e0.png", grey_row(values));
  write_colour(dir / "e1.png", grey_row(values), Film{1.0f, Tonemap::None});
  const Image e0 = read_image(dir / "e0.png"), e1 = read_image(dir / "e1.png");
  ASSERT_EQ(e1.width, int(values.size()));
  for (int x = 0; x < e1.width; ++x) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(e0.at(x, 0, c), values[size_t(x)], 0.004f) << "x " << x;
      EXPECT_NEAR(e1.at(x, 0, c), 2 * values[size_t(x)], 0.004f) << "x " << x;
    }
  }
  EXPECT_EQ(e0.film, "");
  EXPECT_EQ(e1.film, "exposure +1 EV, tonemap none");
  // -1 EV halves; without a tone map values past 1 clip.
  write_colour(dir / "m1.png", grey_row({0.4f, 3.0f}), Film{-1.0f, Tonemap::None});
  const Image m1 = read_image(dir / "m1.png");
  EXPECT_NEAR(m1.at(0, 0, 0), 0.2f, 0.004f);
  EXPECT_EQ(m1.at(1, 0, 0), 1.0f);
}

// Narkowicz's curve: 0 stays 0, values above 1 land below 1 in order, the
// curve rises everywhere it is below 1, and a PNG keeps highlights apart
// that the clamp merges.
TEST(Film, FilmicMapsAboveOneBelowOneAndKeepsOrder) {
  EXPECT_EQ(filmic(0.0f), 0.0f);
  EXPECT_EQ(filmic(-1.0f), 0.0f);
  EXPECT_EQ(filmic(std::nanf("")), 0.0f);
  EXPECT_NEAR(filmic(1.0f), 2.54f / 3.16f, 1e-6f);
  EXPECT_NEAR(filmic(0.18f), 0.26691f, 1e-4f);
  EXPECT_EQ(filmic(1e30f), 1.0f);
  EXPECT_EQ(filmic(std::numeric_limits<float>::infinity()), 1.0f);
  for (float x : {1.5f, 2.0f, 4.0f, 6.0f}) EXPECT_LT(filmic(x), 1.0f) << x;
  float previous = 0;
  for (float x = 0.01f; x < 7.2f; x += 0.01f) {
    EXPECT_GT(filmic(x), previous) << x;
    previous = filmic(x);
  }
  EXPECT_EQ(apply_film(1.0f, Film{1.0f, Tonemap::Filmic}), filmic(2.0f));
  EXPECT_EQ(apply_film(2.0f, Film{}), 1.0f);

  TempDir dir;
  const std::vector<float> highlights{0.5f, 1.0f, 1.5f, 2.0f, 4.0f};
  write_colour(dir / "clip.png", grey_row(highlights));
  write_colour(dir / "filmic.png", grey_row(highlights), Film{0.0f, Tonemap::Filmic});
  const Image clip = read_image(dir / "clip.png"), film = read_image(dir / "filmic.png");
  EXPECT_EQ(film.film, "exposure +0 EV, tonemap filmic");
  for (int x = 1; x < 5; ++x) EXPECT_EQ(clip.at(x, 0, 0), 1.0f) << "clamped";
  for (int x = 0; x < 5; ++x) {
    EXPECT_NEAR(film.at(x, 0, 0), filmic(highlights[size_t(x)]), 0.004f);
    EXPECT_LT(film.at(x, 0, 0), 1.0f) << x;
    if (x > 0) {
      EXPECT_GT(film.at(x, 0, 0), film.at(x - 1, 0, 0)) << x;
    }
  }
}

// EXR holds the radiance as rendered whatever the film: same pixels, no record.
TEST(Film, ExrUnchangedByTheFilm) {
  TempDir dir;
  const Frame f = test_frame(7, 5);
  write_colour(dir / "plain.exr", f);
  write_colour(dir / "film.exr", f, Film{3.0f, Tonemap::Filmic});
  const Image plain = read_image(dir / "plain.exr"), film = read_image(dir / "film.exr");
  EXPECT_EQ(film.pixels, plain.pixels);
  EXPECT_EQ(film.film, "");
  for (size_t i = 0; i < f.colour.size(); ++i) {
    EXPECT_EQ(film.pixels[4 * i], f.colour[i].r);  // 1.5 stays 1.5
    EXPECT_EQ(film.pixels[4 * i + 3], f.colour[i].a);
  }
  EXPECT_EQ(read_text(dir / "film.exr"), read_text(dir / "plain.exr"));
}

// .jpg and .jpeg write a baseline JPEG through the same atomic writer; it
// reads back as sRGB-decoded linear values close to the frame's.
TEST(Film, JpegWrittenAndReadable) {
  TempDir dir;
  EXPECT_EQ(image_format("a.JPG"), ImageFormat::Jpeg);
  EXPECT_EQ(image_format("a.jpeg"), ImageFormat::Jpeg);
  EXPECT_TRUE(is_8bit(ImageFormat::Jpeg));
  EXPECT_FALSE(is_8bit(ImageFormat::Exr));
  Frame f;
  f.width = 32;
  f.height = 16;
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < f.width; ++x) f.colour.emplace_back(0.6f * x / 32, 0.3f, 0.1f + 0.02f * y, 1.0f);
  }
  write_colour(dir / "a.jpg", f, Film{1.0f, Tonemap::None});
  const std::string bytes = read_text(dir / "a.jpg");
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(uint8_t(bytes[0]), 0xFF);
  EXPECT_EQ(uint8_t(bytes[1]), 0xD8);  // SOI
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"a.jpg"}) << "no temporary left";
  const Image im = read_image(dir / "a.jpg");
  ASSERT_EQ(im.width, 32);
  ASSERT_EQ(im.height, 16);
  ASSERT_GE(im.channels.size(), 3u);
  EXPECT_EQ(im.film, "exposure +1 EV, tonemap none");
  // Lossy, compared as encoded: each value within 0.05, 0.01 on average.
  double sum = 0;
  for (uint32_t y = 0; y < f.height; ++y) {
    for (uint32_t x = 0; x < f.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float expected = linear_to_srgb(std::min(1.0f, 2 * f.colour[y * f.width + x][c]));
        const float got = linear_to_srgb(im.at(int(x), int(y), c));
        EXPECT_NEAR(got, expected, 0.05f) << x << "," << y << " channel " << c;
        sum += std::abs(got - expected);
      }
    }
  }
  EXPECT_LT(sum / (3.0 * f.width * f.height), 0.01);
}

// --colour's words: linear R,G,B, or #rrggbb decoded from sRGB.
TEST(Film, ParseColourLinearAndSrgbHex) {
  const glm::vec3 orange = parse_colour("#ff8000");
  EXPECT_EQ(orange.r, 1.0f);
  EXPECT_NEAR(orange.g, 0.21586f, 1e-4f);  // ((128/255 + 0.055) / 1.055)^2.4
  EXPECT_EQ(orange.b, 0.0f);
  EXPECT_EQ(parse_colour("#FF8000"), orange);
  EXPECT_NEAR(parse_colour("#808080").r, 0.21586f, 1e-4f);
  EXPECT_EQ(parse_colour("0.2,0.5,0.8"), glm::vec3(0.2f, 0.5f, 0.8f));
  EXPECT_EQ(parse_colour("0,1,1"), glm::vec3(0, 1, 1));
  EXPECT_EQ(error_of([] { parse_colour("#zz0000"); }),
            "'#zz0000': expected R,G,B (linear, each in [0, 1]) or #rrggbb (sRGB hex)");
  for (const char* bad : {"", "#", "#ff80", "#ff80000", "ff8000", "1,2,3", "0.5,0.5", "0.5,0.5,0.5,0.5", "a,b,c",
                          "nan,0,0", "0.5,,0.5", " 0.5,0.5,0.5", "-0.1,0,0", "0.5,0.5,0.5x"}) {
    EXPECT_THROW(parse_colour(bad), std::invalid_argument) << "'" << bad << "'";
  }
}

}  // namespace
}  // namespace svo::render
