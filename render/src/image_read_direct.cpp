// read_image without OpenImageIO (library svo_image_read_direct, which
// svo-render links; see image_io.h): OpenEXR through the OpenEXR library,
// PNG through libpng's simplified API. Other formats are refused with a
// line that names `svo`, which reads them.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <png.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "image_codec.h"
#include "svo/render/image_io.h"

namespace svo::render {

namespace {

Image read_exr(const std::string& path, uint64_t max_pixels, const std::string& limit_option) {
  Image image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
    std::vector<std::string> names;
    for (auto c = file.header().channels().begin(); c != file.header().channels().end(); ++c) {
      names.push_back(c.name());
    }
    if (width <= 0 || height <= 0 || names.empty()) throw ImageError(path + ": not a 2D image");
    const std::string too_large =
        codec::check_image_size(path, uint64_t(width), uint64_t(height), names.size(), max_pixels, limit_option);
    if (!too_large.empty()) throw ImageError(too_large);
    // R, G, B, A first, as OpenImageIO orders them; the rest as listed.
    auto rank = [](const std::string& name) { return name.size() == 1 ? std::string("RGBA").find(name[0]) : 4; };
    std::stable_sort(names.begin(), names.end(), [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
    image.width = int(width);
    image.height = int(height);
    image.channels = names;
    const size_t n = names.size();
    image.pixels.resize(size_t(width) * size_t(height) * n);
    // The slices' origin is the data window's corner: OpenEXR indexes by
    // absolute pixel coordinates.
    char* base = reinterpret_cast<char*>(image.pixels.data()) -
                 (int64_t(window.min.x) + int64_t(window.min.y) * width) * int64_t(n * sizeof(float));
    Imf::FrameBuffer frame;
    for (size_t c = 0; c < n; ++c) {
      frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float),
                                        size_t(width) * n * sizeof(float)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const ImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageError(path + ": cannot read: " + codec::one_line(e.what()));
  }
  return image;
}

Image read_png(const std::string& path, uint64_t max_pixels, const std::string& limit_option) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    throw ImageError(path + ": cannot read: " + png.message);
  }
  const bool alpha = png.format & PNG_FORMAT_FLAG_ALPHA;
  const size_t n = alpha ? 4 : 3;
  const std::string too_large = codec::check_image_size(path, png.width, png.height, n, max_pixels, limit_option);
  if (!too_large.empty()) {
    png_image_free(&png);
    throw ImageError(too_large);
  }
  png.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;  // 8-bit sRGB
  std::vector<uint8_t> bytes(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, bytes.data(), 0, nullptr)) {
    throw ImageError(path + ": cannot read: " + png.message);
  }
  Image image;
  image.width = int(png.width);
  image.height = int(png.height);
  image.channels = alpha ? std::vector<std::string>{"R", "G", "B", "A"} : std::vector<std::string>{"R", "G", "B"};
  image.pixels.resize(bytes.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    const float v = float(bytes[i]) * (1.0f / 255.0f);  // as OpenImageIO converts
    image.pixels[i] = i % n == 3 ? v : srgb_to_linear(v);
  }
  return image;
}

}  // namespace

Image read_image(const std::string& path, uint64_t max_pixels, const std::string& limit_option) {
  codec::screen_image_file(path);
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".exr") return read_exr(path, max_pixels, limit_option);
  if (ext == ".png") return read_png(path, max_pixels, limit_option);
  throw ImageError(path + ": svo-render reads OpenEXR (.exr) and PNG (.png) images only; svo reads '" + ext +
                   "' through OpenImageIO");
}

}  // namespace svo::render
