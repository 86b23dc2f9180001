#include "svo/render/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "svo/octree/files.h"
#include "svo/octree/image_header.h"

namespace svo::render {

namespace {

namespace fs = std::filesystem;

// OpenImageIO's messages may span lines: one line for the user.
std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  std::replace(text.begin(), text.end(), '\n', ';');
  return text.empty() ? "unknown OpenImageIO error" : text;
}

std::string extension_of(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// OpenImageIO writes through this into an OutputFile: every write checked
// (its PNG writer ignores failed writes: a full disk left a truncated image
// that was then renamed into place) and the first failure kept.
class OutputProxy final : public OIIO::Filesystem::IOProxy {
 public:
  explicit OutputProxy(files::OutputFile& file) : IOProxy(file.temporary(), Write), file_(file) {}
  const char* proxytype() const override { return "svo::files::OutputFile"; }
  void close() override { m_mode = Closed; }
  size_t write(const void* data, size_t size) override {
    size_t n = pwrite(data, size, m_pos);
    m_pos += int64_t(n);
    return n;
  }
  size_t pwrite(const void* data, size_t size, int64_t offset) override {
    if (!failure.empty() || offset < 0) return 0;
    try {
      file_.write_at(data, size, uint64_t(offset));
    } catch (const files::FileError& e) {
      failure = e.what();
      return 0;
    }
    end_ = std::max(end_, uint64_t(offset) + size);
    return size;
  }
  size_t size() const override { return size_t(end_); }
  std::string failure;  // the first failed write's message

 private:
  files::OutputFile& file_;
  uint64_t end_ = 0;
};

// Writes `spec` and `data` (of `type`) to `path` in the format `format_name`
// ("png", "openexr") through an OutputFile.
void write_file(const std::string& path, const char* format_name, const OIIO::ImageSpec& spec, OIIO::TypeDesc type,
                const void* data) {
  try {
    files::OutputFile file(path);
    OutputProxy proxy(file);
    auto out = OIIO::ImageOutput::create(format_name);
    if (!out) throw ImageError(path + ": cannot write: " + one_line(OIIO::geterror()));
    if (!out->supports("ioproxy") || !out->set_ioproxy(&proxy)) {
      throw ImageError(path + ": cannot write: OpenImageIO's " + format_name + " writer takes no I/O proxy");
    }
    bool ok = out->open(file.temporary(), spec) && out->write_image(type, data);
    std::string error = ok ? "" : one_line(out->geterror());
    if (!out->close() && ok) ok = false, error = one_line(out->geterror());
    if (!proxy.failure.empty()) throw ImageError(proxy.failure);
    if (!ok) throw ImageError(path + ": cannot write: " + error);
    file.commit();
  } catch (const ImageError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw ImageError(e.what());
  }
}

// The ImageDescription of an 8-bit file written with a Film, before film_description.
const std::string kFilmPrefix = "svo film: ";

void check_size(const std::string& path, const Frame& frame, size_t count, const char* what) {
  if (frame.width == 0 || frame.height == 0 || count != size_t(frame.width) * frame.height) {
    throw ImageError(path + ": cannot write: the frame's " + what + " holds " + std::to_string(count) +
                     " pixels, not " + std::to_string(frame.width) + " x " + std::to_string(frame.height));
  }
}

}  // namespace

float linear_to_srgb(float x) {
  if (!(x > 0)) return 0;
  if (x >= 1) return 1;
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgb_to_linear(float s) {
  if (!(s > 0)) return 0;
  if (s >= 1) return 1;
  return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
}

glm::vec3 parse_colour(const std::string& text) {
  const std::invalid_argument bad("'" + text + "': expected R,G,B (linear, each in [0, 1]) or #rrggbb (sRGB hex)");
  glm::vec3 colour(0.0f);
  if (!text.empty() && text[0] == '#') {
    if (text.size() != 7) throw bad;
    for (int c = 0; c < 3; ++c) {
      int value = 0;
      for (int k = 0; k < 2; ++k) {
        const char h = char(std::tolower(static_cast<unsigned char>(text[size_t(1 + 2 * c + k)])));
        const int digit = h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10 : -1;
        if (digit < 0) throw bad;
        value = 16 * value + digit;
      }
      colour[c] = srgb_to_linear(float(value) / 255.0f);
    }
    return colour;
  }
  size_t start = 0;
  for (int c = 0; c < 3; ++c) {
    const size_t end = c < 2 ? text.find(',', start) : text.size();
    if (end == std::string::npos) throw bad;
    const std::string part = text.substr(start, end - start);
    char* stop = nullptr;
    const float v = std::strtof(part.c_str(), &stop);
    if (part.empty() || std::isspace(static_cast<unsigned char>(part[0])) || stop != part.c_str() + part.size() ||
        !(v >= 0.0f && v <= 1.0f)) {
      throw bad;
    }
    colour[c] = v;
    start = end + 1;
  }
  return colour;
}

ImageFormat image_format(const std::string& path) {
  std::string ext = extension_of(path);
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
  if (ext == ".exr") return ImageFormat::Exr;
  throw ImageError(path + ": unsupported image extension '" + ext + "' (use .png, .jpg or .exr)");
}

bool is_8bit(ImageFormat format) { return format == ImageFormat::Png || format == ImageFormat::Jpeg; }

std::optional<Tonemap> parse_tonemap(const std::string& name) {
  if (name == "none") return Tonemap::None;
  if (name == "filmic") return Tonemap::Filmic;
  return std::nullopt;
}

const char* tonemap_name(Tonemap tonemap) { return tonemap == Tonemap::Filmic ? "filmic" : "none"; }

float filmic(float x) {
  if (!(x > 0)) return 0;
  constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;  // Narkowicz 2015
  if (x >= 8) return 1;  // past the curve's crossing of 1 (about 7.24); avoids inf / inf
  return std::min(1.0f, x * (a * x + b) / (x * (c * x + d) + e));
}

float apply_film(float linear, const Film& film) {
  if (!(linear > 0)) return 0;  // NaN and negative values
  const float v = film.exposure_ev == 0 ? linear : linear * std::exp2(film.exposure_ev);
  return film.tonemap == Tonemap::Filmic ? filmic(v) : std::min(v, 1.0f);
}

std::string film_description(const Film& film) {
  if (film == Film{}) return "";
  char ev[32];
  std::snprintf(ev, sizeof ev, "%+g", double(film.exposure_ev));
  return std::string("exposure ") + ev + " EV, tonemap " + tonemap_name(film.tonemap);
}

void check_writable_output(const std::string& path) {
  try {
    files::resolve_output(path);
  } catch (const files::FileError& e) {
    throw ImageError(e.what());
  }
}

void write_colour(const std::string& path, const Frame& frame, const Film& film) {
  ImageFormat format = image_format(path);
  check_size(path, frame, frame.colour.size(), "colour");
  const size_t pixels = size_t(frame.width) * frame.height;
  if (is_8bit(format)) {
    std::vector<uint8_t> bytes(pixels * 3);
    for (size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) {
        const float v = apply_film(frame.colour[i][c], film);
        bytes[3 * i + size_t(c)] = uint8_t(std::lround(linear_to_srgb(v) * 255.0f));
      }
    }
    OIIO::ImageSpec spec(int(frame.width), int(frame.height), 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    spec.attribute("Software", "svo");
    const std::string description = film_description(film);
    if (!description.empty()) spec.attribute("ImageDescription", kFilmPrefix + description);
    if (format == ImageFormat::Jpeg) {
      spec.attribute("Compression", "jpeg:95");
      spec.attribute("jpeg:subsampling", "4:4:4");  // no chroma blur across a render's colour edges
    }
    write_file(path, format == ImageFormat::Png ? "png" : "jpeg", spec, OIIO::TypeDesc::UINT8, bytes.data());
  } else {
    OIIO::ImageSpec spec(int(frame.width), int(frame.height), 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A"};
    spec.alpha_channel = 3;
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("compression", "zip");
    spec.attribute("Software", "svo");
    write_file(path, "openexr", spec, OIIO::TypeDesc::FLOAT, frame.colour.data());
  }
}

namespace {

// A G-buffer texel as the channels of kGBufferChannels.
void gbuffer_channels(const GBufferTexel& t, float* out) {
  const float values[] = {
      t.depth,       t.position.x, t.position.y, t.position.z,      t.normal.x,         t.normal.y,
      t.normal.z,    t.tangent.x,  t.tangent.y,  t.tangent.z,       t.slope_cov.x,      t.slope_cov.y,
      t.slope_cov.z, t.sigma_rho2, t.abar.x,     t.abar.y,          t.abar.z,           t.a_s.x,
      t.a_s.y,       t.a_s.z,      t.coverage,   float(t.material), float(t.material2), t.material_mix};
  static_assert(std::size(values) == kGBufferChannels.size());
  std::copy(std::begin(values), std::end(values), out);
}

void write_float_exr(const std::string& path, uint32_t width, uint32_t height, const std::vector<std::string>& names,
                     const std::vector<float>& data) {
  OIIO::ImageSpec spec(int(width), int(height), int(names.size()), OIIO::TypeDesc::FLOAT);
  spec.channelnames = names;
  spec.alpha_channel = -1;
  spec.attribute("compression", "zip");
  spec.attribute("Software", "svo");
  write_file(path, "openexr", spec, OIIO::TypeDesc::FLOAT, data.data());
}

}  // namespace

void write_gbuffer(const std::string& path, const Frame& frame) {
  if (image_format(path) != ImageFormat::Exr) {
    throw ImageError(path + ": the G-buffer is written as OpenEXR only (use .exr)");
  }
  check_size(path, frame, frame.gbuffer.size(), "G-buffer");
  const size_t pixels = size_t(frame.width) * frame.height, n = kGBufferChannels.size();
  std::vector<float> data(pixels * n);
  for (size_t i = 0; i < pixels; ++i) gbuffer_channels(frame.gbuffer[i], data.data() + i * n);
  write_float_exr(path, frame.width, frame.height, {kGBufferChannels.begin(), kGBufferChannels.end()}, data);
}

void write_aov(const std::string& path, Renderer& renderer, const std::string& name) {
  if (image_format(path) != ImageFormat::Exr)
    throw ImageError(path + ": images are written as OpenEXR only (use .exr)");
  FrameImages& images = renderer.images();
  const ImageDesc desc = images.desc(name);
  const uint32_t w = desc.width(images.width()), h = desc.height(images.height());
  const size_t texels = size_t(w) * h;
  ImageMemory& memory = images.read(desc);
  std::vector<std::string> names;
  std::vector<float> data;
  switch (desc.format) {
    case TexelFormat::Rgba32f: {
      names = {"R", "G", "B", "A"};
      const auto* v = static_cast<const float*>(memory.data());
      data.assign(v, v + 4 * texels);
      break;
    }
    case TexelFormat::R32u: {
      names = {name};
      const auto* v = static_cast<const uint32_t*>(memory.data());
      data.assign(v, v + texels);
      break;
    }
    case TexelFormat::Rgba8: {
      names = {"R", "G", "B", "A"};
      const auto* v = static_cast<const uint32_t*>(memory.data());
      data.resize(4 * texels);
      for (size_t i = 0; i < texels; ++i) {
        for (int c = 0; c < 4; ++c) data[4 * i + size_t(c)] = float((v[i] >> (8 * c)) & 255u) / 255.0f;
      }
      break;
    }
    case TexelFormat::GBuffer: {
      names.assign(kGBufferChannels.begin(), kGBufferChannels.end());
      const size_t n = kGBufferChannels.size();
      data.resize(n * texels);
      const auto* v = static_cast<const glm::vec4*>(memory.data());
      for (size_t i = 0; i < texels; ++i) gbuffer_channels(unpack_gbuffer(v + i * kGBufferVec4s), data.data() + i * n);
      break;
    }
  }
  write_float_exr(path, w, h, names, data);
}

void write_steps(const std::string& path, const Frame& frame) {
  if (image_format(path) != ImageFormat::Exr) {
    throw ImageError(path + ": the steps image is written as OpenEXR only (use .exr)");
  }
  check_size(path, frame, frame.steps.size(), "steps image");
  std::vector<float> data(frame.steps.begin(), frame.steps.end());
  OIIO::ImageSpec spec(int(frame.width), int(frame.height), 1, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"steps"};
  spec.alpha_channel = -1;
  spec.attribute("compression", "zip");
  spec.attribute("Software", "svo");
  write_file(path, "openexr", spec, OIIO::TypeDesc::FLOAT, data.data());
}

int Image::channel(const std::string& name) const {
  auto it = std::find(channels.begin(), channels.end(), name);
  return it == channels.end() ? -1 : int(it - channels.begin());
}

Image frame_image(const Frame& frame) {
  Image im;
  im.width = int(frame.width);
  im.height = int(frame.height);
  im.channels = {"R", "G", "B", "A"};
  im.pixels.reserve(frame.colour.size() * 4);
  for (const auto& c : frame.colour) im.pixels.insert(im.pixels.end(), {c.r, c.g, c.b, c.a});
  return im;
}

Image read_image(const std::string& path, uint64_t max_pixels, const std::string& limit_option) {
  try {
    files::require_regular_file(path, "an image");
  } catch (const files::FileError& e) {
    throw ImageError(e.what());
  }
  // Checks in front of the format libraries, which trust their headers.
  for (const std::string& why : {octree::check_exr_header(path, kMaxImageSamples), octree::check_png_chunks(path)}) {
    if (!why.empty()) throw ImageError(path + ": cannot read: " + why);
  }
  // The reader of the file's extension only: OpenImageIO's open() would
  // otherwise try every format it knows on a file its extension's rejects.
  auto in = OIIO::ImageInput::create(path, false);
  if (!in) throw ImageError(path + ": cannot read: " + one_line(OIIO::geterror()));
  OIIO::ImageSpec spec;
  if (!in->open(path, spec)) throw ImageError(path + ": cannot read: " + one_line(in->geterror()));
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    throw ImageError(path + ": not a 2D image");
  }
  // From the header, before the allocation: a forged size is refused here.
  if (uint64_t(spec.width) * uint64_t(spec.height) > max_pixels) {
    throw ImageError(path + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                     " pixels, more than the limit of " + std::to_string(max_pixels) +
                     (limit_option.empty() ? "" : " (" + limit_option + ")"));
  }
  if (double(spec.width) * double(spec.height) * double(spec.nchannels) > kMaxImageSamples) {
    throw ImageError(path + ": " + std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" +
                     std::to_string(spec.nchannels) + " samples, more than the limit of 2^28");
  }
  Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.channels = spec.channelnames;
  image.channels.resize(size_t(spec.nchannels));  // one name per channel, whatever the file says
  image.pixels.resize(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    throw ImageError(path + ": cannot read: " + one_line(in->geterror()));
  }
  const bool integer = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  const std::string description = spec.get_string_attribute("ImageDescription");
  if (integer && description.rfind(kFilmPrefix, 0) == 0) image.film = description.substr(kFilmPrefix.size());
  if (integer && spec.get_string_attribute("oiio:ColorSpace") == "sRGB") {
    const size_t n = size_t(spec.nchannels);
    for (size_t i = 0; i < image.pixels.size(); ++i) {
      if (int(i % n) != spec.alpha_channel) image.pixels[i] = srgb_to_linear(image.pixels[i]);
    }
  }
  return image;
}

}  // namespace svo::render
