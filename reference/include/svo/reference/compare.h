// Error figures of an image against a reference (DESIGN section 9), in
// linear radiance. Images come from render::read_image (EXR as written, PNG
// decoded from sRGB to linear); colour is the channels named R, G, B and
// coverage the channel named A.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "svo/render/image_io.h"
#include "svo/render/renderer.h"

namespace svo::reference {

struct ImageErrors {
  int width = 0, height = 0;
  // Over all pixels and the R, G, B channels, with a the image and b the reference:
  double rmse = 0;       // sqrt(mean (a - b)^2)
  double relmse = 0;     // mean (a - b)^2 / (b + 0.01)^2 (pbrt-v4's MRSE)
  double psnr = 0;       // 10 log10(1 / mean (a - b)^2): peak 1; +infinity for identical colours
  double max_error = 0;  // max |a - b|
  // Mean |alpha_a - alpha_b| over all pixels; nullopt when either image has no A channel.
  std::optional<double> coverage_error;
  // The same over the reference's silhouette pixels (silhouette_mask); nullopt
  // without alpha or when the reference has no silhouette pixel.
  std::optional<double> coverage_error_silhouette;
  uint64_t silhouette_pixels = 0;
  // Outliers, which averages hide (issue 20). The per-pixel error is
  // sqrt(mean over R, G, B of (a - b)^2), what error_image shows:
  double p999_error = 0;  // its 99.9th percentile over all pixels
  // Pixels more than a pixel away from the reference's silhouette pixels
  // (silhouette_mask: all pixels without alpha), and those of them whose
  // error exceeds kOutlierError.
  uint64_t interior_pixels = 0;
  uint64_t outliers = 0;
  // Isolated specks: pixels the image covers (alpha above 0.05) where the
  // reference covers nothing within 2 pixels (alpha 0 in the 5x5 window);
  // nullopt without alpha.
  std::optional<uint64_t> specks;
  double outlier_share() const { return interior_pixels ? double(outliers) / double(interior_pixels) : 0.0; }
};

// The per-pixel error above which a pixel away from silhouettes is an outlier.
inline constexpr double kOutlierError = 0.25;

// Silhouette pixels of a reference's coverage: alpha strictly between 0.02
// and 0.98 (partly covered), or a 4-neighbour whose alpha differs by more
// than 0.5 (an edge between two pixels, however sharp). One byte per pixel,
// row-major; all zero when the image has no A channel.
std::vector<uint8_t> silhouette_mask(const render::Image& reference);

// Compares `image` (called `image_name` in messages) with `reference`.
// RMSE and max error come from OpenImageIO's ImageBufAlgo::compare (PSNR
// from its RMSE); relMSE and the coverage figures are computed here.
// @throw render::ImageError "<name>: <why>" when an image lacks R, G, B
//        channels or holds a value that is not finite, or "<image_name> is
//        WxH but <reference_name> is WxH" for different sizes.
ImageErrors compare_images(const render::Image& image, const render::Image& reference,
                           const std::string& image_name = "image", const std::string& reference_name = "reference");

// The colour map of error_image at `value` in [0, 1] (clamped): black
// through purple and orange to pale yellow, linear RGB.
glm::vec3 false_colour(double value);

// A false-colour picture of the per-pixel error sqrt(mean over R, G, B of
// (a - b)^2): black (0) through purple and orange to pale yellow (`scale`
// and above), an approximation of the "inferno" colour map. Linear RGB,
// alpha 1, ready for render::write_colour. The images must have passed
// compare_images.
render::Frame error_image(const render::Image& image, const render::Image& reference, double scale);

// The largest per-pixel error error_image would show.
double max_pixel_error(const render::Image& image, const render::Image& reference);
// Its q-quantile (q in (0, 1]; 1: the largest), a scale that outliers do not
// set. With `covered_only`, over the pixels either image covers (alpha > 0;
// all pixels when either has no A channel), so that a frame of mostly
// background does not pull the scale to 0; 0 when no pixel is covered.
double pixel_error_quantile(const render::Image& image, const render::Image& reference, double q,
                            bool covered_only = false);

// The default scale of svo compare --diff: the 99th percentile of the
// per-pixel error over covered pixels, or the largest error where that is 0
// (fewer than 1 % of the pixels differ).
inline constexpr double kDiffPercentile = 99.0;
double default_diff_scale(const render::Image& image, const render::Image& reference);

// Height in pixels of the colour bar with_colour_bar adds under a frame `width` wide.
uint32_t colour_bar_height(uint32_t width);
// The colour bar's label of a value: 3 significant digits ("0.0123", "1.5e-05").
std::string colour_bar_label(double value);

// `frame` (an error_image of scale `scale`) with a labelled colour bar
// below it, all of it colour_bar_height(width) rows at text scale
// s = max(1, width / 320): 4s black rows, 10s rows of the colour map from 0
// (left) to the scale (right), then on black, in white 5x7 digits of s x s
// pixels, "0" at the left, the scale (colour_bar_label) at the right and,
// where it fits between them, "per-pixel RMS error" in the middle.
render::Frame with_colour_bar(render::Frame frame, double scale);

}  // namespace svo::reference
