// The height-map surface of `svo bench material --heightmap` (paper Fig. 9,
// bottom) on a synthetic, strongly non-Gaussian map made here: its measured
// statistics against brute-force sums over a fine grid, its gradient against
// finite differences, reading a map from an image file, and the material
// curve at 0 degrees against the mean colour.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "svo/reference/material.h"
#include "svo/render/image_io.h"
#include "svo/voxelizer/heightmap_scene.h"
#include "temp_dir.h"

namespace svo::voxelizer {
namespace {

// Sharp peaks on a flat floor: heights strongly skewed (a Gaussian has 0).
HeightMap peaks_map(int n) {
  HeightMap m;
  m.width = m.height = n;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      float x = -1.0f + 2.0f * float(i) / float(n - 1), y = -1.0f + 2.0f * float(j) / float(n - 1);
      float s = std::sin(9.0f * x + 1.0f) * std::sin(7.0f * y + 0.5f) + 0.3f * std::sin(23.0f * x - 17.0f * y);
      m.values.push_back(std::exp(2.5f * s));
    }
  }
  return m;
}

const glm::vec3 kAbar(0.45f, 0.4f, 0.3f), kAs(0.3f, 0.2f, 0.15f);

TEST(HeightmapScene, StatisticsMatchBruteForceSumsOverAFineGrid) {
  HeightmapScene scene(peaks_map(41), 0.004f, kAbar, kAs);
  const glm::vec2 lo(-0.7f, -0.6f), hi(0.8f, 0.75f);
  SurfaceStatistics s = scene.statistics(lo, hi);
  // Midpoints of a 1200 x 1200 grid over the region.
  const int n = 1200;
  double sum = 0, sum2 = 0, sum3 = 0;
  glm::dvec2 g1(0), g2(0);
  std::vector<double> hs;
  hs.reserve(size_t(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      float x = lo.x + (hi.x - lo.x) * (float(i) + 0.5f) / float(n),
            y = lo.y + (hi.y - lo.y) * (float(j) + 0.5f) / float(n);
      double h = scene.height(x, y);
      glm::dvec2 g(scene.gradient(x, y));
      hs.push_back(h);
      sum += h, g1 += g, g2 += g * g;
    }
  }
  const double count = double(hs.size());
  const double mean = sum / count;
  for (double h : hs) sum2 += (h - mean) * (h - mean), sum3 += (h - mean) * (h - mean) * (h - mean);
  const double var = sum2 / count, skew = sum3 / count / std::pow(var, 1.5);
  const glm::dvec2 slope_var = g2 / count - (g1 / count) * (g1 / count);
  std::printf("sigma_h %.5f (%.5f), skewness %.3f (%.3f), slope variance %.4f %.4f (%.4f %.4f)\n",
              std::sqrt(s.height_variance), std::sqrt(var), s.skewness, skew, s.slope_variance.x, s.slope_variance.y,
              slope_var.x, slope_var.y);
  EXPECT_NEAR(s.mean_height, mean, 0.01 * std::sqrt(var));
  EXPECT_NEAR(s.height_variance, var, 0.01 * var);
  EXPECT_NEAR(s.skewness, skew, 0.02);
  EXPECT_NEAR(s.slope_variance.x, slope_var.x, 0.01 * slope_var.x);
  EXPECT_NEAR(s.slope_variance.y, slope_var.y, 0.01 * slope_var.y);
  EXPECT_GT(s.skewness, 0.5) << "the test map should be far from Gaussian";
  EXPECT_NEAR(s.area, (hi.x - lo.x) * (hi.y - lo.y), 0.03 * s.area);
  // a_s of a(h) = abar + a_s s(h): close to the generating a_s (exactly, when
  // the mean of s(h) over the region is 0).
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.a_s[c], kAs[c], 0.1 * kAs[c]);
}

TEST(HeightmapScene, TheWholeMapIsCentredAndSigmaHIsItsDeviation) {
  HeightmapScene scene(peaks_map(33), 0.01f, kAbar, kAs);
  SurfaceStatistics s = scene.statistics(glm::vec2(-1), glm::vec2(1));
  EXPECT_NEAR(s.mean_height, 0.0, 1e-6);
  EXPECT_NEAR(std::sqrt(s.height_variance), scene.sigma_h(), 1e-4 * scene.sigma_h());
  EXPECT_NEAR(s.area, 4.0, 1e-9);
}

TEST(HeightmapScene, GradientAndDistanceAgreeWithFiniteDifferences) {
  HeightmapScene scene(peaks_map(33), 0.01f, kAbar, kAs);
  for (glm::vec2 p : {glm::vec2(0.013f, -0.271f), glm::vec2(-0.52f, 0.33f), glm::vec2(0.71f, 0.64f)}) {
    const float e = 1e-4f;
    glm::vec2 fd((scene.height(p.x + e, p.y) - scene.height(p.x - e, p.y)) / (2 * e),
                 (scene.height(p.x, p.y + e) - scene.height(p.x, p.y - e)) / (2 * e));
    glm::vec2 g = scene.gradient(p.x, p.y);
    EXPECT_NEAR(g.x, fd.x, 0.01f * (1 + std::abs(fd.x))) << p.x << "," << p.y;
    EXPECT_NEAR(g.y, fd.y, 0.01f * (1 + std::abs(fd.y))) << p.x << "," << p.y;
    // Above the surface positive, below negative, zero on it.
    float h = scene.height(p.x, p.y);
    EXPECT_GT(scene.distance(glm::vec3(p, h + 0.01f)), 0.0f);
    EXPECT_LT(scene.distance(glm::vec3(p, h - 0.01f)), 0.0f);
    EXPECT_NEAR(scene.distance(glm::vec3(p, h)), 0.0f, 1e-6f);
    EXPECT_GE(scene.lipschitz(), glm::length(g));
  }
}

TEST(HeightmapScene, RefusesABadMapOrAmplitude) {
  HeightMap one;
  one.width = one.height = 1;
  one.values = {0.5f};
  EXPECT_THROW(HeightmapScene(one, 0.01f, kAbar, kAs), std::invalid_argument);
  EXPECT_THROW(HeightmapScene(peaks_map(8), 0.0f, kAbar, kAs), std::invalid_argument);
  EXPECT_THROW(HeightmapScene(peaks_map(8), std::nanf(""), kAbar, kAs), std::invalid_argument);
}

TEST(HeightMapFile, ReadsLuminanceBottomRowFirstAndBoxFilters) {
  svo::testing::TempDir dir;
  // 4 x 2 pixels, grey levels; the PNG stores them sRGB-encoded in 8 bits.
  render::Frame f;
  f.width = 4;
  f.height = 2;
  const float top[4] = {0.1f, 0.2f, 0.3f, 0.4f}, bottom[4] = {0.5f, 0.6f, 0.7f, 0.8f};
  for (float v : top) f.colour.push_back(glm::vec4(v, v, v, 1));
  for (float v : bottom) f.colour.push_back(glm::vec4(v, v, v, 1));
  render::write_colour(dir / "map.png", f);
  auto stored = [](float linear) { return std::round(render::linear_to_srgb(linear) * 255.0f) / 255.0f; };
  HeightMap m = read_height_map(dir / "map.png", 0);
  ASSERT_EQ(m.width, 4);
  ASSERT_EQ(m.height, 2);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.at(i, 0), stored(bottom[i]), 1e-3f) << i;  // row 0: the image's bottom row
    EXPECT_NEAR(m.at(i, 1), stored(top[i]), 1e-3f) << i;
  }
  // Box filtering to 2 samples along the longer side: blocks of 2 x 2, at least 2 rows kept.
  HeightMap half = read_height_map(dir / "map.png", 2);
  ASSERT_EQ(half.width, 2);
  ASSERT_EQ(half.height, 2);
  EXPECT_NEAR(half.at(0, 0) + half.at(0, 1),
              0.5f * (stored(top[0]) + stored(top[1]) + stored(bottom[0]) + stored(bottom[1])), 2e-3f);
  EXPECT_THROW(read_height_map(dir / "missing.png", 0), std::runtime_error);
  try {
    read_height_map(dir / "missing.png", 0);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
  }
}

TEST(HeightmapMaterial, TheCurveAtZeroDegreesIsTheMeanColour) {
  HeightmapScene scene(peaks_map(65), 0.006f, kAbar, kAs);
  reference::MaterialOptions o;
  o.degrees = {0};
  o.size = 32;
  o.spp = 4;
  const glm::vec2 half(0.5f * o.patch);
  SurfaceStatistics s = scene.statistics(-half, half);
  reference::MaterialStatistics ms{glm::vec2(s.slope_variance), glm::vec3(s.abar), glm::vec3(s.a_s)};
  std::vector<reference::MaterialPoint> curve = reference::material_curve(scene, ms, o);
  ASSERT_EQ(curve.size(), 1u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(curve[0].truth[c], s.abar[c], 0.015 * s.abar[c]) << "channel " << c;
    EXPECT_NEAR(curve[0].eq17[c], s.abar[c], 1e-5) << "channel " << c;  // Lambda(v) = 0 facing the surface
    EXPECT_NEAR(curve[0].mip[c], s.abar[c], 1e-6) << "channel " << c;
  }
}

}  // namespace
}  // namespace svo::voxelizer
