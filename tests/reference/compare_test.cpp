// svo compare's figures on synthetic images whose answers are known in
// closed form, its silhouette definition, the false-colour picture, and its
// refusals (size mismatch, missing channels, values that are not finite).
#include "svo/reference/compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "temp_dir.h"

namespace svo::reference {
namespace {

using render::Image;

// An RGBA (or RGB) image whose channels are given per pixel.
Image make_image(int w, int h, const std::function<glm::vec4(int, int)>& f, bool with_alpha = true) {
  Image image;
  image.width = w;
  image.height = h;
  image.channels = with_alpha ? std::vector<std::string>{"R", "G", "B", "A"} : std::vector<std::string>{"R", "G", "B"};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      glm::vec4 v = f(x, y);
      for (size_t c = 0; c < image.channels.size(); ++c) image.pixels.push_back(v[int(c)]);
    }
  }
  return image;
}

TEST(Compare, IdenticalImagesHaveNoError) {
  Image a = make_image(9, 7, [](int x, int y) { return glm::vec4(0.1f * x, 0.05f * y, 0.3f, x < 4 ? 1.0f : 0.0f); });
  ImageErrors e = compare_images(a, a);
  EXPECT_EQ(e.rmse, 0);
  EXPECT_EQ(e.relmse, 0);
  EXPECT_EQ(e.max_error, 0);
  EXPECT_TRUE(std::isinf(e.psnr) && e.psnr > 0);
  ASSERT_TRUE(e.coverage_error && e.coverage_error_silhouette);
  EXPECT_EQ(*e.coverage_error, 0);
  EXPECT_EQ(*e.coverage_error_silhouette, 0);
  EXPECT_EQ(e.width, 9);
  EXPECT_EQ(e.height, 7);
}

TEST(Compare, ConstantOffsetGivesKnownFigures) {
  // b = 0.5 everywhere, a = b + 0.1 in R, G, B: RMSE 0.1, PSNR 20 dB,
  // relMSE 0.01 / 0.51^2, max error 0.1.
  Image b = make_image(8, 8, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1.0f); });
  Image a = make_image(8, 8, [](int, int) { return glm::vec4(0.6f, 0.6f, 0.6f, 1.0f); });
  ImageErrors e = compare_images(a, b);
  EXPECT_NEAR(e.rmse, 0.1, 1e-6);
  EXPECT_NEAR(e.psnr, 20.0, 1e-4);
  EXPECT_NEAR(e.relmse, 0.01 / (0.51 * 0.51), 1e-6);
  EXPECT_NEAR(e.max_error, 0.1, 1e-6);
  EXPECT_EQ(*e.coverage_error, 0);
  EXPECT_EQ(e.silhouette_pixels, 0u);
  EXPECT_FALSE(e.coverage_error_silhouette) << "no silhouette pixel: no silhouette figure";
}

TEST(Compare, RelativeErrorWeighsDarkPixelsMore) {
  // b ramps over x, one channel differs by 0.05: relMSE is the mean of
  // 0.0025 / (b + 0.01)^2 over the pixels and the three channels.
  auto ramp = [](int x) { return 0.1f * float(x); };
  Image b = make_image(10, 3, [&](int x, int) { return glm::vec4(ramp(x), 0.2f, 0.2f, 1.0f); });
  Image a = make_image(10, 3, [&](int x, int) { return glm::vec4(ramp(x) + 0.05f, 0.2f, 0.2f, 1.0f); });
  double expected = 0;
  for (int x = 0; x < 10; ++x) expected += 0.0025 / std::pow(double(ramp(x)) + 0.01, 2);
  expected /= 3 * 10;  // three channels, one differs
  ImageErrors e = compare_images(a, b);
  EXPECT_NEAR(e.relmse, expected, 1e-4 * expected);
  EXPECT_NEAR(e.rmse, std::sqrt(0.0025 / 3), 1e-6);
}

TEST(Compare, CoverageErrorOverallAndOnSilhouettes) {
  // Reference: columns 0-3 covered, column 4 half covered, 5-9 empty; 6 rows.
  // Silhouette pixels: column 4 (alpha in (0.02, 0.98)) only: no neighbours
  // differ by more than 0.5. The image's alpha is 0.2 too high in column 4
  // and 0.1 too low in column 0.
  auto ref_alpha = [](int x) { return x < 4 ? 1.0f : x == 4 ? 0.5f : 0.0f; };
  Image b = make_image(10, 6, [&](int x, int) { return glm::vec4(0.3f, 0.3f, 0.3f, ref_alpha(x)); });
  Image a = make_image(10, 6, [&](int x, int) {
    float alpha = ref_alpha(x) + (x == 4 ? 0.2f : 0.0f) - (x == 0 ? 0.1f : 0.0f);
    return glm::vec4(0.3f, 0.3f, 0.3f, alpha);
  });
  ImageErrors e = compare_images(a, b);
  EXPECT_EQ(e.silhouette_pixels, 6u);
  EXPECT_NEAR(*e.coverage_error, (0.2 + 0.1) / 10, 1e-6);
  EXPECT_NEAR(*e.coverage_error_silhouette, 0.2, 1e-6);
  EXPECT_EQ(e.rmse, 0);
}

TEST(Compare, SharpEdgesAreSilhouettesOnBothSides) {
  Image b = make_image(6, 4, [](int x, int) { return glm::vec4(0, 0, 0, x < 3 ? 1.0f : 0.0f); });
  std::vector<uint8_t> mask = silhouette_mask(b);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 6; ++x) EXPECT_EQ(mask[size_t(y * 6 + x)], (x == 2 || x == 3) ? 1 : 0) << x << "," << y;
  }
}

TEST(Compare, WithoutAlphaCoverageIsUnknown) {
  Image b = make_image(4, 4, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1.0f); });
  Image a = make_image(
      4, 4, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1.0f); }, false);
  ImageErrors e = compare_images(a, b);
  EXPECT_FALSE(e.coverage_error);
  EXPECT_FALSE(e.coverage_error_silhouette);
  EXPECT_EQ(e.rmse, 0);
}

// Outliers: a pixel off by 0.5 in the middle of a covered image counts, and
// so does an isolated speck off by 0.3; the same errors beside the
// silhouette do not. A covered pixel 7 pixels from anything the reference
// covers is a speck, one 2 pixels away is not.
TEST(Compare, OutliersAwayFromSilhouettesAndIsolatedSpecks) {
  // Reference: columns 0..9 covered (alpha 1), 10..19 empty; a sharp edge.
  const Image ref =
      make_image(20, 12, [](int x, int) { return x < 10 ? glm::vec4(0.5f, 0.5f, 0.5f, 1) : glm::vec4(0); });
  const Image ours = make_image(20, 12, [](int x, int y) {
    if (x == 4 && y == 6) return glm::vec4(1.0f, 1.0f, 1.0f, 1);      // off by 0.5, interior
    if (x == 9 && y == 3) return glm::vec4(1.0f, 1.0f, 1.0f, 1);      // off by 0.5, on the silhouette
    if (x == 11 && y == 8) return glm::vec4(0.3f, 0.3f, 0.3f, 0.3f);  // covered, 2 pixels from the edge
    if (x == 16 && y == 5) return glm::vec4(0.3f, 0.3f, 0.3f, 0.3f);  // covered, isolated
    return x < 10 ? glm::vec4(0.5f, 0.5f, 0.5f, 1) : glm::vec4(0);
  });
  const ImageErrors e = compare_images(ours, ref);
  // Columns 9 and 10 are silhouettes; widened by a pixel: 8..11 are not interior.
  EXPECT_EQ(e.interior_pixels, uint64_t((20 - 4) * 12));
  EXPECT_EQ(e.outliers, 2u);
  ASSERT_TRUE(e.specks.has_value());
  EXPECT_EQ(*e.specks, 1u);
  // 4 of 240 pixels are off: the 99.9th percentile is the largest error, 0.5.
  EXPECT_NEAR(e.p999_error, 0.5, 1e-6);
  EXPECT_NEAR(e.outlier_share(), 2.0 / double(e.interior_pixels), 1e-12);
  // Without alpha: every pixel is away from silhouettes, no speck figure.
  const ImageErrors n = compare_images(make_image(
                                           4, 4, [](int, int) { return glm::vec4(0.2f); }, false),
                                       make_image(
                                           4, 4, [](int, int) { return glm::vec4(0.6f); }, false));
  EXPECT_EQ(n.interior_pixels, 16u);
  EXPECT_EQ(n.outliers, 16u);
  EXPECT_FALSE(n.specks.has_value());
}

// The diff's scale at a percentile ignores the outliers above it; the colour
// bar below the picture runs from black to the top colour.
TEST(Compare, PercentileScaleAndColourBar) {
  const Image ref = make_image(10, 10, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1); });
  const Image ours = make_image(10, 10, [](int x, int y) {
    const float d = x == 0 && y == 0 ? 0.4f : 0.01f * float(x);  // one outlier, then errors 0 .. 0.09
    return glm::vec4(0.5f + d, 0.5f + d, 0.5f + d, 1);
  });
  EXPECT_NEAR(pixel_error_quantile(ours, ref, 1.0), 0.4, 1e-6);
  EXPECT_NEAR(pixel_error_quantile(ours, ref, 1.0), max_pixel_error(ours, ref), 1e-9);
  EXPECT_NEAR(pixel_error_quantile(ours, ref, 0.99), 0.09, 1e-6);
  const render::Frame bar = with_colour_bar(error_image(ours, ref, 0.09));
  ASSERT_EQ(bar.width, 10u);
  ASSERT_EQ(bar.height, 24u);
  EXPECT_EQ(glm::vec3(bar.colour[size_t(11 * 10)]), glm::vec3(0));  // the gap
  EXPECT_EQ(glm::vec3(bar.colour[size_t(15 * 10)]), false_colour(0.0));
  EXPECT_EQ(glm::vec3(bar.colour[size_t(15 * 10 + 9)]), false_colour(1.0));
}

TEST(Compare, RefusesMismatchedOrBrokenImagesNamingThem) {
  Image a = make_image(4, 3, [](int, int) { return glm::vec4(0.5f); });
  Image b = make_image(3, 4, [](int, int) { return glm::vec4(0.5f); });
  try {
    compare_images(a, b, "a.exr", "b.exr");
    FAIL() << "different sizes were compared";
  } catch (const render::ImageError& e) {
    EXPECT_STREQ(e.what(), "a.exr is 4x3 but b.exr is 3x4");
  }
  Image grey = a;
  grey.channels = {"Y", "A", "Z", "W"};
  EXPECT_THROW(compare_images(grey, a, "grey.png", "a.exr"), render::ImageError);
  Image nan = a;
  nan.pixels[5] = std::nanf("");
  try {
    compare_images(nan, a, "nan.exr", "a.exr");
    FAIL() << "a NaN was compared";
  } catch (const render::ImageError& e) {
    EXPECT_STREQ(e.what(), "nan.exr: pixel (1, 0) channel G is not finite");
  }
}

TEST(Compare, ErrorImageRunsFromBlackToTheTopColour) {
  Image b = make_image(4, 1, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1.0f); });
  Image a = make_image(4, 1, [](int x, int) { return glm::vec4(0.5f + 0.1f * x, 0.5f, 0.5f, 1.0f); });
  const double top = max_pixel_error(a, b);
  EXPECT_NEAR(top, 0.3 / std::sqrt(3.0), 1e-6);
  render::Frame f = error_image(a, b, top);
  ASSERT_EQ(f.colour.size(), 4u);
  EXPECT_LT(f.colour[0].r + f.colour[0].g, 1e-3f) << "no error: black";
  // Brightness grows with the error; the largest is the pale yellow top.
  for (int x = 1; x < 4; ++x) {
    EXPECT_GT(f.colour[size_t(x)].r + f.colour[size_t(x)].g, f.colour[size_t(x) - 1].r + f.colour[size_t(x) - 1].g);
  }
  EXPECT_GT(f.colour[3].g, 0.9f);
  EXPECT_EQ(f.colour[3].a, 1.0f);
}

TEST(Compare, FilesRoundTripThroughExrAndPng) {
  render::testing::TempDir dir;
  render::Frame frame;
  frame.width = 5;
  frame.height = 4;
  for (int i = 0; i < 20; ++i) frame.colour.push_back(glm::vec4(0.05f * i, 0.5f, 0.25f, i % 2 ? 1.0f : 0.25f));
  render::write_colour(dir / "a.exr", frame);
  render::write_colour(dir / "a.png", frame);
  ImageErrors exact = compare_images(render::read_image(dir / "a.exr"), render::read_image(dir / "a.exr"));
  EXPECT_EQ(exact.rmse, 0);
  // PNG: 8-bit sRGB, no alpha; decoded to linear it agrees within quantisation.
  ImageErrors png = compare_images(render::read_image(dir / "a.png"), render::read_image(dir / "a.exr"));
  EXPECT_LT(png.max_error, 0.01);
  EXPECT_FALSE(png.coverage_error);
}

}  // namespace
}  // namespace svo::reference
