#include "svo/reference/compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <limits>

#include "common/shared_math.h"
#include "svo/render/text.h"

namespace svo::reference {

namespace {

using render::Image;
using render::ImageError;

// compare() counts values above its thresholds as failures; we want figures only.
constexpr float kNoThreshold = std::numeric_limits<float>::max();

std::array<int, 3> rgb_channels(const Image& image, const std::string& name) {
  std::array<int, 3> c{image.channel("R"), image.channel("G"), image.channel("B")};
  if (c[0] < 0 || c[1] < 0 || c[2] < 0) {
    std::string names;
    for (const auto& n : image.channels) names += (names.empty() ? "" : ", ") + n;
    throw ImageError(name + ": needs R, G, B channels, has " + (names.empty() ? "none" : names));
  }
  return c;
}

void check_finite(const Image& image, const std::string& name) {
  const size_t channels = image.channels.size();
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    if (!std::isfinite(image.pixels[i])) {
      const size_t pixel = i / channels;
      throw ImageError(name + ": pixel (" + std::to_string(pixel % size_t(image.width)) + ", " +
                       std::to_string(pixel / size_t(image.width)) + ") channel " + image.channels[i % channels] +
                       " is not finite");
    }
  }
}

// The R, G, B channels as an OpenImageIO float buffer.
OIIO::ImageBuf rgb_buffer(const Image& image, const std::array<int, 3>& c) {
  OIIO::ImageBuf buffer(OIIO::ImageSpec(image.width, image.height, 3, OIIO::TypeDesc::FLOAT));
  std::array<float, 3> rgb{};
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (int k = 0; k < 3; ++k) rgb[size_t(k)] = image.at(x, y, c[size_t(k)]);
      buffer.setpixel(x, y, rgb.data(), 3);
    }
  }
  return buffer;
}

// Squared error of pixel (x, y) averaged over R, G, B.
double pixel_mse(const Image& a, const std::array<int, 3>& ca, const Image& b, const std::array<int, 3>& cb, int x,
                 int y) {
  double sum = 0;
  for (size_t k = 0; k < 3; ++k) {
    const double d = double(a.at(x, y, ca[k])) - double(b.at(x, y, cb[k]));
    sum += d * d;
  }
  return sum / 3;
}

// Stops of the colour map, sRGB-encoded (after matplotlib's "inferno").
constexpr std::array<glm::vec3, 5> kStops{glm::vec3(0.0f, 0.0f, 0.016f), glm::vec3(0.341f, 0.063f, 0.431f),
                                          glm::vec3(0.737f, 0.216f, 0.329f), glm::vec3(0.976f, 0.557f, 0.035f),
                                          glm::vec3(0.988f, 1.0f, 0.643f)};

}  // namespace

std::vector<uint8_t> silhouette_mask(const Image& reference) {
  const int w = reference.width, h = reference.height, a = reference.channel("A");
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  if (a < 0) return mask;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const float alpha = reference.at(x, y, a);
      bool edge = alpha > 0.02f && alpha < 0.98f;
      const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4 && !edge; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        edge = std::abs(reference.at(nx[k], ny[k], a) - alpha) > 0.5f;
      }
      mask[size_t(y) * size_t(w) + size_t(x)] = edge ? 1 : 0;
    }
  }
  return mask;
}

namespace {

// The outlier figures of ImageErrors (p999_error, interior_pixels, outliers, specks).
// The q-quantile of `errors` (reordered), q in (0, 1].
double quantile(std::vector<double>& errors, double q) {
  if (errors.empty()) return 0;
  const size_t k = std::min(errors.size() - 1, size_t(std::max(1.0, std::ceil(q * double(errors.size())))) - 1);
  std::nth_element(errors.begin(), errors.begin() + std::ptrdiff_t(k), errors.end());
  return errors[k];
}

void outliers(const Image& image, const std::array<int, 3>& ca, int aa, const Image& reference,
              const std::array<int, 3>& cb, int ab, const std::vector<uint8_t>& silhouette, ImageErrors& e) {
  const int w = image.width, h = image.height;
  // Whether any pixel of the (2r + 1)^2 window around (x, y) passes `test`.
  auto any_within = [&](int x, int y, int r, auto test) {
    for (int v = std::max(0, y - r); v <= std::min(h - 1, y + r); ++v)
      for (int u = std::max(0, x - r); u <= std::min(w - 1, x + r); ++u)
        if (test(u, v)) return true;
    return false;
  };
  std::vector<double> errors;
  errors.reserve(size_t(w) * size_t(h));
  uint64_t specks = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double error = std::sqrt(pixel_mse(image, ca, reference, cb, x, y));
      errors.push_back(error);
      if (!any_within(x, y, 1, [&](int u, int v) { return silhouette[size_t(v) * size_t(w) + size_t(u)] != 0; })) {
        ++e.interior_pixels;
        if (error > kOutlierError) ++e.outliers;
      }
      if (aa >= 0 && ab >= 0 && image.at(x, y, aa) > 0.05f &&
          !any_within(x, y, 2, [&](int u, int v) { return reference.at(u, v, ab) > 0.0f; })) {
        ++specks;
      }
    }
  }
  if (aa >= 0 && ab >= 0) e.specks = specks;
  e.p999_error = quantile(errors, 0.999);
}

}  // namespace

ImageErrors compare_images(const Image& image, const Image& reference, const std::string& image_name,
                           const std::string& reference_name) {
  const auto ca = rgb_channels(image, image_name);
  const auto cb = rgb_channels(reference, reference_name);
  if (image.width != reference.width || image.height != reference.height) {
    throw ImageError(image_name + " is " + std::to_string(image.width) + "x" + std::to_string(image.height) + " but " +
                     reference_name + " is " + std::to_string(reference.width) + "x" +
                     std::to_string(reference.height));
  }
  check_finite(image, image_name);
  check_finite(reference, reference_name);
  ImageErrors e;
  e.width = image.width;
  e.height = image.height;
  const OIIO::ImageBuf a = rgb_buffer(image, ca), b = rgb_buffer(reference, cb);
  const OIIO::ImageBufAlgo::CompareResults r = OIIO::ImageBufAlgo::compare(a, b, kNoThreshold, kNoThreshold);
  if (r.error) throw ImageError(image_name + ": comparison failed: " + OIIO::geterror());
  e.rmse = r.rms_error;
  e.psnr = r.rms_error > 0 ? 20.0 * std::log10(1.0 / r.rms_error) : std::numeric_limits<double>::infinity();
  e.max_error = r.maxerror;
  // pbrt-v4's MRSE, by hand: OpenImageIO has no relative error.
  double relative = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      for (size_t k = 0; k < 3; ++k) {
        const double ref = reference.at(x, y, cb[k]), d = double(image.at(x, y, ca[k])) - ref;
        relative += d * d / ((ref + 0.01) * (ref + 0.01));
      }
    }
  }
  const double samples = 3.0 * double(image.width) * double(image.height);
  e.relmse = relative / samples;
  const std::vector<uint8_t> silhouette = silhouette_mask(reference);
  for (uint8_t s : silhouette) e.silhouette_pixels += s;
  const int aa = image.channel("A"), ab = reference.channel("A");
  if (aa >= 0 && ab >= 0) {
    double all = 0, edge = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const double d = std::abs(double(image.at(x, y, aa)) - double(reference.at(x, y, ab)));
        all += d;
        if (silhouette[size_t(y) * size_t(image.width) + size_t(x)]) edge += d;
      }
    }
    e.coverage_error = all / (double(image.width) * double(image.height));
    if (e.silhouette_pixels > 0) e.coverage_error_silhouette = edge / double(e.silhouette_pixels);
  }
  outliers(image, ca, aa, reference, cb, ab, silhouette, e);
  return e;
}

double max_pixel_error(const Image& image, const Image& reference) {
  return pixel_error_quantile(image, reference, 1.0);
}

double pixel_error_quantile(const Image& image, const Image& reference, double q, bool covered_only) {
  const auto ca = rgb_channels(image, "image"), cb = rgb_channels(reference, "reference");
  const int aa = covered_only ? image.channel("A") : -1, ab = covered_only ? reference.channel("A") : -1;
  const bool all = aa < 0 || ab < 0;
  std::vector<double> errors;
  errors.reserve(size_t(image.width) * size_t(image.height));
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (all || image.at(x, y, aa) > 0 || reference.at(x, y, ab) > 0) {
        errors.push_back(std::sqrt(pixel_mse(image, ca, reference, cb, x, y)));
      }
    }
  }
  return quantile(errors, q);
}

double default_diff_scale(const Image& image, const Image& reference) {
  const double scale = pixel_error_quantile(image, reference, kDiffPercentile / 100.0, true);
  return scale > 0 ? scale : max_pixel_error(image, reference);
}

namespace {

// The text scale of a colour bar under a frame `width` wide.
int bar_text_scale(uint32_t width) { return std::max(1, int(width / 320)); }

}  // namespace

uint32_t colour_bar_height(uint32_t width) {
  // gap, bar, gap, digits, margin
  return uint32_t(bar_text_scale(width)) * (4 + 10 + 3 + uint32_t(render::kGlyphHeight) + 3);
}

std::string colour_bar_label(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

render::Frame with_colour_bar(render::Frame frame, double scale) {
  const int s = bar_text_scale(frame.width);
  const uint32_t w = frame.width, top = frame.height + uint32_t(4 * s), bar = uint32_t(10 * s);
  frame.colour.resize(size_t(w) * (frame.height + colour_bar_height(w)), glm::vec4(0, 0, 0, 1));
  for (uint32_t y = top; y < top + bar; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      frame.colour[size_t(y) * w + x] = glm::vec4(false_colour(w > 1 ? double(x) / double(w - 1) : 1.0), 1.0f);
    }
  }
  frame.height += colour_bar_height(w);
  const int text_y = int(top + bar) + 3 * s, margin = s;
  const glm::vec3 white(1.0f);
  const std::string high = colour_bar_label(scale), title = "per-pixel RMS error";
  const int high_x = int(w) - margin - render::text_width(high, s);
  render::draw_text(frame, margin, text_y, "0", white, s);
  render::draw_text(frame, std::max(high_x, margin), text_y, high, white, s);
  const int title_w = render::text_width(title, s), title_x = (int(w) - title_w) / 2;
  const int gap = render::kGlyphAdvance * s;
  if (title_x >= margin + render::text_width("0", s) + gap && title_x + title_w + gap <= high_x) {
    render::draw_text(frame, title_x, text_y, title, white, s);
  }
  return frame;
}

glm::vec3 false_colour(double value) {
  const double f = std::clamp(value, 0.0, 1.0) * double(kStops.size() - 1);
  const size_t i = std::min(size_t(f), kStops.size() - 2);
  const glm::vec3 srgb = glm::mix(kStops[i], kStops[i + 1], float(f - double(i)));
  return {svo::math::svo_srgb_to_linear(srgb.x), svo::math::svo_srgb_to_linear(srgb.y),
          svo::math::svo_srgb_to_linear(srgb.z)};
}

render::Frame error_image(const Image& image, const Image& reference, double scale) {
  const auto ca = rgb_channels(image, "image"), cb = rgb_channels(reference, "reference");
  render::Frame frame;
  frame.width = uint32_t(image.width);
  frame.height = uint32_t(image.height);
  frame.colour.resize(size_t(image.width) * size_t(image.height));
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double error = std::sqrt(pixel_mse(image, ca, reference, cb, x, y));
      const glm::vec3 c = false_colour(scale > 0 ? error / scale : (error > 0 ? 1.0 : 0.0));
      frame.colour[size_t(y) * size_t(image.width) + size_t(x)] = glm::vec4(c, 1.0f);
    }
  }
  return frame;
}

}  // namespace svo::reference
