// svo compare: error figures of an image against a reference (DESIGN
// section 9), optionally a false-colour picture of the error.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_hint.h"
#include "commands.h"
#include "output_checks.h"
#include "svo/reference/compare.h"
#include "svo/render/image_io.h"

namespace svo::tools {

namespace {

struct CompareArgs {
  std::string image;
  std::string reference;
  std::string diff;
  double diff_scale = 0;
  double diff_percentile = 0;  // > 0: the diff's scale at this percentile of the per-pixel error
  bool json = false;
  double max_megapixels = 32;
};

nlohmann::json optional_json(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace

void add_compare_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "compare",
      "Error of image A against reference B in linear radiance (EXR as written; PNG decoded from sRGB): RMSE, "
      "relMSE (pbrt-v4's MRSE, (a-b)^2/(b+0.01)^2), PSNR (peak 1), max error, and coverage error (mean |alpha "
      "difference|, overall and on B's silhouette pixels: alpha in (0.02, 0.98) or a 4-neighbour's alpha more "
      "than 0.5 away); and the outliers averages hide: the 99.9th percentile of the per-pixel error "
      "sqrt(mean over RGB (a-b)^2), the pixels more than a pixel away from B's silhouettes whose error exceeds "
      "0.25, and specks (pixels A covers, alpha > 0.05, where B covers nothing within 2 pixels)");
  auto a = std::make_shared<CompareArgs>();
  cmd->add_option("A", a->image, "The image to judge (e.g. svo render's .exr)")->required()->group("Input");
  cmd->add_option("B", a->reference, "The reference (e.g. svo reference's .exr)")->required()->group("Input");
  cmd->add_option("--max-megapixels", a->max_megapixels,
                  "Refuse an input of more pixels than this (in units of 2^20), from its header, before reading it "
                  "(about 60 bytes of memory per pixel of each input)")
      ->default_val(32)
      ->check(CLI::Range(0.001, 256.0))
      ->group("Input");
  cmd->add_flag("--json", a->json,
                "Print one JSON object on stdout: rmse, relmse, psnr (null when the colours are identical), "
                "max_error, coverage_error, coverage_error_silhouette, silhouette_pixels (coverage figures null "
                "without alpha), p999_error, interior_pixels, outliers, specks (null without alpha), width, height")
      ->group("Output");
  cmd->add_option("--diff", a->diff,
                  "Also write the per-pixel error sqrt(mean over RGB (a-b)^2) in false colour (.png, .jpg or .exr): "
                  "black 0, purple, orange, pale yellow at the scale and above, with a colour bar below labelled "
                  "0 (left) and the scale (right); the scale is printed. Default scale: the 99th percentile of "
                  "the error over covered pixels (alpha > 0 in either image; all pixels without alpha), so that a "
                  "few outliers do not darken the rest; the largest error where that percentile is 0")
      ->group("Output");
  auto* scale_option = cmd->add_option("--diff-scale", a->diff_scale,
                                       "Error shown as the top of the colour map, for diffs on one scale "
                                       "(default: the 99th percentile, see --diff)")
                           ->check(positive_number())
                           ->group("Output");
  cmd->add_option("--diff-percentile", a->diff_percentile,
                  "The top of the colour map at this percentile of the per-pixel error over covered pixels "
                  "instead of the 99th (100: the largest error)")
      ->check(CLI::Range(0.001, 100.0))
      ->excludes(scale_option)
      ->group("Output");

  cmd->callback([a, &exit_code] {
    if (!a->diff.empty()) {
      render::image_format(a->diff);
      render::check_writable_output(a->diff);
      check_distinct_outputs({{"A", a->image}, {"--diff", a->diff}});
      check_distinct_outputs({{"B", a->reference}, {"--diff", a->diff}});
    }
    const uint64_t max_pixels = uint64_t(a->max_megapixels * 1048576.0);
    const render::Image image = render::read_image(a->image, max_pixels, "--max-megapixels");
    const render::Image reference = render::read_image(a->reference, max_pixels, "--max-megapixels");
    const reference::ImageErrors e = reference::compare_images(image, reference, a->image, a->reference);
    if (image.film != reference.film) {
      std::cerr << "svo: warning: " << a->image << " and " << a->reference
                << " were written with different film settings (" << (image.film.empty() ? "linear" : image.film)
                << " vs " << (reference.film.empty() ? "linear" : reference.film)
                << "): 8-bit outputs are compared as displayed; compare the .exr files for radiance\n";
    }
    double scale = a->diff_scale;
    std::string scale_source = "--diff-scale";
    if (!a->diff.empty()) {
      if (!(scale > 0)) {
        const double percentile = a->diff_percentile > 0 ? a->diff_percentile : reference::kDiffPercentile;
        scale = reference::pixel_error_quantile(image, reference, percentile / 100, true);
        std::ostringstream name;
        if (percentile == 100) {
          name << "the largest error";
        } else {
          name << percentile << "th percentile";
        }
        scale_source = name.str();
      }
      if (!(scale > 0)) {
        scale = reference::max_pixel_error(image, reference);
        scale_source = "the largest error";
      }
      render::write_colour(a->diff, reference::with_colour_bar(reference::error_image(image, reference, scale), scale));
    }
    if (a->json) {
      nlohmann::json out{
          {"image", a->image},
          {"reference", a->reference},
          {"width", e.width},
          {"height", e.height},
          {"rmse", e.rmse},
          {"relmse", e.relmse},
          {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json(nullptr)},
          {"max_error", e.max_error},
          {"coverage_error", optional_json(e.coverage_error)},
          {"coverage_error_silhouette", optional_json(e.coverage_error_silhouette)},
          {"silhouette_pixels", e.silhouette_pixels},
          {"p999_error", e.p999_error},
          {"interior_pixels", e.interior_pixels},
          {"outliers", e.outliers},
          {"specks", e.specks ? nlohmann::json(*e.specks) : nlohmann::json(nullptr)},
          {"diff", a->diff.empty() ? nlohmann::json(nullptr) : nlohmann::json(a->diff)},
          {"diff_scale", a->diff.empty() ? nlohmann::json(nullptr) : nlohmann::json(scale)},
          {"diff_scale_source", a->diff.empty() ? nlohmann::json(nullptr) : nlohmann::json(scale_source)}};
      std::cout << out.dump() << "\n";
    } else {
      std::cout << std::setprecision(4) << a->image << " vs " << a->reference << " (" << e.width << "x" << e.height
                << "): RMSE " << e.rmse << ", relMSE " << e.relmse << ", PSNR " << e.psnr << " dB, max error "
                << e.max_error;
      if (e.coverage_error) {
        std::cout << ", coverage error " << *e.coverage_error;
        if (e.coverage_error_silhouette) {
          std::cout << " (" << *e.coverage_error_silhouette << " on " << e.silhouette_pixels << " silhouette pixels)";
        }
      } else {
        std::cout << ", no coverage (an image has no alpha)";
      }
      std::cout << "; 99.9th percentile error " << e.p999_error << ", " << e.outliers << " of " << e.interior_pixels
                << " pixels away from silhouettes off by more than " << reference::kOutlierError;
      if (e.specks) std::cout << ", " << *e.specks << " specks";
      if (!a->diff.empty()) std::cout << "; " << a->diff << " at scale " << scale << " (" << scale_source << ")";
      std::cout << "\n";
    }
    exit_code = 0;
  });
}

}  // namespace svo::tools
