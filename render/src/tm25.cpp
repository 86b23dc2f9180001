// The import of IES TM-25-13 ray files into a light field (luminaire.h;
// the layout read and the binning: docs/luminaire_tm25.md).
//
// The layout is the one of the public TM-25 readers (JuliusMuschaweck/
// TM25RaySetTools, TM25Library/TM25_impl.h, whose field names carry the
// standard's section numbers; LarryBoxler/IESTM25RayFiles; holg/tm25ray,
// which checked it against real ams OSRAM files), not of the standard's
// text, which is not public: little-endian,
//   0    char[4]  "TM25"                       4.7.1.1
//   4    i32      version, 2013                4.7.1.2
//   8    i32      creation method              4.7.1.3
//   12   f32      total luminous flux (lm)     4.7.1.4
//   16   f32      total radiant flux (W)       4.7.1.5
//   20   u64      number of rays               4.7.1.6
//   28   char[28] creation date and time       4.7.1.7
//   56   i32      ray start position           4.7.1.8
//   60   i32      spectral data identifier 0-4 4.7.1.9
//   64   f32 x 3  single, minimum, maximum wavelength (nm) 4.7.1.10-12
//   76   i32      number of spectral tables    4.7.1.13
//   80   i32      number of additional ray items 4.7.1.14
//   84   i32      size of the additional text block in bytes 4.7.1.15
//   88   168 bytes reserved
//   256  i32 x 8  known-data flags: position, direction, radiant flux,
//                 wavelength, luminous flux, Stokes, tristimulus, spectrum index
//   288  9 x 4000 bytes: description strings, UTF-32LE (name first)
//   36288 spectral tables: i32 point count, then (f32 nm, f32 weight) pairs,
//                 the block padded with zeros to a multiple of 32 bytes
//   then  512 bytes (UTF-32LE) per additional ray item's name, the
//                 additional text block, and the rays: f32 each,
//   x y z kx ky kz [radiant flux] [wavelength] [luminous flux]
//   [S1 S2 S3 (+ polarisation ellipse x y z)] [tristimulus X Z]
//   [spectrum index] [additional items].
#include <fcntl.h>
#include <sys/stat.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "svo/octree/files.h"
#include "svo/render/luminaire.h"

namespace svo::render {

namespace {

namespace fs = std::filesystem;

constexpr uint64_t kFixedHeader = 256 + 32 + 9 * 4000;  // 36288
constexpr uint64_t kMaxRays = 1ull << 31;
constexpr uint64_t kMaxFileBytes = 8ull << 30;
constexpr int32_t kMaxSpectra = 1024, kMaxSpectrumPoints = 1 << 20, kMaxAdditional = 1024;
constexpr int32_t kMaxTextBytes = 16 << 20;
// Rays whose direction has kz below this travel (nearly) sideways or back:
// they never cross plane S at a finite distance and are dropped.
constexpr float kMinKz = 1e-4f;
// Origins farther than this from the file's origin (mm) are refused.
constexpr float kMaxCoordinate = 1e9f;
// |k| may differ from 1 by this much (then it is normalised).
constexpr float kUnitTolerance = 1e-3f;
// The share of the flux whose crossings the extents of U and S cover.
constexpr double kCoverage = 0.999;
constexpr size_t kSampleRays = 1u << 18;
constexpr size_t kChunkRays = 1u << 15;

[[noreturn]] void fail(const fs::path& path, const std::string& why) {
  throw std::runtime_error("tm25: " + path.string() + ": " + why);
}

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

int32_t i32_at(const uint8_t* p) {
  return int32_t(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24);
}
uint64_t u64_at(const uint8_t* p) { return uint64_t(uint32_t(i32_at(p))) | uint64_t(uint32_t(i32_at(p + 4))) << 32; }
float f32_at(const uint8_t* p) {
  const uint32_t bits = uint32_t(i32_at(p));
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

// A regular file opened without blocking (a FIFO would block open()).
class RayFile {
 public:
  explicit RayFile(const fs::path& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) fail(path, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) != 0) {
      ::close(fd_);
      fail(path, std::string("cannot stat: ") + std::strerror(errno));
    }
    if (!S_ISREG(st.st_mode)) {
      ::close(fd_);
      fail(path, "is " + files::file_kind_of_mode(st.st_mode) + ", expected a TM-25 ray file");
    }
    size_ = uint64_t(st.st_size);
  }
  ~RayFile() { ::close(fd_); }
  RayFile(const RayFile&) = delete;
  RayFile& operator=(const RayFile&) = delete;
  uint64_t size() const { return size_; }
  void read(uint64_t offset, void* out, size_t bytes) const {
    auto* p = static_cast<uint8_t*>(out);
    while (bytes > 0) {
      const ssize_t got = ::pread(fd_, p, bytes, off_t(offset));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) fail(path_, std::string("cannot read: ") + std::strerror(errno));
      if (got == 0) fail(path_, "truncated at byte " + std::to_string(offset) + " (the file changed while read)");
      p += got;
      offset += uint64_t(got);
      bytes -= size_t(got);
    }
  }

 private:
  fs::path path_;
  int fd_ = -1;
  uint64_t size_ = 0;
};

struct Header {
  uint64_t rays = 0;
  uint64_t ray_start = 0;
  uint32_t columns = 0;            // f32 per ray
  uint32_t flux = 0;               // the column of the flux binned
  int32_t tri_x = -1, tri_z = -1;  // tristimulus X and Z columns (photometric colour)
  bool photometric = false;
  std::string name;  // 4.7.3.1, printable ASCII only
};

Header read_header(const RayFile& file, const fs::path& path) {
  const uint64_t size = file.size();
  if (size > kMaxFileBytes) fail(path, "the file has " + std::to_string(size) + " bytes (at most 8 GiB)");
  if (size < kFixedHeader) {
    fail(path, "truncated: " + std::to_string(size) + " bytes, the header alone has " + std::to_string(kFixedHeader));
  }
  std::array<uint8_t, 288> h{};
  file.read(0, h.data(), h.size());
  if (std::memcmp(h.data(), "TM25", 4) != 0) {
    std::string magic;
    for (int k = 0; k < 4; ++k) magic += (h[k] >= 32 && h[k] < 127) ? char(h[k]) : '?';
    fail(path, "not a TM-25 ray file (magic '" + magic + "', expected 'TM25')");
  }
  const int32_t version = i32_at(&h[4]);
  if (version != 2013) fail(path, "version " + std::to_string(version) + " is not supported (2013 only)");
  for (int k : {12, 16}) {
    const float total = f32_at(&h[k]);
    if (!std::isnan(total) && !(total >= 0.0f && std::isfinite(total))) {
      fail(path, std::string("the header's total ") + (k == 12 ? "luminous" : "radiant") + " flux is " + num(total));
    }
  }
  Header out;
  out.rays = u64_at(&h[20]);
  if (out.rays == 0) fail(path, "the file holds no rays");
  if (out.rays > kMaxRays) fail(path, std::to_string(out.rays) + " rays (at most 2^31)");
  const int32_t spectral = i32_at(&h[60]);
  if (spectral < 0 || spectral > 4) fail(path, "spectral data identifier " + std::to_string(spectral) + " (0 to 4)");
  const int32_t spectra = i32_at(&h[76]);
  const int32_t additional = i32_at(&h[80]);
  const int32_t text_bytes = i32_at(&h[84]);
  if (spectra < 0 || spectra > kMaxSpectra) fail(path, std::to_string(spectra) + " spectral tables (0 to 1024)");
  if ((spectral == 3 || spectral == 4) && spectra == 0) {
    fail(path, "spectral data identifier " + std::to_string(spectral) + " without a spectral table");
  }
  if (additional < 0 || additional > kMaxAdditional) {
    fail(path, std::to_string(additional) + " additional ray items (0 to 1024)");
  }
  if (text_bytes < 0 || text_bytes > kMaxTextBytes || text_bytes % 4 != 0) {
    fail(path, "additional text block of " + std::to_string(text_bytes) + " bytes (a multiple of 4, at most 16 MiB)");
  }
  static const char* kFlags[8] = {"position",      "direction", "radiant flux", "wavelength",
                                  "luminous flux", "Stokes",    "tristimulus",  "spectrum index"};
  bool flag[8];
  for (int k = 0; k < 8; ++k) {
    const int32_t v = i32_at(&h[256 + 4 * k]);
    if (v != 0 && v != 1) fail(path, std::string("the ") + kFlags[k] + " flag is " + std::to_string(v) + " (0 or 1)");
    flag[k] = v == 1;
  }
  if (!flag[0] || !flag[1]) fail(path, "the position and direction flags must be 1");
  if (!flag[2] && !flag[4]) fail(path, "neither the radiant nor the luminous flux flag is set");
  if (flag[6] && !flag[4]) fail(path, "the tristimulus flag needs the luminous flux flag");
  if (flag[7] != (spectral == 4))
    fail(path, "the spectrum index flag must be set exactly when the spectral identifier is 4");

  // 4.7.3.1, the light source's name: UTF-32LE, NUL-terminated.
  std::array<uint8_t, 4 * 64> name{};
  file.read(288, name.data(), name.size());
  for (size_t k = 0; k < name.size(); k += 4) {
    const int32_t c = i32_at(&name[k]);
    if (c == 0) break;
    out.name += (c >= 32 && c < 127) ? char(c) : '?';
  }

  // The variable blocks: spectral tables (padded to 32 bytes), column names, text.
  uint64_t at = kFixedHeader;
  for (int32_t t = 0; t < spectra; ++t) {
    uint8_t count[4];
    if (at + 4 > size) fail(path, "truncated in spectral table " + std::to_string(t + 1));
    file.read(at, count, 4);
    const int32_t points = i32_at(count);
    if (points <= 0 || points > kMaxSpectrumPoints) {
      fail(path, "spectral table " + std::to_string(t + 1) + " has " + std::to_string(points) + " points (1 to 2^20)");
    }
    at += 4 + 8 * uint64_t(points);
    if (at > size) fail(path, "truncated in spectral table " + std::to_string(t + 1));
  }
  if ((at - kFixedHeader) % 32 != 0) at += 32 - (at - kFixedHeader) % 32;
  at += 512 * uint64_t(additional) + uint64_t(text_bytes);
  if (at > size) fail(path, "truncated: the header's variable blocks end at byte " + std::to_string(at));
  out.ray_start = at;

  // The columns the flags imply (Stokes: 3 or 6 columns, the size decides).
  uint32_t col = 6;
  const uint32_t radiant = flag[2] ? col++ : 0;
  if (flag[3]) ++col;
  const uint32_t luminous = flag[4] ? col++ : 0;
  const uint32_t stokes_at = col;
  auto columns_with = [&](uint32_t stokes) {
    return col + (flag[5] ? stokes : 0) + (flag[6] ? 2 : 0) + (flag[7] ? 1 : 0) + uint32_t(additional);
  };
  const uint64_t payload = size - at;
  uint32_t stokes = 3;
  if (flag[5] && payload != out.rays * 4 * columns_with(3)) stokes = 6;
  out.columns = columns_with(stokes);
  if (payload != out.rays * 4 * out.columns) {
    fail(path, "the file has " + std::to_string(size) + " bytes, but " + std::to_string(out.rays) + " rays of " +
                   std::to_string(4 * out.columns) + " bytes after a header of " + std::to_string(at) + " bytes make " +
                   std::to_string(at + out.rays * 4 * out.columns));
  }
  out.photometric = flag[4];
  out.flux = out.photometric ? luminous : radiant;
  if (flag[6]) {
    out.tri_x = int32_t(stokes_at + (flag[5] ? stokes : 0));
    out.tri_z = out.tri_x + 1;
  }
  return out;
}

struct Ray {
  glm::vec3 origin;
  glm::vec3 k;  // unit
  float flux;
  glm::vec3 rgb;  // flux per channel (grey: flux each)
};

// Reads the rays in chunks, checks each and calls visit(Ray).
template <typename Visit>
void for_each_ray(const RayFile& file, const fs::path& path, const Header& header, Visit&& visit) {
  std::vector<uint8_t> buffer;
  const size_t stride = 4 * size_t(header.columns);
  for (uint64_t first = 0; first < header.rays; first += kChunkRays) {
    const size_t count = size_t(std::min<uint64_t>(kChunkRays, header.rays - first));
    buffer.resize(count * stride);
    file.read(header.ray_start + first * stride, buffer.data(), buffer.size());
    for (size_t r = 0; r < count; ++r) {
      const uint8_t* p = &buffer[r * stride];
      const uint64_t index = first + r;
      auto where = [&] { return "ray " + std::to_string(index) + ": "; };
      Ray ray;
      ray.origin = {f32_at(p), f32_at(p + 4), f32_at(p + 8)};
      ray.k = {f32_at(p + 12), f32_at(p + 16), f32_at(p + 20)};
      ray.flux = f32_at(p + 4 * header.flux);
      for (int c = 0; c < 3; ++c) {
        if (!std::isfinite(ray.origin[c]) || std::fabs(ray.origin[c]) > kMaxCoordinate) {
          fail(path, where() + "the origin (" + num(ray.origin.x) + ", " + num(ray.origin.y) + ", " +
                         num(ray.origin.z) + ") is not finite or beyond 1e9 mm");
        }
      }
      const double len = std::sqrt(double(ray.k.x) * ray.k.x + double(ray.k.y) * ray.k.y + double(ray.k.z) * ray.k.z);
      if (!(std::fabs(len - 1.0) <= kUnitTolerance)) {
        fail(path, where() + "the direction (" + num(ray.k.x) + ", " + num(ray.k.y) + ", " + num(ray.k.z) +
                       ") is not a unit vector");
      }
      ray.k = glm::vec3(glm::dvec3(ray.k) / len);
      if (!std::isfinite(ray.flux)) fail(path, where() + "the flux is " + num(ray.flux));
      if (ray.flux < 0.0f) fail(path, where() + "negative flux " + num(ray.flux));
      ray.rgb = glm::vec3(ray.flux);
      if (header.tri_x >= 0) {
        float x = f32_at(p + 4 * header.tri_x), z = f32_at(p + 4 * header.tri_z);
        if (!std::isfinite(x) || !std::isfinite(z)) fail(path, where() + "a tristimulus value is not finite");
        x = std::max(x, 0.0f);
        z = std::max(z, 0.0f);
        const float y = ray.flux;
        // CIE XYZ to linear sRGB (D65): its luminance row gives back Y.
        ray.rgb = {3.2404542f * x - 1.5371385f * y - 0.4985314f * z, -0.9692660f * x + 1.8760108f * y + 0.0415560f * z,
                   0.0556434f * x - 0.2040259f * y + 1.0572252f * z};
      }
      visit(ray);
    }
  }
}

// The flux-weighted quantile q of the values.
double quantile(std::vector<std::pair<double, double>>& values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  double total = 0.0;
  for (const auto& v : values) total += v.second;
  double sum = 0.0;
  for (const auto& v : values) {
    sum += v.second;
    if (sum >= q * total) return v.first;
  }
  return values.back().first;
}

// The integral of cos^4(theta) / delta^2 over the quadrant [0, x] x [0, y]
// of a plane at distance delta (signed: odd in x and in y), from the form
// factor of a differential area to a parallel rectangle: pi F.
struct Corner {
  double a, ia, ra;  // a = x / delta, ia = 1 / sqrt(1 + a^2), ra = a ia
  explicit Corner(double x_over_delta) : a(x_over_delta), ia(1.0 / std::sqrt(1.0 + a * a)), ra(a * ia) {}
};
double quadrant(const Corner& x, const Corner& y) {
  return 0.5 * (x.ra * std::atan(y.a * x.ia) + y.ra * std::atan(x.a * y.ia));
}

}  // namespace

LightField import_tm25(const std::filesystem::path& path, uint32_t grid, uint32_t resolution) {
  if (resolution < 1 || resolution > LightField::kMaxImageSide) {
    throw std::invalid_argument("tm25: the resolution must be 1 to " + std::to_string(LightField::kMaxImageSide) +
                                ", not " + std::to_string(resolution));
  }
  if (grid < 1 || grid > LightField::kMaxGridSide) {
    throw std::invalid_argument("tm25: the grid must be 1 to " + std::to_string(LightField::kMaxGridSide) +
                                " basis functions across, not " + std::to_string(grid));
  }
  if (uint64_t(grid) * grid * resolution * resolution > LightField::kMaxTexels) {
    throw std::invalid_argument("tm25: " + std::to_string(grid) + "^2 images of " + std::to_string(resolution) +
                                "^2 texels exceed " + std::to_string(LightField::kMaxTexels) + " texels");
  }
  const RayFile file(path);
  const Header header = read_header(file, path);

  // Pass 1: checks every ray; the forward rays' top origin, the totals, and
  // a sample (about one forward ray in stride) for the extents.
  const uint64_t stride = std::max<uint64_t>(1, (header.rays + kSampleRays - 1) / kSampleRays);
  double total = 0.0, backward = 0.0;
  float z_top = -INFINITY;
  std::vector<Ray> sample;
  uint64_t index = 0;
  for_each_ray(file, path, header, [&](const Ray& ray) {
    total += ray.flux;
    if (ray.k.z < kMinKz) {
      backward += ray.flux;
    } else if (ray.flux > 0.0f) {
      z_top = std::max(z_top, ray.origin.z);
      // A hashed choice: files often list their rays in strata.
      uint64_t z = (index + 1) * 0x9e3779b97f4a7c15ull;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
      if ((z ^ (z >> 31)) % stride == 0) sample.push_back(ray);
    }
    ++index;
  });
  if (!(total > 0.0)) fail(path, "the rays carry no flux");
  if (!(total - backward > 0.0) || sample.empty()) fail(path, "no ray with flux travels towards +z");

  // U: the plane z = z_top; the sample's crossings of U fix its half size a,
  // delta = 2a, and the crossings of S its extent (kCoverage of the flux).
  auto cross_u = [&](const Ray& r) {
    const double t = (double(z_top) - r.origin.z) / r.k.z;
    return glm::dvec2(r.origin.x + r.k.x * t, r.origin.y + r.k.y * t);
  };
  std::vector<std::pair<double, double>> ux, uy;
  for (const Ray& r : sample) {
    const glm::dvec2 u = cross_u(r);
    ux.emplace_back(std::fabs(u.x), r.flux);
    uy.emplace_back(std::fabs(u.y), r.flux);
  }
  const double a = std::max({quantile(ux, kCoverage), quantile(uy, kCoverage), 1e-3});
  const double delta = 2.0 * a;
  std::vector<std::pair<double, double>> sx, sy;
  for (const Ray& r : sample) {
    const glm::dvec2 s = cross_u(r) + glm::dvec2(r.k.x, r.k.y) / double(r.k.z) * delta;
    sx.emplace_back(std::fabs(s.x), r.flux);
    sy.emplace_back(std::fabs(s.y), r.flux);
  }
  // A margin of 1% for the sample's quantile; at least half of U's size.
  const glm::dvec2 half_s(std::max(1.01 * quantile(sx, kCoverage), 0.5 * a),
                          std::max(1.01 * quantile(sy, kCoverage), 0.5 * a));

  LightField f;
  f.width = f.height = resolution;
  f.grid_w = f.grid_h = grid;
  f.basis = LuminaireBasis::BSpline;
  f.delta = float(delta);
  f.extent = glm::vec2(2.0 * half_s);
  // The B-splines sum to 1 within (grid/2 - 1) h of the axis: that zone
  // covers U's size a (grids of 3 or fewer: h = 2a, the border normalised).
  f.spacing = float(a / std::max(0.5 * grid - 1.0, 0.5));
  f.units = "mm";
  f.metres_per_unit = 0.001f;
  f.images.assign(f.image_count(), std::vector<float>(size_t(resolution) * resolution * 3, 0.0f));

  // Pass 2: each forward ray's flux into the texel it crosses S at, split
  // among the bases by Phi_m(u) (normalised where the weights sum below 1).
  const double h = f.spacing;
  const double centre0 = -0.5 * double(grid - 1) * h;  // basis 0's centre
  double lost_s = 0.0, lost_u = 0.0;
  for_each_ray(file, path, header, [&](const Ray& ray) {
    if (ray.k.z < kMinKz || ray.flux <= 0.0f) return;
    const glm::dvec2 u = cross_u(ray);
    const glm::dvec2 s = u + glm::dvec2(ray.k.x, ray.k.y) / double(ray.k.z) * delta;
    const glm::dvec2 tf = (s / glm::dvec2(f.extent) + 0.5) * double(resolution);
    if (!(tf.x >= 0.0 && tf.y >= 0.0 && tf.x < resolution && tf.y < resolution)) {
      lost_s += ray.flux;
      return;
    }
    const size_t texel = size_t(uint32_t(tf.y)) * resolution + uint32_t(tf.x);
    int first[2];
    float w[2][3];
    float sum[2] = {0.0f, 0.0f};
    for (int axis = 0; axis < 2; ++axis) {
      const double x = (u[axis] - centre0) / h;  // in units of h from basis 0
      first[axis] = int(std::ceil(x - 1.5));
      for (int k = 0; k < 3; ++k) {
        const int i = first[axis] + k;
        w[axis][k] = (i >= 0 && i < int(grid)) ? luminaire_basis_phi(f.basis, float(x - i)) : 0.0f;
        sum[axis] += w[axis][k];
      }
    }
    if (!(sum[0] > 0.0f && sum[1] > 0.0f)) {
      lost_u += ray.flux;
      return;
    }
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        const float weight = w[0][i] * w[1][j] / (sum[0] * sum[1]);
        if (weight <= 0.0f) continue;
        float* c = &f.images[size_t(first[1] + j) * grid + size_t(first[0] + i)][3 * texel];
        c[0] += weight * ray.rgb.x;
        c[1] += weight * ray.rgb.y;
        c[2] += weight * ray.rgb.z;
      }
    }
  });

  // C_m(t) = flux_m(t) / integral over U x texel t of Phi_m(u) cos^4 / delta^2:
  // on U by 3-point Gauss-Legendre in each cell of h (Phi is quadratic on
  // each), over the texel exactly (quadrant()).
  const uint32_t cells = grid + 2;  // the supports' union: (grid + 2) h across
  const double gauss_x[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double gauss_w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  std::vector<double> nodes, weights;  // along one axis
  for (uint32_t c = 0; c < cells; ++c) {
    const double mid = (double(c) - 0.5 * cells + 0.5) * h;
    for (int k = 0; k < 3; ++k) {
      nodes.push_back(mid + 0.5 * h * gauss_x[k]);
      weights.push_back(0.5 * h * gauss_w[k]);
    }
  }
  const glm::dvec2 texel_size = glm::dvec2(f.extent) / double(resolution);
  const size_t images = f.image_count();
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, resolution), [&](const tbb::blocked_range<uint32_t>& rows) {
    std::vector<double> denom(images * resolution);
    std::vector<Corner> xs;
    std::vector<double> band(resolution);
    std::vector<uint8_t> lit(images);
    for (uint32_t y = rows.begin(); y != rows.end(); ++y) {
      bool any = false;
      for (size_t m = 0; m < images; ++m) {
        const float* row = &f.images[m][3 * size_t(y) * resolution];
        lit[m] = std::any_of(row, row + 3 * resolution, [](float v) { return v != 0.0f; });
        any = any || lit[m];
      }
      if (!any) continue;
      std::fill(denom.begin(), denom.end(), 0.0);
      const double y0 = double(y) * texel_size.y - 0.5 * f.extent.y, y1 = y0 + texel_size.y;
      for (size_t qy = 0; qy < nodes.size(); ++qy) {
        const double vy = nodes[qy];
        const double py = (vy - centre0) / h;
        const Corner c0((y0 - vy) / delta), c1((y1 - vy) / delta);
        for (size_t qx = 0; qx < nodes.size(); ++qx) {
          const double vx = nodes[qx];
          const double px = (vx - centre0) / h;
          // The bases this point lies in the support of, with Phi > 0.
          size_t ms[9];
          double phis[9];
          int count = 0;
          for (int j = int(std::ceil(py - 1.5)); j <= int(std::floor(py + 1.5)); ++j) {
            if (j < 0 || j >= int(grid)) continue;
            const double fy = luminaire_basis_phi(f.basis, float(py - j));
            for (int i = int(std::ceil(px - 1.5)); i <= int(std::floor(px + 1.5)); ++i) {
              if (i < 0 || i >= int(grid) || count == 9) continue;
              const size_t m = size_t(j) * grid + size_t(i);
              const double phi = fy * luminaire_basis_phi(f.basis, float(px - i));
              if (phi > 0.0 && lit[m]) {
                ms[count] = m;
                phis[count++] = phi;
              }
            }
          }
          if (count == 0) continue;
          xs.clear();
          for (uint32_t x = 0; x <= resolution; ++x) {
            xs.emplace_back((double(x) * texel_size.x - 0.5 * f.extent.x - vx) / delta);
          }
          double prev = quadrant(xs[0], c1) - quadrant(xs[0], c0);
          for (uint32_t x = 0; x < resolution; ++x) {
            const double next = quadrant(xs[x + 1], c1) - quadrant(xs[x + 1], c0);
            band[x] = next - prev;
            prev = next;
          }
          const double wq = weights[qx] * weights[qy];
          for (int k = 0; k < count; ++k) {
            double* d = &denom[ms[k] * resolution];
            const double scale = wq * phis[k];
            for (uint32_t x = 0; x < resolution; ++x) d[x] += scale * band[x];
          }
        }
      }
      for (size_t m = 0; m < images; ++m) {
        if (!lit[m]) continue;
        float* row = &f.images[m][3 * size_t(y) * resolution];
        for (uint32_t x = 0; x < resolution; ++x) {
          const double d = denom[m * resolution + x];
          for (int c = 0; c < 3; ++c) {
            float& v = row[3 * x + c];
            v = (d > 0.0 && v > 0.0f) ? float(double(v) / d) : 0.0f;
            if (!std::isfinite(v)) v = 0.0f;
          }
        }
      }
    }
  });

  const auto percent = [&](double part) { return num(100.0 * part / total) + "%"; };
  std::string source = "tm25: " + (header.name.empty() ? std::string("?") : header.name.substr(0, 48)) + " (" +
                       path.filename().string().substr(0, 64) + "), " + std::to_string(header.rays) + " rays, " +
                       num(total) + (header.photometric ? " lm photometric" : " W radiometric") +
                       "; lost: " + percent(backward) + " backward, " + percent(lost_s) + " outside S, " +
                       percent(lost_u) + " outside U";
  if (source.size() > 255) source.resize(255);
  for (char& c : source) {
    if (uint8_t(c) < 0x20 || uint8_t(c) >= 0x7f) c = '?';  // one line of ASCII
  }
  f.source = source;
  validate_light_field(f);
  return f;
}

}  // namespace svo::render
