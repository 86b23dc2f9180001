// MERL measured BRDFs: the table index against the reference code, files
// written from analytic BRDFs and read back, evaluation through merl.glsl,
// the tabulated sampler (chi-square against its pdf), hostile files.
#include "svo/render/merl.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "common/shared_math.h"
#include "numerics/chi_square.h"
#include "render/temp_dir.h"

namespace svo::math {
// merl.glsl over the shading tables.
struct MerlTestReader {
  const float* t;
  float svo_table(uint32_t i) const { return t[i]; }
#include "common/merl.glsl"
};
}  // namespace svo::math

namespace {

namespace fs = std::filesystem;
using namespace svo::render;
using svo::math::MerlTestReader;

constexpr double kPi = 3.14159265358979323846;

// Lambert plus a normalized Blinn-Phong lobe, coloured.
glm::dvec3 analytic(glm::dvec3 wi, glm::dvec3 wo) {
  const glm::dvec3 kd(0.5, 0.35, 0.2), ks(0.3, 0.4, 0.5);
  const double n = 60;
  const glm::dvec3 h = glm::normalize(wi + wo);
  return kd / kPi + ks * ((n + 8) / (8 * kPi) * std::pow(std::max(h.z, 0.0), n));
}

glm::dvec3 random_upper(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const double z = u(rng), r = std::sqrt(1 - z * z), phi = 2 * kPi * u(rng);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// The reference code (BRDFRead.cpp: std_coords_to_half_diff_coords,
// theta_half_index, theta_diff_index, phi_diff_index, lookup_brdf_val),
// transcribed in double, independently of merl.glsl.
glm::dvec3 rotate_vector(glm::dvec3 v, glm::dvec3 axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (glm::dot(axis, v) * (1 - c)) + glm::cross(axis, v) * s;
}
uint32_t reference_index(glm::dvec3 in, glm::dvec3 out) {
  in = glm::normalize(in), out = glm::normalize(out);
  const glm::dvec3 half = glm::normalize((in + out) / 2.0);
  const double theta_half = std::acos(half.z), fi_half = std::atan2(half.y, half.x);
  const glm::dvec3 temp = rotate_vector(in, {0, 0, 1}, -fi_half);
  const glm::dvec3 diff = rotate_vector(temp, {0, 1, 0}, -theta_half);
  const double theta_diff = std::acos(diff.z);
  double fi_diff = std::atan2(diff.y, diff.x);
  int th = 0;
  if (theta_half > 0) th = std::clamp(int(std::sqrt(theta_half / (kPi / 2) * 90 * 90)), 0, 89);
  const int td = std::clamp(int(theta_diff / (kPi * 0.5) * 90), 0, 89);
  if (fi_diff < 0) fi_diff += kPi;
  const int pd = std::clamp(int(fi_diff / kPi * 360 / 2), 0, 179);
  return uint32_t(pd + td * 180 + th * 180 * 90);
}

uint32_t glsl_index(glm::dvec3 wi, glm::dvec3 wo) {
  MerlTestReader r{nullptr};
  return r.svo_merl_index(r.svo_merl_angles(glm::vec3(wi), glm::vec3(wo)));
}

// Indices that differ only where float rounding may cross a cell boundary:
// each of the three coordinates at most one apart (phi_d cyclically).
bool neighbours(uint32_t a, uint32_t b) {
  const int pa = int(a % 180), pb = int(b % 180), da = int(a / 180 % 90), db = int(b / 180 % 90);
  const int ha = int(a / (180 * 90)), hb = int(b / (180 * 90));
  const int dp = std::abs(pa - pb);
  return std::min(dp, 180 - dp) <= 1 && std::abs(da - db) <= 1 && std::abs(ha - hb) <= 1;
}

TEST(MerlIndex, MatchesTheReferenceCode) {
  std::mt19937_64 rng(7);
  int same = 0, reciprocal = 0, rotated = 0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const glm::dvec3 wi = random_upper(rng), wo = random_upper(rng);
    const uint32_t ref = reference_index(wi, wo), got = glsl_index(wi, wo);
    ASSERT_LT(got, kMerlSamples);
    EXPECT_TRUE(neighbours(ref, got)) << "wi " << wi.x << " " << wi.y << " " << wi.z << ", wo " << wo.x << " " << wo.y
                                      << " " << wo.z << ": reference " << ref << ", merl.glsl " << got;
    same += ref == got;
    // Reciprocity (phi_d folded to [0, pi)) and isotropy (phi_h ignored).
    reciprocal += glsl_index(wo, wi) == got;
    const double a = 1.234, c = std::cos(a), s = std::sin(a);
    auto turn = [&](glm::dvec3 v) { return glm::dvec3(c * v.x - s * v.y, s * v.x + c * v.y, v.z); };
    rotated += glsl_index(turn(wi), turn(wo)) == got;
  }
  EXPECT_GE(same, n * 995 / 1000);
  EXPECT_GE(reciprocal, n * 995 / 1000);
  EXPECT_GE(rotated, n * 995 / 1000);
  // The pole: both directions along the normal.
  EXPECT_EQ(glsl_index({0, 0, 1}, {0, 0, 1}), 0u);
  EXPECT_EQ(reference_index({0.6, 0, 0.8}, {-0.6, 0, 0.8}), glsl_index({0.6, 0, 0.8}, {-0.6, 0, 0.8}));
}

TEST(MerlIndex, SampleDirectionsHaveTheirAngles) {
  // The cell's own directions sit on the lower edges of its index ranges:
  // nudged into the cell they index back to it.
  std::mt19937_64 rng(3);
  for (int n = 0; n < 2000; ++n) {
    const uint32_t k = uint32_t(rng() % kMerlSamples);
    auto [wi, wo] = merl_sample_directions(k);
    EXPECT_NEAR(glm::length(wi), 1.0, 1e-12);
    EXPECT_NEAR(glm::length(wo), 1.0, 1e-12);
    const glm::dvec3 h = glm::normalize(wi + wo);
    const double theta_h = std::atan2(std::hypot(h.x, h.y), h.z);
    const double expected = std::pow(double(k / (180 * 90)) / 90, 2) * kPi / 2;
    EXPECT_NEAR(theta_h, expected, 1e-9) << k;
    EXPECT_NEAR(h.y, 0.0, 1e-12) << "phi_h = 0";
    // (phi_d is arbitrary where theta_d = 0.)
    if (k / 180 % 90 != 0) {
      EXPECT_TRUE(neighbours(reference_index(wi, wo), k)) << k;
    }
  }
}

class MerlFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto t0 = std::chrono::steady_clock::now();
    table_ = new MerlBrdf(tabulate_merl(analytic));
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("tabulate_merl: %.3f s for %u samples\n", s, kMerlSamples);
    EXPECT_LT(s, 10.0);  // < 2 s in Release on an idle machine
  }
  static void TearDownTestSuite() {
    delete table_;
    table_ = nullptr;
  }
  static MerlBrdf* table_;
  svo::testing::TempDir dir_;
};
MerlBrdf* MerlFiles::table_ = nullptr;

TEST_F(MerlFiles, RoundTrip) {
  const fs::path file = dir_.path() / "analytic.binary";
  write_merl(file, *table_);
  EXPECT_EQ(fs::file_size(file), kMerlFileBytes);
  EXPECT_EQ(svo::testing::names_in(dir_.path()), std::vector<std::string>{"analytic.binary"});
  const MerlBrdf back = load_merl(file);
  ASSERT_EQ(back.rgb.size(), table_->rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < back.rgb.size(); ++i) {
    // Divided by the scale in double and multiplied again: within one float rounding.
    const float a = table_->rgb[i], b = back.rgb[i];
    if (std::abs(a - b) > std::abs(a) * 6e-8f) ++differ;
  }
  EXPECT_EQ(differ, 0u);
  // The header and one value as the format has them.
  std::ifstream in(file, std::ios::binary);
  int32_t dims[3];
  in.read(reinterpret_cast<char*>(dims), sizeof dims);
  EXPECT_EQ(dims[0], 90);
  EXPECT_EQ(dims[1], 90);
  EXPECT_EQ(dims[2], 180);
  const uint32_t k = 40 + 180 * (20 + 90 * 30);
  double g = 0;
  in.seekg(std::streamoff(12 + 8 * (uint64_t(kMerlSamples) + k)));
  in.read(reinterpret_cast<char*>(&g), sizeof g);
  auto [wi, wo] = merl_sample_directions(k);
  EXPECT_NEAR(g * (1.15 / 1500), analytic(wi, wo).y, 1e-6 * analytic(wi, wo).y);
}

TEST_F(MerlFiles, EvalMatchesTheAnalyticBrdfAtItsCell) {
  std::vector<float> tables(17, 0.0f);  // something before, as the shading tables will have
  const auto [values, sampling] = append_merl_tables(*table_, tables);
  EXPECT_EQ(values, 17u);
  EXPECT_EQ(sampling, 17u + 3 * kMerlSamples);
  EXPECT_EQ(tables.size(), size_t(sampling) + merl_sampling_floats());
  const MerlTestReader r{tables.data()};
  std::mt19937_64 rng(11);
  int above = 0;
  double worst_lambert = 0;
  for (int n = 0; n < 100; ++n) {
    const glm::dvec3 wi = random_upper(rng), wo = random_upper(rng);
    MerlTestReader q = r;
    const glm::vec3 got = q.svo_merl_eval(values, glm::vec3(wi), glm::vec3(wo));
    // The value of the cell the pair falls in: the analytic BRDF at the
    // cell's own directions (0 where one of them is below the surface).
    const uint32_t k = q.svo_merl_index(q.svo_merl_angles(glm::vec3(wi), glm::vec3(wo)));
    auto [cwi, cwo] = merl_sample_directions(k);
    const glm::dvec3 want = cwi.z > 0 && cwo.z > 0 ? analytic(cwi, cwo) : glm::dvec3(0);
    above += cwi.z > 0 && cwo.z > 0;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-6 * want[c] + 1e-12) << n << " channel " << c;
    // Against the analytic value at the pair itself: the cell is at most
    // one step of each angle away, so a smooth BRDF differs little.
    if (cwi.z > 0 && cwo.z > 0) {
      const glm::dvec3 exact = analytic(wi, wo);
      const double lobe = exact.x - 0.5 / kPi;
      worst_lambert = std::max(worst_lambert, std::abs(got.x - exact.x) / (0.5 / kPi + lobe));
    }
  }
  EXPECT_GE(above, 90);
  // The lobe (exponent 60) changes by at most ~(n/2) * 2 d(theta_h) ~ 20% over a theta_h step near its peak.
  EXPECT_LT(worst_lambert, 0.35);
  // Nothing below the surface.
  MerlTestReader q = r;
  EXPECT_EQ(q.svo_merl_eval(values, glm::vec3(0.6f, 0, -0.8f), glm::vec3(0, 0, 1)), glm::vec3(0));
  EXPECT_EQ(q.svo_merl_eval(values, glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)), glm::vec3(0));
  // Normal incidence: sample 0 (theta_h = theta_d = 0).
  const glm::dvec3 top = analytic({0, 0, 1}, {0, 0, 1});
  EXPECT_NEAR(q.svo_merl_eval(values, glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)).z, top.z, 1e-6 * top.z);
}

TEST_F(MerlFiles, SamplerMatchesItsPdf) {
  std::vector<float> tables;
  const auto [values, sampling] = append_merl_tables(*table_, tables);
  MerlTestReader r{tables.data()};
  const double elevations[] = {0.0, 25.0, 50.0, 75.0, 88.0};
  const double alpha = svo::test::sidak_significance(0.01, 5);
  svo::test::ChiSquareOptions options;
  options.samples = 500000;
  options.integration_points = 24;  // the pdf is a step function of (phi, theta)
  int azimuth = 0;
  for (double deg : elevations) {
    const double t = deg * kPi / 180, p = 0.7 * azimuth++;
    const glm::vec3 wo(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)), float(std::cos(t)));
    uint64_t mismatched = 0, nonpositive = 0;
    auto sample = [&](glm::dvec2 u) -> std::optional<glm::dvec3> {
      const glm::vec4 s = r.svo_merl_sample(sampling, wo, glm::vec2(u));
      const glm::vec3 wi(s);
      if (!(s.w > 0)) {
        ++nonpositive;
        return std::nullopt;
      }
      if (s.w != r.svo_merl_pdf(sampling, wo, wi)) ++mismatched;
      return glm::dvec3(wi);
    };
    auto pdf = [&](glm::dvec3 d) { return double(r.svo_merl_pdf(sampling, wo, glm::vec3(d))); };
    const svo::test::ChiSquareResult result = svo::test::chi_square_test(sample, pdf, options);
    std::printf("theta_o %g: chi2 %.1f, dof %d, p-value %.3g, pdf integral %.5f\n", deg, result.statistic, result.dof,
                result.p_value, result.pdf_integral);
    EXPECT_TRUE(result.passed(alpha)) << "theta_o " << deg << ": " << result.summary();
    EXPECT_NEAR(result.pdf_integral, 1.0, 0.01) << "theta_o " << deg;
    EXPECT_EQ(mismatched, 0u) << "theta_o " << deg;
    EXPECT_LE(nonpositive, 2u) << "theta_o " << deg;
    // pdf > 0 wherever f > 0, finite at the pole.
    std::mt19937_64 rng(5);
    for (int n = 0; n < 2000; ++n) {
      const glm::vec3 wi(random_upper(rng));
      if (r.svo_merl_eval(values, wi, wo) != glm::vec3(0)) {
        EXPECT_GT(r.svo_merl_pdf(sampling, wo, wi), 0.0f);
      }
    }
    const float pole = r.svo_merl_pdf(sampling, wo, glm::vec3(0, 0, 1));
    EXPECT_TRUE(pole > 0 && std::isfinite(pole)) << pole;
    const glm::vec4 corner = r.svo_merl_sample(sampling, wo, glm::vec2(0.0f));
    EXPECT_TRUE(std::isfinite(corner.w) && corner.w > 0 && corner.z > 0) << corner.w;
    const glm::vec4 last = r.svo_merl_sample(sampling, wo, glm::vec2(1.0f));
    EXPECT_TRUE(std::isfinite(last.w) && last.z >= 0) << last.w;
  }
  // Below the surface: no sample, pdf 0.
  EXPECT_EQ(r.svo_merl_sample(sampling, glm::vec3(0, 0.6f, -0.8f), glm::vec2(0.5f)).w, 0.0f);
  EXPECT_EQ(r.svo_merl_pdf(sampling, glm::vec3(0, 0, 1), glm::vec3(0, 0.6f, -0.8f)), 0.0f);
}

// The chi-square test can fail here: the sampler of one view elevation
// against the pdf of another.
TEST_F(MerlFiles, SamplerOfAnotherViewIsRejected) {
  std::vector<float> tables;
  const auto [values, sampling] = append_merl_tables(*table_, tables);
  (void)values;
  MerlTestReader r{tables.data()};
  const glm::vec3 wo_sampled(float(std::sin(0.35)), 0, float(std::cos(0.35)));
  const glm::vec3 wo_pdf(float(std::sin(1.0)), 0, float(std::cos(1.0)));
  svo::test::ChiSquareOptions options;
  options.samples = 100000;
  const svo::test::ChiSquareResult result = svo::test::chi_square_test(
      [&](glm::dvec2 u) -> std::optional<glm::dvec3> {
        return glm::dvec3(glm::vec3(r.svo_merl_sample(sampling, wo_sampled, glm::vec2(u))));
      },
      [&](glm::dvec3 d) { return double(r.svo_merl_pdf(sampling, wo_pdf, glm::vec3(d))); }, options);
  EXPECT_FALSE(result.passed(1e-6)) << result.summary();
}

// An all-black BRDF still samples (uniformly over solid angle, from the floor).
TEST(MerlTables, BlackBrdfSamplesUniformly) {
  MerlBrdf black;
  black.rgb.assign(3 * size_t(kMerlSamples), 0.0f);
  std::vector<float> tables;
  const auto offsets = append_merl_tables(black, tables);
  const MerlTestReader r{tables.data()};
  MerlTestReader q = r;
  const glm::vec4 s = q.svo_merl_sample(offsets[1], glm::vec3(0, 0, 1), glm::vec2(0.3f, 0.6f));
  EXPECT_NEAR(s.w, 1 / (2 * kPi), 0.05 / (2 * kPi));
  black.rgb[5] = -1.0f;
  EXPECT_THROW(append_merl_tables(black, tables), std::invalid_argument);
  EXPECT_THROW(tabulate_merl([](glm::dvec3, glm::dvec3) { return glm::dvec3(std::nan("")); }), std::invalid_argument);
}

// Hostile files: each a one-line error naming the file.
class MerlHostile : public ::testing::Test {
 protected:
  // A valid file's bytes: raw value 1 + (k % 7) in every channel.
  static const std::vector<char>& valid() {
    static const std::vector<char> bytes = [] {
      std::vector<char> b(kMerlFileBytes);
      const int32_t dims[3] = {90, 90, 180};
      std::memcpy(b.data(), dims, sizeof dims);
      for (uint64_t i = 0; i < 3 * uint64_t(kMerlSamples); ++i) {
        const double v = 1.0 + double(i % kMerlSamples % 7);
        std::memcpy(b.data() + 12 + 8 * i, &v, 8);
      }
      return b;
    }();
    return bytes;
  }
  fs::path put(const std::string& name, const std::vector<char>& bytes) {
    const fs::path file = dir_.path() / name;
    std::ofstream out(file, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    return file;
  }
  static void set_double(std::vector<char>& b, uint32_t channel, uint32_t k, double v) {
    std::memcpy(b.data() + 12 + 8 * (uint64_t(channel) * kMerlSamples + k), &v, 8);
  }
  // load_merl(file) throws a one-line runtime_error "merl: FILE: ..." containing `what`.
  static void expect_refused(const fs::path& file, const std::string& what) {
    try {
      load_merl(file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("merl: " + file.string() + ": ", 0), 0u) << m;
      EXPECT_NE(m.find(what), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  svo::testing::TempDir dir_;
};

TEST_F(MerlHostile, ValidFileLoads) {
  const MerlBrdf b = load_merl(put("valid.binary", valid()));
  ASSERT_EQ(b.rgb.size(), 3 * size_t(kMerlSamples));
  EXPECT_EQ(b.rgb[3 * 10 + 1], float((1.0 + 10 % 7) * (1.15 / 1500)));
}

TEST_F(MerlHostile, WrongSizes) {
  std::vector<char> b = valid();
  b.pop_back();
  expect_refused(put("truncated.binary", b), "34992011 bytes, expected 34992012");
  b.push_back(0);
  b.push_back(0);
  expect_refused(put("long.binary", b), "34992013 bytes, expected 34992012");
  expect_refused(put("empty.binary", {}), "0 bytes");
  expect_refused(put("header.binary", std::vector<char>(valid().begin(), valid().begin() + 12)), "12 bytes");
}

TEST_F(MerlHostile, WrongDimensions) {
  std::vector<char> b = valid();
  const int32_t swapped[3] = {180, 90, 90};
  std::memcpy(b.data(), swapped, sizeof swapped);
  expect_refused(put("swapped.binary", b), "dimensions 180 x 90 x 90, expected 90 x 90 x 180");
  const int32_t negative[3] = {-90, -90, 180};
  std::memcpy(b.data(), negative, sizeof negative);
  expect_refused(put("negative.binary", b), "dimensions -90 x -90 x 180");
  const int32_t full[3] = {90, 90, 360};  // the phi_d count some code uses before halving
  std::memcpy(b.data(), full, sizeof full);
  expect_refused(put("full.binary", b), "dimensions 90 x 90 x 360");
}

TEST_F(MerlHostile, NonFiniteValues) {
  std::vector<char> b = valid();
  set_double(b, 1, 1234, std::nan(""));
  expect_refused(put("nan.binary", b), "G sample 1234 (theta_h 0, theta_d 6, phi_d 154) is NaN");
  b = valid();
  set_double(b, 2, kMerlSamples - 1, -INFINITY);
  expect_refused(put("inf.binary", b), "B sample 1457999 (theta_h 89, theta_d 89, phi_d 179) is infinite");
  b = valid();
  set_double(b, 0, 7, 1e300);
  expect_refused(put("huge.binary", b), "R sample 7 (theta_h 0, theta_d 0, phi_d 7) is too large for a float");
}

TEST_F(MerlHostile, NotRegularFiles) {
  expect_refused(dir_.path(), "is a directory");
  const fs::path fifo = dir_.path() / "fifo.binary";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_refused(fifo, "is a FIFO");
  expect_refused("/dev/zero", "is a character device");
  expect_refused(dir_.path() / "missing.binary", "no such file");
  // A link to a FIFO is judged by what it names.
  fs::create_symlink(fifo, dir_.path() / "link.binary");
  expect_refused(dir_.path() / "link.binary", "is a FIFO");
}

TEST_F(MerlHostile, MissingSamplesReadAsZero) {
  std::vector<char> b = valid();
  set_double(b, 0, 100, -1.0);
  set_double(b, 1, 200, -1.0);
  set_double(b, 2, 300, -0.25);
  const MerlBrdf m = load_merl(put("missing.binary", b));
  EXPECT_EQ(m.rgb[3 * 100 + 0], 0.0f);
  EXPECT_EQ(m.rgb[3 * 200 + 1], 0.0f);
  EXPECT_EQ(m.rgb[3 * 300 + 2], 0.0f);
  EXPECT_EQ(m.rgb[3 * 100 + 1], float((1.0 + 100 % 7) * (1.15 / 1500)));
  EXPECT_EQ(m.rgb[3 * 101 + 0], float((1.0 + 101 % 7) / 1500));
}

TEST_F(MerlHostile, WriteRefusesAWrongTable) {
  MerlBrdf small;
  small.rgb.assign(30, 0.0f);
  const fs::path file = dir_.path() / "small.binary";
  EXPECT_THROW(write_merl(file, small), std::runtime_error);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_THROW(write_merl(dir_.path() / "no-such-dir" / "x.binary", load_merl(put("v.binary", valid()))),
               std::runtime_error);
}

}  // namespace
