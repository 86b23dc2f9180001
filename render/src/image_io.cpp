#include "svo/render/image_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "image_codec.h"
#include "svo/octree/files.h"

namespace svo::render {

namespace {

namespace fs = std::filesystem;

std::string extension_of(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Encoded bytes (PNG, JPEG) to `path` through an OutputFile: every write
// checked, fsync, rename.
void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  try {
    files::OutputFile file(path);
    file.write_at(bytes.data(), bytes.size(), 0);
    file.commit();
  } catch (const files::FileError& e) {
    throw ImageError(e.what());
  }
}

// Channel-interleaved floats to `path` as OpenEXR through an OutputFile.
void write_float_exr(const std::string& path, uint32_t width, uint32_t height, const std::vector<std::string>& names,
                     const float* data) {
  try {
    files::OutputFile file(path);
    codec::write_exr(file, path, width, height, names, data);
    file.commit();
  } catch (const files::FileError& e) {
    throw ImageError(e.what());
  }
}

void check_size(const std::string& path, const Frame& frame, size_t count, const char* what) {
  if (frame.width == 0 || frame.height == 0 || count != size_t(frame.width) * frame.height) {
    throw ImageError(path + ": cannot write: the frame's " + what + " holds " + std::to_string(count) +
                     " pixels, not " + std::to_string(frame.width) + " x " + std::to_string(frame.height));
  }
}

}  // namespace

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
    const std::string film_text = film_description(film);
    const std::string description = film_text.empty() ? "" : codec::kFilmPrefix + film_text;
    std::vector<uint8_t> encoded;
    const std::string why = format == ImageFormat::Png
                                ? codec::encode_png(frame.width, frame.height, bytes.data(), description, encoded)
                                : codec::encode_jpeg(frame.width, frame.height, bytes.data(), description, 95, encoded);
    if (!why.empty()) throw ImageError(path + ": cannot write: " + why);
    write_bytes(path, encoded);
  } else {
    write_float_exr(path, frame.width, frame.height, {"R", "G", "B", "A"}, &frame.colour[0].r);
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

}  // namespace

void write_gbuffer(const std::string& path, const Frame& frame) {
  if (image_format(path) != ImageFormat::Exr) {
    throw ImageError(path + ": the G-buffer is written as OpenEXR only (use .exr)");
  }
  check_size(path, frame, frame.gbuffer.size(), "G-buffer");
  const size_t pixels = size_t(frame.width) * frame.height, n = kGBufferChannels.size();
  std::vector<float> data(pixels * n);
  for (size_t i = 0; i < pixels; ++i) gbuffer_channels(frame.gbuffer[i], data.data() + i * n);
  write_float_exr(path, frame.width, frame.height, {kGBufferChannels.begin(), kGBufferChannels.end()}, data.data());
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
  write_float_exr(path, w, h, names, data.data());
}

void write_steps(const std::string& path, const Frame& frame) {
  if (image_format(path) != ImageFormat::Exr) {
    throw ImageError(path + ": the steps image is written as OpenEXR only (use .exr)");
  }
  check_size(path, frame, frame.steps.size(), "steps image");
  const std::vector<float> data(frame.steps.begin(), frame.steps.end());
  write_float_exr(path, frame.width, frame.height, {"steps"}, data.data());
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

}  // namespace svo::render
