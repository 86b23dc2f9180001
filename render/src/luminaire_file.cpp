// The .lfl light-field file (docs/luminaire.md, "The .lfl file"): its
// writer, its parser (safe for untrusted input) and the checks of a light
// field in memory (luminaire.h). Images are stored as the paper stores
// coloured ones (Lu et al. 2015, section 5): per image, the luminance C_m,
// then the chromaticity c_m = C_m / (R + G + B) as (r, g).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "svo/octree/files.h"
#include "svo/render/luminaire.h"

namespace svo::render {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'S', 'V', 'O', 'L', 'F', 'L', '\0', '\0'};
// The fixed part of the header (through the source's length); the source's
// bytes follow it, then the images.
constexpr size_t kFixedHeader = 104;
constexpr size_t kUnitsBytes = 16;
constexpr size_t kMaxSource = 255;
constexpr size_t kChecksumBytes = 8;
// Per texel: f32 luminance, then f32 r and g chromaticities.
constexpr uint64_t kTexelBytes = 12;
// Rec. 709 luminance weights (the same as light_field_flux's).
constexpr double kWr = 0.2126, kWg = 0.7152, kWb = 0.0722;
// How far r + g may exceed 1 (float rounding of r / sum and g / sum).
constexpr double kChromaSlack = 1e-5;
// The largest file the limits allow.
constexpr uint64_t kMaxFileBytes = kFixedHeader + kMaxSource + LightField::kMaxTexels * kTexelBytes + kChecksumBytes;

[[noreturn]] void fail(const std::string& name, const std::string& why) {
  throw std::runtime_error("luminaire: " + name + ": " + why);
}

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// --- little-endian bytes -----------------------------------------------

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int b = 0; b < 4; ++b) out.push_back(uint8_t(v >> (8 * b)));
}
void put_f32(std::vector<uint8_t>& out, float v) { put_u32(out, std::bit_cast<uint32_t>(v)); }
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  for (int b = 0; b < 8; ++b) out.push_back(uint8_t(v >> (8 * b)));
}
uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
float get_f32(const uint8_t* p) { return std::bit_cast<float>(get_u32(p)); }
uint64_t get_u64(const uint8_t* p) { return uint64_t(get_u32(p)) | uint64_t(get_u32(p + 4)) << 32; }

// --- the checks shared by the parser and validate_light_field ----------

// The counts: image sides, grid, texels over all images.
void check_counts(const std::string& name, uint32_t width, uint32_t height, uint32_t grid_w, uint32_t grid_h) {
  const uint32_t side = LightField::kMaxImageSide, grid = LightField::kMaxGridSide;
  if (width < 1 || width > side || height < 1 || height > side) {
    fail(name, "image size " + std::to_string(width) + " x " + std::to_string(height) + " is outside 1 to " +
                   std::to_string(side) + " per side");
  }
  if (grid_w < 1 || grid_w > grid || grid_h < 1 || grid_h > grid) {
    fail(name, "basis grid " + std::to_string(grid_w) + " x " + std::to_string(grid_h) + " is outside 1 to " +
                   std::to_string(grid) + " per side");
  }
  const uint64_t texels = uint64_t(width) * height * grid_w * grid_h;
  if (texels > LightField::kMaxTexels) {
    fail(name, std::to_string(grid_w * grid_h) + " images of " + std::to_string(width) + " x " +
                   std::to_string(height) + " are " + std::to_string(texels) + " texels, more than the limit of " +
                   std::to_string(LightField::kMaxTexels));
  }
}

void check_positive(const std::string& name, const char* what, float v) {
  if (!(v > 0.0f) || !std::isfinite(v)) fail(name, std::string(what) + " " + number(v) + " is not finite and > 0");
}

void check_finite(const std::string& name, const char* what, const glm::vec3& v) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(v[k])) fail(name, std::string(what) + " is not finite (" + number(v[k]) + ")");
  }
}

// Every scalar of the header but the counts.
void check_header_values(const std::string& name, const LightField& f) {
  check_positive(name, "delta", f.delta);
  check_positive(name, "extent x", f.extent.x);
  check_positive(name, "extent y", f.extent.y);
  check_positive(name, "spacing", f.spacing);
  check_positive(name, "metres per unit", f.metres_per_unit);
  if (f.basis != LuminaireBasis::BSpline && f.basis != LuminaireBasis::Quadratic) {
    fail(name, "unknown basis " + std::to_string(uint32_t(f.basis)) + " (expected 0 bspline or 1 quadratic)");
  }
  check_finite(name, "pose at", f.pose.at);
  check_finite(name, "pose aim", f.pose.aim);
  if (!std::isfinite(f.pose.size)) fail(name, "pose size is not finite (" + number(f.pose.size) + ")");
  // The bytes first: the length's message quotes the units (a newline in
  // them broke its one line; found by the luminaire fuzz target).
  for (char c : f.units) {
    if (c < 0x20 || c > 0x7e) fail(name, "units hold byte " + std::to_string(uint8_t(c)) + ", not printable ASCII");
  }
  if (f.units.empty() || f.units.size() >= kUnitsBytes) {
    fail(name, "units '" + (f.units.size() < 64 ? f.units : f.units.substr(0, 64)) + "' must be 1 to " +
                   std::to_string(kUnitsBytes - 1) + " characters");
  }
  if (f.source.size() > kMaxSource) {
    fail(name, "source is " + std::to_string(f.source.size()) + " bytes, more than " + std::to_string(kMaxSource));
  }
  for (char c : f.source) {
    if (uint8_t(c) < 0x20 || c == 0x7f) {
      fail(name, "source holds control byte " + std::to_string(uint8_t(c)) + " (it must be one line of text)");
    }
  }
}

std::string texel_name(const LightField& f, uint32_t m, size_t t) {
  return "image " + std::to_string(m) + " texel (" + std::to_string(t % f.width) + ", " + std::to_string(t / f.width) +
         ")";
}

// The name of a light field in memory, for messages: its source when that is
// a short line of text.
std::string field_name(const LightField& f) {
  if (f.source.empty() || f.source.size() > 80) return "light field";
  for (char c : f.source) {
    if (uint8_t(c) < 0x20 || c == 0x7f) return "light field";
  }
  return f.source;
}

void validate(const LightField& f, const std::string& name) {
  check_counts(name, f.width, f.height, f.grid_w, f.grid_h);
  check_header_values(name, f);
  if (f.images.size() != f.image_count()) {
    fail(name, std::to_string(f.images.size()) + " images, expected " + std::to_string(f.image_count()) + " (" +
                   std::to_string(f.grid_w) + " x " + std::to_string(f.grid_h) + ")");
  }
  const size_t texels = size_t(f.width) * f.height;
  static const char* kChannel[3] = {"R", "G", "B"};
  for (uint32_t m = 0; m < f.image_count(); ++m) {
    const std::vector<float>& image = f.images[m];
    if (image.size() != 3 * texels) {
      fail(name, "image " + std::to_string(m) + " holds " + std::to_string(image.size()) + " values, expected " +
                     std::to_string(3 * texels) + " (3 x " + std::to_string(f.width) + " x " +
                     std::to_string(f.height) + ")");
    }
    for (size_t i = 0; i < image.size(); ++i) {
      if (!(image[i] >= 0.0f) || !std::isfinite(image[i])) {
        fail(name, texel_name(f, m, i / 3) + " " + kChannel[i % 3] + " is " + number(image[i]) +
                       ", expected finite and >= 0");
      }
    }
  }
}

// --- the layout --------------------------------------------------------

// The header's fields, read from the first kFixedHeader bytes and the
// source, with the counts checked.
struct Header {
  LightField field;  // no images yet
  uint32_t header_bytes = 0;
  uint64_t file_bytes = 0;  // what the header implies
};

// Reads and checks the header from `data` (at least min(size, kFixedHeader
// + kMaxSource) bytes of a file of `file_bytes`): magic, version, counts and
// the file's size. The values are checked later (after the checksum).
Header read_header(const uint8_t* data, size_t available, uint64_t file_bytes, const std::string& name) {
  if (file_bytes >= sizeof kMagic && std::memcmp(data, kMagic, sizeof kMagic) != 0) {
    fail(name, "not a light-field file (bad magic; expected \"SVOLFL\" and two NUL bytes)");
  }
  if (file_bytes < kFixedHeader + kChecksumBytes) {
    fail(name, "truncated: " + std::to_string(file_bytes) + " bytes, shorter than the " + std::to_string(kFixedHeader) +
                   "-byte header and the checksum");
  }
  const uint32_t version = get_u32(data + 8);
  if (version != LightField::kVersion) {
    fail(name, "unsupported version " + std::to_string(version) + " (this build reads version " +
                   std::to_string(LightField::kVersion) + ")");
  }
  Header h;
  LightField& f = h.field;
  h.header_bytes = get_u32(data + 12);
  f.delta = get_f32(data + 16);
  f.extent = {get_f32(data + 20), get_f32(data + 24)};
  f.width = get_u32(data + 28);
  f.height = get_u32(data + 32);
  f.grid_w = get_u32(data + 36);
  f.grid_h = get_u32(data + 40);
  f.spacing = get_f32(data + 44);
  f.basis = LuminaireBasis(get_u32(data + 48));
  f.metres_per_unit = get_f32(data + 52);
  f.pose.at = {get_f32(data + 56), get_f32(data + 60), get_f32(data + 64)};
  f.pose.aim = {get_f32(data + 68), get_f32(data + 72), get_f32(data + 76)};
  f.pose.size = get_f32(data + 80);
  const uint8_t* units = data + 84;
  const uint32_t source_bytes = get_u32(data + 100);
  check_counts(name, f.width, f.height, f.grid_w, f.grid_h);
  if (source_bytes > kMaxSource) {
    fail(name, "source of " + std::to_string(source_bytes) + " bytes, more than " + std::to_string(kMaxSource));
  }
  if (h.header_bytes != kFixedHeader + source_bytes) {
    fail(name, "header of " + std::to_string(h.header_bytes) + " bytes, expected " +
                   std::to_string(kFixedHeader + source_bytes) + " (" + std::to_string(kFixedHeader) + " and a " +
                   std::to_string(source_bytes) + "-byte source)");
  }
  const uint64_t texels = uint64_t(f.width) * f.height * f.image_count();
  h.file_bytes = h.header_bytes + texels * kTexelBytes + kChecksumBytes;
  if (file_bytes != h.file_bytes) {
    fail(name, std::string(file_bytes < h.file_bytes ? "truncated: " : "") + std::to_string(file_bytes) +
                   " bytes, the header implies " + std::to_string(h.file_bytes) + " (" +
                   std::to_string(f.image_count()) + " images of " + std::to_string(f.width) + " x " +
                   std::to_string(f.height) + ")");
  }
  if (available < h.header_bytes) fail(name, "truncated header");  // not reached: the size was checked
  // The units: printable ASCII, then NUL bytes to the end of the field.
  size_t n = 0;
  while (n < kUnitsBytes && units[n] != 0) ++n;
  for (size_t i = n; i < kUnitsBytes; ++i) {
    if (units[i] != 0) fail(name, "units field holds byte " + std::to_string(units[i]) + " after its NUL");
  }
  f.units.assign(reinterpret_cast<const char*>(units), n);
  f.source.assign(reinterpret_cast<const char*>(data + kFixedHeader), source_bytes);
  return h;
}

// Luminance and chromaticity of one RGB texel (docs/luminaire.md).
void encode_texel(const float* rgb, float& y, float& cr, float& cg) {
  const double r = rgb[0], g = rgb[1], b = rgb[2];
  y = float(kWr * r + kWg * g + kWb * b);
  const double sum = r + g + b;
  if (y > 0.0f && sum > 0.0) {
    cr = float(r / sum);
    cg = float(g / sum);
  } else {
    y = 0.0f;
    cr = cg = float(1.0 / 3.0);
  }
}

// The bytes of a validated field.
std::vector<uint8_t> encode(const LightField& field) {
  const size_t texels = size_t(field.width) * field.height;
  std::vector<uint8_t> out;
  out.reserve(kFixedHeader + field.source.size() + field.image_count() * texels * kTexelBytes + kChecksumBytes);
  for (char c : kMagic) out.push_back(uint8_t(c));
  put_u32(out, LightField::kVersion);
  put_u32(out, uint32_t(kFixedHeader + field.source.size()));
  put_f32(out, field.delta);
  put_f32(out, field.extent.x);
  put_f32(out, field.extent.y);
  put_u32(out, field.width);
  put_u32(out, field.height);
  put_u32(out, field.grid_w);
  put_u32(out, field.grid_h);
  put_f32(out, field.spacing);
  put_u32(out, uint32_t(field.basis));
  put_f32(out, field.metres_per_unit);
  for (int k = 0; k < 3; ++k) put_f32(out, field.pose.at[k]);
  for (int k = 0; k < 3; ++k) put_f32(out, field.pose.aim[k]);
  put_f32(out, field.pose.size);
  char units[kUnitsBytes] = {};
  std::memcpy(units, field.units.data(), field.units.size());
  for (char c : units) out.push_back(uint8_t(c));
  put_u32(out, uint32_t(field.source.size()));
  out.insert(out.end(), field.source.begin(), field.source.end());
  std::vector<float> y(texels), chroma(2 * texels);
  for (const std::vector<float>& image : field.images) {
    for (size_t t = 0; t < texels; ++t) encode_texel(&image[3 * t], y[t], chroma[2 * t], chroma[2 * t + 1]);
    for (float v : y) put_f32(out, v);
    for (float v : chroma) put_f32(out, v);
  }
  put_u64(out, XXH64(out.data(), out.size(), 0));
  return out;
}

}  // namespace

void validate_light_field(const LightField& field) { validate(field, field_name(field)); }

std::vector<uint8_t> encode_light_field(const LightField& field) {
  validate(field, field_name(field));
  return encode(field);
}

LightField parse_light_field(const uint8_t* data, size_t size, const std::string& name) {
  if (size < sizeof kMagic) {
    fail(name, "truncated: " + std::to_string(size) + " bytes, shorter than the " + std::to_string(kFixedHeader) +
                   "-byte header and the checksum");
  }
  Header h = read_header(data, size, size, name);
  const uint64_t stored = get_u64(data + size - kChecksumBytes);
  const uint64_t computed = XXH64(data, size - kChecksumBytes, 0);
  if (stored != computed) {
    char text[96];
    std::snprintf(text, sizeof text, "checksum mismatch (stored %016llx, computed %016llx): the file is damaged",
                  static_cast<unsigned long long>(stored), static_cast<unsigned long long>(computed));
    fail(name, text);
  }
  LightField f = std::move(h.field);
  check_header_values(name, f);
  // The images: the size was checked, so every read below is in bounds.
  const size_t texels = size_t(f.width) * f.height;
  const uint8_t* at = data + h.header_bytes;
  f.images.resize(f.image_count());
  for (uint32_t m = 0; m < f.image_count(); ++m) {
    const uint8_t* lum = at;
    const uint8_t* chroma = at + 4 * texels;
    std::vector<float>& image = f.images[m];
    image.resize(3 * texels);
    for (size_t t = 0; t < texels; ++t) {
      const float y = get_f32(lum + 4 * t);
      const float cr = get_f32(chroma + 8 * t), cg = get_f32(chroma + 8 * t + 4);
      if (!(y >= 0.0f) || !std::isfinite(y)) {
        fail(name, texel_name(f, m, t) + ": luminance " + number(y) + ", expected finite and >= 0");
      }
      if (!(cr >= 0.0f && cr <= 1.0f) || !(cg >= 0.0f && cg <= 1.0f) || double(cr) + cg > 1.0 + kChromaSlack) {
        fail(name, texel_name(f, m, t) + ": chromaticity (" + number(cr) + ", " + number(cg) +
                       "), expected r, g in [0, 1] and r + g <= 1");
      }
      float* rgb = &image[3 * t];
      if (y == 0.0f) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        continue;
      }
      // sum = Y / (wr r + wg g + wb b), the denominator >= wb.
      const double cb = std::max(0.0, 1.0 - double(cr) - double(cg));
      const double sum = double(y) / (kWr * cr + kWg * cg + kWb * cb);
      const double c[3] = {cr * sum, cg * sum, cb * sum};
      for (int k = 0; k < 3; ++k) {
        // Rounding may carry a value a hair past the float range: clamp
        // that; a texel that decodes far past it is refused.
        constexpr double kMax = std::numeric_limits<float>::max();
        if (c[k] > kMax * (1.0 + 1e-4)) {
          fail(name, texel_name(f, m, t) + ": luminance " + number(y) + " at chromaticity (" + number(cr) + ", " +
                         number(cg) + ") decodes past the float range");
        }
        rgb[k] = float(std::min(c[k], kMax));
      }
    }
    at += kTexelBytes * texels;
  }
  return f;
}

void save_light_field(const LightField& field, const fs::path& path) {
  validate(field, path.string());
  const std::vector<uint8_t> bytes = encode(field);
  try {
    files::write_file(path.string(), bytes.data(), bytes.size());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("luminaire: ") + e.what());
  }
}

LightField load_light_field(const fs::path& path) {
  const std::string name = path.string();
  // The kind of file first, following links, before anything opens it (a
  // FIFO would block the open, /dev/zero never ends).
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) fail(name, "no such file");
  if (ec) fail(name, "cannot inspect: " + ec.message());
  if (status.type() != fs::file_type::regular)
    fail(name, "is " + files::file_kind(status.type()) + ", expected a .lfl file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) fail(name, std::string("cannot open: ") + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  // And again on what was opened (the path may have changed in between).
  struct stat st {};
  if (::fstat(fd, &st) != 0) fail(name, std::string("cannot inspect: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(name, "is " + files::file_kind_of_mode(st.st_mode) + ", expected a .lfl file");
  const uint64_t file_bytes = uint64_t(st.st_size);
  if (file_bytes > kMaxFileBytes) {
    fail(name, std::to_string(file_bytes) + " bytes, more than the largest light field (" +
                   std::to_string(kMaxFileBytes) + ")");
  }
  std::vector<uint8_t> bytes;
  auto read_to = [&](size_t n) {
    const size_t from = bytes.size();
    bytes.resize(n);
    for (size_t done = from; done < n;) {
      const ssize_t r = ::read(fd, bytes.data() + done, n - done);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) fail(name, std::string("cannot read: ") + std::strerror(errno));
      if (r == 0)
        fail(name,
             "ends at byte " + std::to_string(done) + ", expected " + std::to_string(n) + " (it changed while read)");
      done += size_t(r);
    }
  };
  // The header first: the counts and the size are checked before the
  // images' bytes are read or allocated.
  read_to(size_t(std::min<uint64_t>(file_bytes, kFixedHeader + kMaxSource)));
  if (file_bytes < sizeof kMagic) {
    fail(name, "truncated: " + std::to_string(file_bytes) + " bytes, shorter than the " + std::to_string(kFixedHeader) +
                   "-byte header and the checksum");
  }
  read_header(bytes.data(), bytes.size(), file_bytes, name);
  read_to(size_t(file_bytes));
  return parse_light_field(bytes.data(), bytes.size(), name);
}

}  // namespace svo::render
