// svo compare's figures on synthetic images whose answers are known in
// closed form, its silhouette definition, the false-colour picture, and its
// refusals (size mismatch, missing channels, values that are not finite).
#include "svo/reference/compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "svo/render/text.h"
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
  const render::Frame bar = with_colour_bar(error_image(ours, ref, 0.09), 0.09);
  ASSERT_EQ(bar.width, 10u);
  ASSERT_EQ(colour_bar_height(10), 27u);
  ASSERT_EQ(bar.height, 37u);
  EXPECT_EQ(glm::vec3(bar.colour[size_t(11 * 10)]), glm::vec3(0));  // the gap
  EXPECT_EQ(glm::vec3(bar.colour[size_t(15 * 10)]), false_colour(0.0));
  EXPECT_EQ(glm::vec3(bar.colour[size_t(15 * 10 + 9)]), false_colour(1.0));
}

// svo compare --diff's default scale: the 99th percentile over covered
// pixels, so that one outlier does not set it (the diff is not black), and
// the largest error where fewer than 1 % of the pixels differ.
TEST(Compare, DefaultDiffScaleIsAPercentileOverCoveredPixels) {
  // 20 x 20: the left half covered, small errors there and one outlier; the
  // right half background (alpha 0, no error) that would pull a percentile
  // over all pixels down.
  const Image ref = make_image(20, 20, [](int x, int) { return glm::vec4(0.5f, 0.5f, 0.5f, x < 10 ? 1.0f : 0.0f); });
  const Image ours = make_image(20, 20, [](int x, int y) {
    const float d = x == 3 && y == 3 ? 0.5f : x < 10 ? 0.02f + 0.002f * float(y % 5) : 0.0f;
    return glm::vec4(0.5f + d, 0.5f + d, 0.5f + d, x < 10 ? 1.0f : 0.0f);
  });
  const double scale = default_diff_scale(ours, ref);
  EXPECT_NEAR(scale, 0.028, 1e-6);
  EXPECT_LT(scale, 0.1 * max_pixel_error(ours, ref));
  EXPECT_NEAR(pixel_error_quantile(ours, ref, 0.5, false), 0.0, 1e-9) << "half the pixels are background";
  // A typical covered pixel is far from black at this scale, and black at the largest.
  const render::Frame diff = error_image(ours, ref, scale), worst = error_image(ours, ref, max_pixel_error(ours, ref));
  const glm::vec4 typical = diff.colour[size_t(7 * 20 + 5)], dark = worst.colour[size_t(7 * 20 + 5)];
  EXPECT_GT(typical.r + typical.g + typical.b, 0.3f);
  EXPECT_LT(dark.r + dark.g + dark.b, 0.05f);
  // One differing pixel of 400: the 99th percentile is 0, the scale its error.
  const Image one =
      make_image(20, 20, [](int x, int y) { return glm::vec4(x == 1 && y == 1 ? 0.8f : 0.5f, 0.5f, 0.5f, 1.0f); });
  EXPECT_NEAR(default_diff_scale(one, ref), 0.3 / std::sqrt(3.0), 1e-6);
  EXPECT_EQ(default_diff_scale(ref, ref), 0.0);
}

// The colour bar is labelled: "0" at its left and the scale at its right in
// white digits under the bar, the title between them where it fits.
TEST(Compare, ColourBarIsLabelled) {
  EXPECT_EQ(colour_bar_label(0.0123456), "0.0123");
  EXPECT_EQ(colour_bar_label(1.5e-05), "1.5e-05");
  EXPECT_EQ(colour_bar_label(0.25), "0.25");
  const Image ref = make_image(200, 50, [](int, int) { return glm::vec4(0.5f, 0.5f, 0.5f, 1); });
  const Image ours = make_image(200, 50, [](int x, int) { return glm::vec4(0.5f + 0.001f * float(x), 0.5f, 0.5f, 1); });
  const render::Frame f = with_colour_bar(error_image(ours, ref, 0.0123), 0.0123);
  ASSERT_EQ(f.height, 50u + colour_bar_height(200));
  // White pixels in the label rows: left (the "0"), right (the scale), middle (the title).
  auto white_in = [&](uint32_t x0, uint32_t x1) {
    int n = 0;
    for (uint32_t y = 50 + 17; y < 50 + 24; ++y) {
      for (uint32_t x = x0; x < x1; ++x) n += f.colour[size_t(y) * 200 + x] == glm::vec4(1.0f);
    }
    return n;
  };
  EXPECT_GT(white_in(0, 8), 5) << "the 0";
  EXPECT_GT(white_in(160, 200), 20) << "the scale, 0.0123";
  EXPECT_GT(white_in(60, 140), 40) << "per-pixel RMS error";
  EXPECT_EQ(white_in(8, 40), 0);
  // The scale's digits exactly: "0.0123" right-aligned, one pixel from the edge.
  render::Frame label;
  label.width = 200;
  label.height = f.height;
  label.colour.assign(size_t(200) * f.height, glm::vec4(0, 0, 0, 1));
  render::draw_text(label, 200 - 1 - render::text_width("0.0123"), 50 + 17, "0.0123", glm::vec3(1.0f));
  for (uint32_t y = 50 + 17; y < 50 + 24; ++y) {
    for (uint32_t x = 160; x < 200; ++x) {
      EXPECT_EQ(f.colour[size_t(y) * 200 + x], label.colour[size_t(y) * 200 + x]) << x << "," << y;
    }
  }
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
