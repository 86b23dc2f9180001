// read_image through OpenImageIO: any format it reads (library
// svo_image_read_oiio, which svo_render links; see image_io.h).
#include <OpenImageIO/imageio.h>

#include <cctype>
#include <filesystem>

#include "image_codec.h"
#include "svo/render/image_io.h"

namespace svo::render {

Image read_image(const std::string& path, uint64_t max_pixels, const std::string& limit_option) {
  codec::screen_image_file(path);
  // The reader of the file's extension only, created from the extension
  // alone: given the file's name, OpenImageIO 2.4 asks every format it knows
  // whether the file is theirs when the extension's reader rejects it, and
  // the DICOM reader (dcmtk) then frees with the wrong operator (an
  // AddressSanitizer report on a mutated PNG seed, Fuzz.MutatedSeeds*).
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));  // "PNG" is not a format name
  auto in = extension.size() > 1 ? OIIO::ImageInput::create(extension.substr(1)) : nullptr;
  if (!in && extension.size() <= 1) throw ImageError(path + ": cannot read: no extension to tell its format");
  if (!in) throw ImageError(path + ": cannot read: " + codec::one_line(OIIO::geterror()));
  OIIO::ImageSpec spec;
  if (!in->open(path, spec)) throw ImageError(path + ": cannot read: " + codec::one_line(in->geterror()));
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    throw ImageError(path + ": not a 2D image");
  }
  // From the header, before the allocation: a forged size is refused here.
  const std::string too_large = codec::check_image_size(path, uint64_t(spec.width), uint64_t(spec.height),
                                                        uint64_t(spec.nchannels), max_pixels, limit_option);
  if (!too_large.empty()) throw ImageError(too_large);
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.channelnames;
  image.channels.resize(size_t(spec.nchannels));  // one name per channel, whatever the file says
  image.pixels.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  // A scanline file is read one row at a time: OpenImageIO 2.4's read_image
  // converts through a buffer of 256 rows whatever the image's height, so a
  // header of 1111111 x 4 pixels asked for 3.4 GB (a 105-byte .hdr found by
  // the environment fuzz target, tests/fuzz/regressions/environment/). A
  // tiled file's buffer is bounded by its tiles.
  const size_t row = size_t(spec.width) * size_t(spec.nchannels);
  bool read = true;
  if (spec.tile_width == 0) {
    for (int y = 0; y < spec.height && read; ++y)
      read = in->read_scanline(spec.y + y, spec.z, OIIO::TypeDesc::FLOAT, image.pixels.data() + size_t(y) * row);
  } else {
    read = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
  }
  if (!read) throw ImageError(path + ": cannot read: " + codec::one_line(in->geterror()));
  const bool integer = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  const std::string description = spec.get_string_attribute("ImageDescription");
  if (integer && description.rfind(codec::kFilmPrefix, 0) == 0)
    image.film = description.substr(codec::kFilmPrefix.size());
  if (integer && spec.get_string_attribute("oiio:ColorSpace") == "sRGB") {
    const size_t n = size_t(spec.nchannels);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      if (int(i % n) != spec.alpha_channel) image.pixels[i] = srgb_to_linear(image.pixels[i]);
    }
  }
  return image;
}

}  // namespace svo::render
