// The import of IES TM-25 ray files (import_tm25, docs/luminaire.md):
// flux conservation, the radiance of a Lambertian emitter, colour from
// tristimulus data, and hostile files, on ray files the tests write
// (tm25_writer.h).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <fstream>
#include <random>

#include "svo/render/luminaire.h"
#include "temp_dir.h"
#include "tm25_writer.h"

namespace {

using svo::render::import_tm25;
using svo::render::light_field_flux;
using svo::render::LightField;
using svo::testing::encode_tm25;
using svo::testing::lambertian;
using svo::testing::Tm25File;
using svo::testing::Tm25Ray;

constexpr float kPi = 3.14159265358979f;

void write(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  ASSERT_TRUE(bool(out)) << path;
}

double total_flux(const Tm25File& file) {
  double sum = 0.0;
  for (const auto& r : file.rays) sum += r.flux;
  return sum;
}

TEST(Tm25, LambertianEmitterHasItsRadiance) {
  svo::testing::TempDir dir;
  const float L0 = 3.0f;
  const std::string path = dir / "panel.tm25ray";
  write(path, encode_tm25(lambertian(L0, 2.0f, 100, 100)));
  const LightField f = import_tm25(path, 8, 16);
  EXPECT_EQ(f.units, "mm");
  EXPECT_FLOAT_EQ(f.metres_per_unit, 0.001f);
  EXPECT_EQ(f.image_count(), 64u);
  EXPECT_NE(f.source.find("panel.tm25ray"), std::string::npos) << f.source;
  EXPECT_NE(f.source.find("1000000 rays"), std::string::npos) << f.source;
  EXPECT_NE(f.source.find("radiometric"), std::string::npos) << f.source;
  // From the centre of U through the central part of S: the 2 x 2 texels
  // around the axis (|s| < 5.5 delta, 93% of the flux) each within 2%, and
  // the mean of the 4 x 4 around it (noisier: fewer rays) within 2%.
  ASSERT_EQ(f.width, 16u);
  for (float sy : {-0.055f, -0.01f, 0.03f, 0.06f}) {
    for (float sx : {-0.06f, -0.03f, 0.01f, 0.055f}) {
      const glm::vec2 s = glm::vec2(sx, sy) * f.extent;
      const glm::vec3 L = f.radiance(glm::vec2(0.0f), s);
      EXPECT_NEAR(L.x, L0, 0.02f * L0) << "s = (" << s.x << ", " << s.y << ")";
      EXPECT_FLOAT_EQ(L.x, L.y);
      EXPECT_FLOAT_EQ(L.x, L.z);
    }
  }
  double mean = 0.0;
  for (int y = 6; y < 10; ++y) {
    for (int x = 6; x < 10; ++x) {
      const glm::vec2 s = (glm::vec2(float(x), float(y)) + 0.5f) / 16.0f * f.extent - 0.5f * f.extent;
      mean += f.radiance(glm::vec2(0.0f), s).x / 16.0;
    }
  }
  EXPECT_NEAR(mean, L0, 0.02 * L0);
  // Beyond the emitter's edge (U's corner zone) no light.
  EXPECT_LT(f.radiance(glm::vec2(f.spacing * 4.9f), glm::vec2(0.0f)).x, 0.02f * L0);
}

TEST(Tm25, FluxIsConserved) {
  svo::testing::TempDir dir;
  // A Lambertian panel off the axis, below z = 0, and a narrow beam from a
  // small disc at z = 1 aimed 10 degrees off the axis with uneven flux.
  Tm25File file = lambertian(1.5f, 3.0f, 60, 64, -2.0f);
  for (auto& r : file.rays) r.x += 0.7f;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  for (int k = 0; k < 200000; ++k) {
    const float rad = 0.5f * std::sqrt(uni(rng)), a = 2.0f * kPi * uni(rng);
    const float t = 0.17f + 0.05f * (uni(rng) - 0.5f), p = 2.0f * kPi * uni(rng);
    glm::vec3 k3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
    file.rays.push_back({rad * std::cos(a), rad * std::sin(a), 1.0f, k3.x, k3.y, k3.z, 1e-4f * (0.5f + uni(rng))});
  }
  const std::string path = dir / "two.tm25ray";
  write(path, encode_tm25(file));
  const double expected = total_flux(file);
  for (uint32_t grid : {1u, 4u, 8u}) {
    const LightField f = import_tm25(path, grid, 24);
    const double flux = light_field_flux(f, 8);
    EXPECT_NEAR(flux / expected, 1.0, 0.01) << "grid " << grid << ": " << f.source;
  }
}

TEST(Tm25, TristimulusGivesColour) {
  svo::testing::TempDir dir;
  Tm25File file = lambertian(1.0f, 1.0f, 30, 36);
  file.photometric = true;
  file.tristimulus = true;
  for (auto& r : file.rays) {
    r.tri_x = 1.3f * r.flux;  // a warm (reddish) white
    r.tri_z = 0.4f * r.flux;
  }
  const std::string path = dir / "warm.tm25ray";
  write(path, encode_tm25(file));
  const LightField f = import_tm25(path, 4, 8);
  EXPECT_NE(f.source.find("photometric"), std::string::npos) << f.source;
  const glm::vec3 L = f.radiance(glm::vec2(0.0f), glm::vec2(0.0f));
  EXPECT_GT(L.x, 1.2f * L.y);
  EXPECT_GT(L.y, 1.2f * L.z);
  EXPECT_NEAR(light_field_flux(f, 8) / total_flux(file), 1.0, 0.02);  // luminance carries the lumens
}

TEST(Tm25, ReadsSpectralTableAndSkipsIt) {
  svo::testing::TempDir dir;
  Tm25File file = lambertian(1.0f, 1.0f, 10, 16);
  file.spectrum_points = 13;  // 4 + 13 * 8 = 108 bytes, padded to 128
  const std::string path = dir / "spectral.tm25ray";
  write(path, encode_tm25(file));
  EXPECT_NO_THROW(import_tm25(path, 2, 4));
}

// Imports `bytes` and expects one line "tm25: PATH: ..." containing `why`.
void expect_refused(const std::string& path, const std::string& why) {
  try {
    import_tm25(path, 4, 8);
    ADD_FAILURE() << path << " was accepted; expected: " << why;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("tm25: " + path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(why), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(Tm25, HostileFilesAreRefused) {
  svo::testing::TempDir dir;
  const Tm25File good = lambertian(1.0f, 1.0f, 4, 4);
  const std::vector<uint8_t> bytes = encode_tm25(good);
  auto variant = [&](const std::string& name, std::vector<uint8_t> b) {
    const std::string path = dir / name;
    write(path, b);
    return path;
  };
  {  // the good file is accepted
    const std::string path = variant("good.tm25ray", bytes);
    EXPECT_NO_THROW(import_tm25(path, 4, 8));
  }
  expect_refused(variant("truncated-ray", std::vector<uint8_t>(bytes.begin(), bytes.end() - 9)),
                 "bytes, but 64 rays of 28 bytes");
  expect_refused(variant("truncated-header", std::vector<uint8_t>(bytes.begin(), bytes.begin() + 1000)),
                 "truncated: 1000 bytes");
  {
    auto b = bytes;
    std::memcpy(b.data(), "TM26", 4);
    expect_refused(variant("magic", b), "magic 'TM26'");
  }
  {
    Tm25File lie = good;
    lie.count_override = 65;
    expect_refused(variant("count-lie", encode_tm25(lie)), "65 rays of 28 bytes");
    lie.count_override = int64_t(1) << 40;
    expect_refused(variant("count-huge", encode_tm25(lie)), "rays (at most 2^31)");
    lie.count_override = 0;
    expect_refused(variant("count-zero", encode_tm25(lie)), "no rays");
  }
  {
    Tm25File bad = good;
    bad.rays[5].y = std::nanf("");
    expect_refused(variant("nan-origin", encode_tm25(bad)), "ray 5: the origin (");
  }
  {
    Tm25File bad = good;
    bad.rays[3].flux = -0.5f;
    expect_refused(variant("negative-flux", encode_tm25(bad)), "ray 3: negative flux -0.5");
  }
  {
    Tm25File bad = good;
    bad.rays[2].kx = bad.rays[2].ky = bad.rays[2].kz = 0.0f;
    expect_refused(variant("zero-direction", encode_tm25(bad)), "ray 2: the direction (0, 0, 0) is not a unit vector");
    bad.rays[2].kz = 0.9f;
    expect_refused(variant("short-direction", encode_tm25(bad)), "is not a unit vector");
  }
  {
    Tm25File bad = good;
    for (auto& r : bad.rays) r.kz = -r.kz;
    expect_refused(variant("backward", encode_tm25(bad)), "no ray with flux travels towards +z");
  }
  {
    auto b = bytes;
    b[256 + 4 * 2] = 2;  // radiant flux flag 2
    expect_refused(variant("flag", b), "the radiant flux flag is 2");
    b[256 + 4 * 2] = 0;  // no flux column at all
    expect_refused(variant("no-flux", b), "neither the radiant nor the luminous flux flag");
  }
  {
    auto b = bytes;
    b[4] = 0xe4;  // 2020 (0x7e4) for 2013 (0x7dd)
    expect_refused(variant("version", b), "version 2020 is not supported (2013 only)");
  }
  {
    const std::string fifo = dir / "fifo.tm25ray";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expect_refused(fifo, "is a FIFO, expected a TM-25 ray file");
  }
  expect_refused("/dev/zero", "is a character device, expected a TM-25 ray file");
  expect_refused(dir / "missing.tm25ray", "cannot open");
  EXPECT_THROW(import_tm25(dir / "good.tm25ray", 0, 8), std::invalid_argument);
  EXPECT_THROW(import_tm25(dir / "good.tm25ray", 4, 2000), std::invalid_argument);
}

}  // namespace
