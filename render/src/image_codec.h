// Image files without OpenImageIO: PNG through libpng, JPEG through
// libjpeg(-turbo), OpenEXR through the OpenEXR library, so that the
// renderer alone (svo-render) links no format plugins. Internal to
// svo_render and its two image readers.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "svo/octree/files.h"
#include "svo/octree/image_header.h"
#include "svo/render/image_io.h"

namespace svo::render::codec {

// The ImageDescription of an 8-bit file written with a Film, before
// film_description (PNG: the tEXt chunk "Description"; JPEG: a comment).
inline const std::string kFilmPrefix = "svo film: ";

// An 8-bit RGB picture (row-major, top row first, sRGB values) as PNG bytes:
// 8-bit RGB, an sRGB chunk, the text chunks "Software" = "svo" and, when
// not empty, "Description". Returns "" or libpng's message.
std::string encode_png(uint32_t width, uint32_t height, const uint8_t* rgb, const std::string& description,
                       std::vector<uint8_t>& out);

// The same as baseline JPEG at `quality`, chroma not subsampled (4:4:4),
// the description as a comment. Returns "" or libjpeg's message.
std::string encode_jpeg(uint32_t width, uint32_t height, const uint8_t* rgb, const std::string& description,
                        int quality, std::vector<uint8_t>& out);

// Channel-interleaved 32-bit floats as a ZIP-compressed scanline OpenEXR
// into `file` (not committed). Every write is checked.
// @throw ImageError "<path>: cannot write: ..." one line.
void write_exr(files::OutputFile& file, const std::string& path, uint32_t width, uint32_t height,
               const std::vector<std::string>& channels, const float* data);

// "<path>: WxH pixels, more than the limit of N (OPTION)" when an image's
// header states more than `max_pixels` pixels or kMaxImageSamples samples;
// "" otherwise. The image readers check this before they allocate.
inline std::string check_image_size(const std::string& path, uint64_t width, uint64_t height, uint64_t channels,
                                    uint64_t max_pixels, const std::string& limit_option) {
  if (width * height > max_pixels) {
    return path + ": " + std::to_string(width) + "x" + std::to_string(height) + " pixels, more than the limit of " +
           std::to_string(max_pixels) + (limit_option.empty() ? "" : " (" + limit_option + ")");
  }
  if (double(width) * double(height) * double(channels) > kMaxImageSamples) {
    return path + ": " + std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels) +
           " samples, more than the limit of 2^28";
  }
  return "";
}

// A library's message as one line ("unknown error" when empty).
inline std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::replace(text.begin(), text.end(), '\n', ';');
  return text.empty() ? "unknown error" : text;
}

// What both image readers check before a format library sees the file: a
// regular file (a FIFO or a link to /dev/zero would hang them), and the
// headers OpenEXR and libpng trust (octree/image_header.h).
// @throw ImageError "<path>: ..." one line.
inline void screen_image_file(const std::string& path) {
  try {
    files::require_regular_file(path, "an image");
  } catch (const files::FileError& e) {
    throw ImageError(e.what());
  }
  for (const std::string& why : {octree::check_exr_header(path, kMaxImageSamples), octree::check_png_chunks(path)}) {
    if (!why.empty()) throw ImageError(path + ": cannot read: " + why);
  }
}

}  // namespace svo::render::codec
