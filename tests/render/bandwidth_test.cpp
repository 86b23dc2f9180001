// The input bandwidths of Bagher et al. 2013 Sec. 2.3 (bandwidth.h): Haar
// bandwidth of sinusoids of known frequency against [f, 4f], the windowed-FFT
// reference against f, constants, locality, the zero frame of area lights,
// environment maps with stripes in longitude, BRDF slices of a sharp and a
// rough lobe, and bad input.
#include "svo/render/bandwidth.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

namespace {

using svo::render::brdf_bandwidth;
using svo::render::BrdfKind;
using svo::render::Environment;
using svo::render::environment_bandwidth;
using svo::render::kBrdfBandwidthSlice;
using svo::render::kBrdfBandwidthTheta;
using svo::render::Material;
using svo::render::wavelet_bandwidth;
using svo::render::WaveletOptions;
using svo::render::windowed_fft_bandwidth;

constexpr double kPi = 3.14159265358979323846;
constexpr uint32_t kSize = 256;
constexpr uint32_t kMargin = 40;  // interior: away from the replicated border

enum class Axis { X, Y, Diagonal };

// k cycles across kSize pixels along x, y, or both (the diagonal's frequency
// is then sqrt(2) k / kSize).
std::vector<float> sinusoid(Axis axis, double k) {
  std::vector<float> image(size_t(kSize) * kSize);
  for (uint32_t y = 0; y < kSize; ++y) {
    for (uint32_t x = 0; x < kSize; ++x) {
      const double t = axis == Axis::X ? x : axis == Axis::Y ? y : double(x + y);
      image[size_t(y) * kSize + x] = float(0.5 + 0.5 * std::sin(2.0 * kPi * k * t / kSize + 0.3));
    }
  }
  return image;
}

double frequency(Axis axis, double k) { return (axis == Axis::Diagonal ? std::sqrt(2.0) : 1.0) * k / kSize; }

const char* name(Axis axis) { return axis == Axis::X ? "x" : axis == Axis::Y ? "y" : "diagonal"; }

struct Range {
  double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
};

Range interior_range(const std::vector<float>& values) {
  Range r;
  for (uint32_t y = kMargin; y < kSize - kMargin; ++y) {
    for (uint32_t x = kMargin; x < kSize - kMargin; ++x) {
      r.lo = std::min(r.lo, double(values[size_t(y) * kSize + x]));
      r.hi = std::max(r.hi, double(values[size_t(y) * kSize + x]));
    }
  }
  return r;
}

TEST(WaveletBandwidth, SinusoidsReadBetweenTheirFrequencyAndFourTimesIt) {
  for (Axis axis : {Axis::X, Axis::Y, Axis::Diagonal}) {
    for (double k : {2.0, 3.0, 5.0, 8.0, 12.0, 20.0, 32.0, 48.0}) {
      const double f = frequency(axis, k);
      if (f > 3.0 / 16.0) continue;  // the header's range of validity
      const Range r = interior_range(wavelet_bandwidth(sinusoid(axis, k), kSize, kSize));
      EXPECT_GE(r.lo, f) << name(axis) << " k " << k << ": [" << r.lo / f << ", " << r.hi / f << "] f";
      EXPECT_LE(r.hi, 4.0 * f) << name(axis) << " k " << k << ": [" << r.lo / f << ", " << r.hi / f << "] f";
    }
  }
}

TEST(WindowedFftBandwidth, SinusoidsReadWithinOneAndAHalfOfTheirFrequency) {
  for (Axis axis : {Axis::X, Axis::Y, Axis::Diagonal}) {
    // >= 2.5 cycles per window (the Hann window adds a bin): k 8 needs a 96-pixel window.
    for (auto [k, window] : {std::pair{8.0, 96u}, {12.0, 32u}, {20.0, 32u}, {32.0, 32u}, {48.0, 32u}}) {
      const double f = frequency(axis, k);
      const Range r = interior_range(windowed_fft_bandwidth(sinusoid(axis, k), kSize, kSize, window, 8));
      EXPECT_GE(r.lo, f / 1.5) << name(axis) << " k " << k << ": [" << r.lo / f << ", " << r.hi / f << "] f";
      EXPECT_LE(r.hi, f * 1.5) << name(axis) << " k " << k << ": [" << r.lo / f << ", " << r.hi / f << "] f";
    }
  }
}

TEST(WaveletBandwidth, ConstantIsZero) {
  for (float v : {0.0f, 0.3f, 1e6f}) {
    const std::vector<float> image(size_t(100) * 37, v);
    for (bool wrap : {false, true}) {
      WaveletOptions options;
      options.wrap_x = wrap;
      for (float b : wavelet_bandwidth(image, 100, 37, options)) ASSERT_EQ(b, 0.0f) << v;
    }
    for (float b : windowed_fft_bandwidth(image, 100, 37)) ASSERT_EQ(b, 0.0f) << v;
  }
  EXPECT_EQ(wavelet_bandwidth(std::vector<float>{2.0f}, 1, 1), std::vector<float>{0.0f});
}

TEST(WaveletBandwidth, IsLocal) {
  // Smooth (2 cycles across the image) on the left, 48 cycles on the right.
  std::vector<float> image(size_t(kSize) * kSize);
  for (uint32_t y = 0; y < kSize; ++y) {
    for (uint32_t x = 0; x < kSize; ++x) {
      const double k = x < kSize / 2 ? 2.0 : 48.0;
      image[size_t(y) * kSize + x] = float(0.5 + 0.5 * std::sin(2.0 * kPi * k * x / kSize));
    }
  }
  const std::vector<float> b = wavelet_bandwidth(image, kSize, kSize);
  double left = 0.0, right = std::numeric_limits<double>::infinity();
  for (uint32_t y = 0; y < kSize; ++y) {
    // 32 pixels clear of the seam, kMargin of the border.
    for (uint32_t x = kMargin; x < kSize / 2 - 32; ++x) left = std::max(left, double(b[size_t(y) * kSize + x]));
    for (uint32_t x = kSize / 2 + 32; x < kSize - kMargin; ++x) {
      right = std::min(right, double(b[size_t(y) * kSize + x]));
    }
  }
  EXPECT_GT(left, 0.0);
  EXPECT_GE(right, 4.0 * left) << "left at most " << left << ", right at least " << right;
}

TEST(WaveletBandwidth, ZeroFrameShowsTheOutlineOfAnAreaLight) {
  // A solid white square light (Bagher et al. Fig. 6(d)): constant, so 0
  // without the frame; with it, high at the outline and low in the middle.
  constexpr uint32_t n = 64;
  const std::vector<float> square(size_t(n) * n, 1.0f);
  for (float b : wavelet_bandwidth(square, n, n)) ASSERT_EQ(b, 0.0f);
  WaveletOptions options;
  options.zero_pad = true;
  const std::vector<float> b = wavelet_bandwidth(square, n, n, options);
  double edge = std::numeric_limits<double>::infinity(), middle = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    for (size_t p : {size_t(i), size_t(n - 1) * n + i, size_t(i) * n, size_t(i) * n + n - 1}) {
      edge = std::min(edge, double(b[p]));
    }
  }
  for (uint32_t y = n / 2 - 4; y < n / 2 + 4; ++y) {
    for (uint32_t x = n / 2 - 4; x < n / 2 + 4; ++x) middle = std::max(middle, double(b[size_t(y) * n + x]));
  }
  EXPECT_GE(edge, 0.2) << "the outline";  // band 1 or 2 (the largest value is 1/4)
  EXPECT_GE(edge, 4.0 * middle) << "edge at least " << edge << ", middle at most " << middle;
}

Environment stripes(uint32_t width, uint32_t height, double cycles) {
  Environment env;
  env.width = width;
  env.height = height;
  env.rgb.resize(size_t(width) * height * 3);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      const float v = float(1.0 + 0.5 * std::sin(2.0 * kPi * cycles * (x + 0.5) / width));
      for (int c = 0; c < 3; ++c) env.rgb[(size_t(y) * width + x) * 3 + size_t(c)] = v;
    }
  }
  return env;
}

double equator_median(const svo::render::EnvironmentBandwidth& b) {
  std::vector<float> row(b.cycles_per_radian.begin() + ptrdiff_t(b.height / 2) * b.width,
                         b.cycles_per_radian.begin() + ptrdiff_t(b.height / 2 + 1) * b.width);
  std::nth_element(row.begin(), row.begin() + ptrdiff_t(row.size() / 2), row.end());
  return row[row.size() / 2];
}

// An area light's spatial bandwidth (render::area_light_bandwidth): a
// white light reads low inside (its own size) and its outline at the grid's finest bands;
// in cycles per scene unit, so a light half as large reads twice as high;
// a checkered texture reads high inside too.
TEST(AreaLightBandwidth, TheOutlineOfAWhiteLightAndTheCheckersOfATexturedOne) {
  using svo::render::AreaLight;
  const AreaLight white = AreaLight::placed({0, 1, 0}, {0, 0, 0}, 1.0f, 1, 1, {1, 1, 1}, "white");
  const auto bw = svo::render::area_light_bandwidth(white);
  ASSERT_EQ(bw.width, 32u);
  ASSERT_EQ(bw.height, 32u);
  const float inside = bw.cycles_per_unit[16 * 32 + 16], edge = bw.cycles_per_unit[16 * 32];
  std::printf("white light: %.3f cycles per unit inside, %.3f at its edge\n", inside, edge);
  EXPECT_LT(inside, 1.0f);  // the light as a whole, about a cycle over twice its width
  EXPECT_GT(edge, 4.0f);    // at least 1/8 cycle per texel of 1/32 unit
  EXPECT_GT(edge, 8 * inside);
  const AreaLight small = AreaLight::placed({0, 1, 0}, {0, 0, 0}, 0.5f, 1, 1, {1, 1, 1}, "small");
  EXPECT_NEAR(svo::render::area_light_bandwidth(small).cycles_per_unit[16 * 32], 2 * edge, 1e-3 * edge);
  std::vector<float> checker(8 * 8 * 3);
  for (uint32_t i = 0; i < 64; ++i)
    for (uint32_t c = 0; c < 3; ++c) checker[3 * i + c] = (i % 8 + i / 8) % 2 == 0 ? 1.0f : 0.0f;
  const auto cb =
      svo::render::area_light_bandwidth(AreaLight::placed({0, 1, 0}, {0, 0, 0}, 1.0f, 8, 8, checker, "checker"));
  ASSERT_EQ(cb.width, 32u);  // each texel repeated 4 x 4
  EXPECT_GT(cb.cycles_per_unit[16 * 32 + 16], 1.0f);
  const AreaLight bad = AreaLight::placed({0, 1, 0}, {0, 0, 0}, 1.0f, 1, 1, {0, 0, 0}, "black");
  EXPECT_THROW(svo::render::area_light_bandwidth(bad), std::invalid_argument);
}

TEST(EnvironmentBandwidth, ConstantIsZeroAndStripesScaleWithTheirCount) {
  const auto constant = environment_bandwidth(svo::render::constant_environment(glm::vec3(0.7f), 128, 64), 32);
  EXPECT_EQ(constant.width, 32u);
  EXPECT_EQ(constant.height, 16u);
  for (float b : constant.cycles_per_radian) ASSERT_EQ(b, 0.0f);

  const auto few = environment_bandwidth(stripes(512, 256, 4), 64);
  const auto many = environment_bandwidth(stripes(512, 256, 64), 64);
  ASSERT_EQ(many.cycles_per_radian.size(), size_t(64) * 32);
  for (const auto* b : {&few, &many}) {
    for (float v : b->cycles_per_radian) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << v;
  }
  // At the equator, k stripes are k / (2 pi) cycles per radian.
  const double lo = equator_median(few), hi = equator_median(many);
  EXPECT_GE(lo, 4.0 / (2.0 * kPi));
  EXPECT_LE(lo, 4.0 * 4.0 / (2.0 * kPi));
  EXPECT_GE(hi / lo, 8.0) << "4 stripes: " << lo << ", 64 stripes: " << hi << " cycles per radian";
  EXPECT_LE(hi / lo, 32.0) << "4 stripes: " << lo << ", 64 stripes: " << hi << " cycles per radian";
  // Near the poles a pixel spans little angle: higher, never NaN or Inf.
  EXPECT_GT(many.cycles_per_radian[0], hi);
}

float mirror_value(const std::vector<float>& table, uint32_t ti) {
  // The mirror direction of view elevation texel ti: theta_l = theta_v at the
  // light's azimuth pi (x = -r, y = 0 on the equal-area disk: rows 7 and 8).
  const double theta = (ti + 0.5) * (kPi / 2.0) / kBrdfBandwidthTheta;
  const double r = std::sqrt(2.0) * std::sin(0.5 * theta);
  const size_t col = std::min(size_t((1.0 - r) * 8.0), size_t(15));
  const size_t base = size_t(ti) * kBrdfBandwidthSlice;
  return std::max(table[(base + 7) * kBrdfBandwidthSlice + col], table[(base + 8) * kBrdfBandwidthSlice + col]);
}

TEST(BrdfBandwidth, SharpLobesAreWiderBandThanRoughOnes) {
  Material lambert;
  lambert.kind = BrdfKind::Lambert;
  Material sharp;
  sharp.kind = BrdfKind::Beckmann;
  sharp.roughness = 0.05f;
  Material rough = sharp;
  rough.roughness = 0.5f;
  const std::vector<float> l = brdf_bandwidth(lambert), s = brdf_bandwidth(sharp), r = brdf_bandwidth(rough);
  const size_t size = size_t(kBrdfBandwidthTheta) * kBrdfBandwidthSlice * kBrdfBandwidthSlice;
  for (const auto* t : {&l, &s, &r}) {
    ASSERT_EQ(t->size(), size);
    for (float v : *t) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << v;
  }
  // Lambert: f cos(theta_l) = cos(theta_l) / pi, a quarter period across
  // the disk (0.16 cycles per radian; Haar's leakage reads it as up to ~1.7,
  // highest at the rim) everywhere: the equal-area disk has no pole where a
  // pixel spans little angle.
  float lambert_max = 0.0f;
  for (float v : l) lambert_max = std::max(lambert_max, v);
  EXPECT_LE(lambert_max, 2.0f);
  // Roughness 0.05 (reflected lobe deviation ~0.07 rad, ~4 pixels of the
  // 128x128 slice; its Gaussian's 95% quantile is 3.1 cycles per radian)
  // reads 7-10 at the mirror direction; roughness 0.5 several times less,
  // for view elevations away from grazing and from the pole.
  for (uint32_t ti = 2; ti < 12; ++ti) {
    const float sv = mirror_value(s, ti), rv = mirror_value(r, ti);
    EXPECT_GE(sv, 6.0f * rv) << "theta_i texel " << ti << ": roughness 0.05 " << sv << ", 0.5 " << rv;
    EXPECT_GE(sv, 3.5f * lambert_max) << ti;
    EXPECT_LE(sv, 0.25f * 64.0f * 1.01f) << ti;  // band 1 (t = 1) at the horizon's scale is the most it can read
  }
}

TEST(Bandwidth, BadInputThrows) {
  const std::vector<float> ok(16, 1.0f);
  EXPECT_THROW(wavelet_bandwidth({}, 0, 0), std::invalid_argument);
  EXPECT_THROW(wavelet_bandwidth(ok, 5, 4), std::invalid_argument);
  EXPECT_THROW(wavelet_bandwidth(ok, 4, 0), std::invalid_argument);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::vector<float> image = ok;
    image[5] = bad;
    EXPECT_THROW(wavelet_bandwidth(image, 4, 4), std::invalid_argument);
    EXPECT_THROW(windowed_fft_bandwidth(image, 4, 4, 4, 1), std::invalid_argument);
    Environment env = svo::render::constant_environment(glm::vec3(1.0f), 8, 4);
    env.rgb[7] = bad;
    EXPECT_THROW(environment_bandwidth(env, 4), std::invalid_argument);
  }
  WaveletOptions options;
  options.percentile = 1.5f;
  EXPECT_THROW(wavelet_bandwidth(ok, 4, 4, options), std::invalid_argument);
  options = {};
  options.epsilon = 0.0f;
  EXPECT_THROW(wavelet_bandwidth(ok, 4, 4, options), std::invalid_argument);
  EXPECT_THROW(windowed_fft_bandwidth(ok, 4, 4, 5, 1), std::invalid_argument);
  EXPECT_THROW(windowed_fft_bandwidth(ok, 4, 4, 4, 0), std::invalid_argument);
  EXPECT_THROW(windowed_fft_bandwidth(ok, 3, 4, 4, 1), std::invalid_argument);
  const Environment env = svo::render::constant_environment(glm::vec3(1.0f), 8, 4);
  EXPECT_THROW(environment_bandwidth(env, 16), std::invalid_argument);  // wider than the map
  EXPECT_THROW(environment_bandwidth(env, 6), std::invalid_argument);   // not a power of two
  EXPECT_THROW(environment_bandwidth(Environment{}, 4), std::invalid_argument);
  Environment short_map = env;
  short_map.rgb.pop_back();
  EXPECT_THROW(environment_bandwidth(short_map, 4), std::invalid_argument);
  try {
    wavelet_bandwidth(ok, 5, 4);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find("wavelet_bandwidth"), std::string::npos) << what;
  }
}

}  // namespace
