// Frames to image files and back. Writes go through libpng, libjpeg and
// OpenEXR directly (no OpenImageIO, so that svo-render links no format
// plugins); read_image has two implementations, chosen at link time: the
// svo_render library reads any format OpenImageIO reads, svo_render_core
// with svo_image_read_direct (svo-render) reads OpenEXR and PNG only.
// Every write goes to a temporary file in the target's directory, is flushed to disk and renamed
// over the target: a crash or a failed write never leaves a half-written
// file under the final name nor destroys the file that was there.
//
// Colour files, chosen by the extension (case-insensitive):
//   .png  8-bit RGB, sRGB transfer, no alpha. Frame::colour's RGB already
//         holds the background in the bits no element covered (the tracer
//         composites), so the PNG is the finished picture; linear radiance
//         goes through the Film (exposure, tone map) and is clamped to
//         [0, 1] before the sRGB transfer.
//   .jpg, .jpeg  the same as PNG, baseline JPEG at quality 95, chroma not
//         subsampled (4:4:4).
//   .exr  32-bit float R, G, B, A, linear radiance as rendered (no clamp,
//         no Film); A = coverage. RGB includes the background, so A records
//         coverage and is not an associated (premultiplied) alpha.
// G-buffer files are .exr only: one 32-bit float channel per field of
// GBufferTexel (shaders/common/gbuffer.glsl), named in kGBufferChannels.
#pragma once

#include <array>
#include <cmath>
#include <glm/vec3.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "svo/render/renderer.h"

namespace svo::render {

// Any problem with an image file: one line that starts with the path.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ImageFormat { Png, Jpeg, Exr };

// Whether a format stores 8-bit display values (PNG, JPEG), which the Film makes.
bool is_8bit(ImageFormat format);

// The format of `path` from its extension.
// @throw ImageError "<path>: unsupported image extension '<ext>' (use .png, .jpg or .exr)".
ImageFormat image_format(const std::string& path);

// How linear radiance becomes an 8-bit picture (PNG, JPEG). Float outputs
// (EXR) are never touched: they hold the radiance as rendered.
enum class Tonemap {
  None,    // clamp to [0, 1]
  Filmic,  // the ACES filmic curve as fitted by Narkowicz (2015), per channel
};
struct Film {
  float exposure_ev = 0;  // radiance is scaled by 2^exposure_ev first
  Tonemap tonemap = Tonemap::None;
  bool operator==(const Film&) const = default;
};

// "none", "filmic"; nullopt for another name.
std::optional<Tonemap> parse_tonemap(const std::string& name);
const char* tonemap_name(Tonemap tonemap);

// Narkowicz's fit of the ACES reference rendering transform: x (2.51 x + 0.03)
// / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]: 0 -> 0, 0.18 -> 0.27,
// 1 -> 0.80, 2 -> 0.91, 1 at about 7.2 and above; increasing on [0, 7.2].
// (K. Narkowicz, "ACES Filmic Tone Mapping Curve", 2015.) NaN and values
// below 0 give 0.
float filmic(float linear);

// One linear value as the Film shows it: scaled by 2^exposure_ev, tone
// mapped, in [0, 1] (display-linear, before the sRGB transfer). NaN gives 0.
float apply_film(float linear, const Film& film);

// Refuses an output path before any work is done, by the rules of
// svo::files::OutputFile: its directory must exist and be writable; an
// existing file there must be a regular, writable file (a symbolic link is
// written through to its target).
// @throw ImageError "<path>: directory <dir> does not exist" (or "is not a
//        directory", "is not writable"), "<path>: is a directory; ...",
//        "<path>: is read-only; ...".
void check_writable_output(const std::string& path);

// Writes frame.colour as PNG, JPEG or EXR (see above), atomically; `film`
// applies to PNG and JPEG only. A PNG or JPEG written with a Film other than
// the default says so in its ImageDescription ("svo film: exposure +1 EV,
// tonemap filmic"), which read_image returns as Image::film.
// @throw ImageError for an unsupported extension, a frame whose colour does
//        not hold width * height pixels, or any failure to write.
void write_colour(const std::string& path, const Frame& frame, const Film& film = {});

// "exposure +1 EV, tonemap filmic"; "" for the default Film.
std::string film_description(const Film& film);

constexpr std::array<const char*, 24> kGBufferChannels{
    "depth",  "P.x",   "P.y",          "P.z",          "N.x",          "N.y",        "N.z",       "T.x",
    "T.y",    "T.z",   "slope_cov.xx", "slope_cov.yy", "slope_cov.xy", "sigma_rho2", "abar.R",    "abar.G",
    "abar.B", "a_s.R", "a_s.G",        "a_s.B",        "coverage",     "material",   "material2", "material_mix"};

// Writes frame.gbuffer as one multi-channel float EXR, atomically.
// @throw ImageError when `path` is not .exr, the frame has no G-buffer of
//        width * height texels, or the write fails.
void write_gbuffer(const std::string& path, const Frame& frame);

// Writes the image `name` of the renderer's last frame (its level 0) as a
// float EXR, atomically: Rgba32f as R, G, B, A; R32u as one channel named
// after the image; Rgba8 as R, G, B, A in [0, 1]; the G-buffer as
// kGBufferChannels.
// @throw ImageError when `path` is not .exr or the write fails;
//        std::invalid_argument when the last frame has no such image.
void write_aov(const std::string& path, Renderer& renderer, const std::string& name);

// Writes frame.steps (cone elements visited per pixel, shadow cones
// included) as a one-channel float EXR named "steps", atomically: where a
// frame's cost goes.
// @throw ImageError when `path` is not .exr, the frame has no steps for
//        width * height pixels, or the write fails.
void write_steps(const std::string& path, const Frame& frame);

// An image in memory: float samples, channel-interleaved, row-major, top row first.
struct Image {
  int width = 0, height = 0;
  std::vector<std::string> channels;  // names as stored in the file
  std::vector<float> pixels;          // width * height * channels.size()
  // An 8-bit file's Film as write_colour recorded it (film_description);
  // "" for a float file or one written without exposure or tone map.
  std::string film;

  // Index of the channel called `name`, or -1.
  int channel(const std::string& name) const {
    for (size_t c = 0; c < channels.size(); ++c)
      if (channels[c] == name) return int(c);
    return -1;
  }
  float at(int x, int y, int c) const {
    return pixels[(size_t(y) * size_t(width) + size_t(x)) * channels.size() + size_t(c)];
  }
};

inline constexpr double kMaxImageSamples = 268435456.0;  // 2^28: 1 GiB of floats
// The default budget of read_image: 2^25 pixels (8192 x 4096), about 0.5 GiB
// as RGBA floats.
inline constexpr uint64_t kDefaultMaxImagePixels = uint64_t(1) << 25;

// Reads any image OpenImageIO reads (svo-render: OpenEXR and PNG only), as float. 8- and 16-bit files in the
// sRGB colour space (PNG, as written here) are converted to linear values,
// so that a PNG and an EXR of the same frame compare directly.
// Only a regular file is opened (a FIFO or a link to /dev/zero would hang
// the format libraries). Images of more than `max_pixels` pixels or
// kMaxImageSamples samples (width x height x channels) are refused from
// their header, before their pixels are allocated; `limit_option` (e.g.
// "--max-megapixels") is named in that message as the way to raise it.
// @throw ImageError "<path>: <reason>" (does not exist, is a FIFO, cannot
//        open, not an image, too large, ...).
Image read_image(const std::string& path, uint64_t max_pixels = kDefaultMaxImagePixels,
                 const std::string& limit_option = "");

// A frame's colour as an image of channels R, G, B, A (for compare_images and the like).
Image frame_image(const Frame& frame);

// The sRGB transfer and its inverse, for values in [0, 1] (IEC 61966-2-1).
inline float linear_to_srgb(float x) {
  if (!(x > 0)) return 0;
  if (x >= 1) return 1;
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}
inline float srgb_to_linear(float s) {
  if (!(s > 0)) return 0;
  if (s >= 1) return 1;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

// A colour as a user writes it, as linear RGB: "R,G,B" (three linear values
// in [0, 1]) or "#rrggbb" (hexadecimal sRGB, as colour pickers give it,
// decoded by srgb_to_linear). Untrusted text.
// @throw std::invalid_argument "'<text>': expected R,G,B (linear, each in
//        [0, 1]) or #rrggbb (sRGB hex)" for anything else.
glm::vec3 parse_colour(const std::string& text);

}  // namespace svo::render
