#include "svo/render/merl.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/shared_math.h"
#include "svo/octree/files.h"

namespace svo::math {
// merl.glsl over one BRDF's values (at offset 0) or over the shading tables.
struct MerlTableReader {
  const float* t;
  float svo_table(uint32_t i) const { return t[i]; }
#include "common/merl.glsl"
};
}  // namespace svo::math

namespace svo::render {

namespace {

namespace fs = std::filesystem;
using Merl = math::MerlTableReader;

constexpr double kPi = 3.14159265358979323846;
constexpr const char* kChannel[3] = {"R", "G", "B"};

[[noreturn]] void fail(const fs::path& path, const std::string& why) {
  throw std::runtime_error("merl: " + path.string() + ": " + why);
}

// Where sample k lies in the table, for messages.
std::string sample_name(uint32_t k) {
  return "sample " + std::to_string(k) + " (theta_h " + std::to_string(k / (kMerlPhiD * kMerlThetaD)) + ", theta_d " +
         std::to_string(k / kMerlPhiD % kMerlThetaD) + ", phi_d " + std::to_string(k % kMerlPhiD) + ")";
}

// Closes a descriptor on scope exit.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// Builds a distribution of nu x nv cells over f (nv rows of nu, >= 0) in
// distribution.glsl's layout and appends it to `out`.
void append_dist2d(const std::vector<double>& f, uint32_t nu, uint32_t nv, std::vector<float>& out) {
  std::vector<float> block(Merl{nullptr}.svo_dist2d_floats(nu, nv), 0.0f);
  float* values = block.data();
  float* rows = values + nu * nv;
  float* marginal = rows + nv * (nu + 1);
  std::vector<double> row_sum(nv, 0.0);
  double total = 0;
  for (uint32_t v = 0; v < nv; ++v) {
    double run = 0;
    rows[v * (nu + 1)] = 0.0f;
    for (uint32_t u = 0; u < nu; ++u) {
      values[v * nu + u] = float(f[v * nu + u]);
      run += double(values[v * nu + u]);
      rows[v * (nu + 1) + u + 1] = float(run);
    }
    for (uint32_t u = 1; u <= nu; ++u) {
      float& c = rows[v * (nu + 1) + u];
      c = run > 0 ? float(double(c) / run) : float(u) / float(nu);
    }
    rows[v * (nu + 1) + nu] = 1.0f;
    row_sum[v] = run;
    total += run;
  }
  double run = 0;
  marginal[0] = 0.0f;
  for (uint32_t v = 0; v < nv; ++v) {
    run += row_sum[v];
    marginal[v + 1] = total > 0 ? float(run / total) : float(v + 1) / float(nv);
  }
  marginal[nv] = 1.0f;
  marginal[nv + 1] = float(total / double(nu * nv));
  out.insert(out.end(), block.begin(), block.end());
}

}  // namespace

MerlBrdf load_merl(const fs::path& path) {
  // The kind of file first, following links, before anything opens it (a
  // FIFO would block the open).
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) fail(path, "no such file");
  if (ec) fail(path, "cannot inspect: " + ec.message());
  if (status.type() != fs::file_type::regular)
    fail(path, "is " + files::file_kind(status.type()) + ", expected a MERL .binary file");
  Fd file{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY)};
  if (file.fd < 0) fail(path, std::string("cannot open: ") + std::strerror(errno));
  // And again on what was opened (the path may have changed in between).
  struct stat st {};
  if (::fstat(file.fd, &st) != 0) fail(path, std::string("cannot inspect: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(path, "is " + files::file_kind_of_mode(st.st_mode) + ", expected a MERL .binary file");
  if (uint64_t(st.st_size) != kMerlFileBytes) {
    fail(path, std::to_string(st.st_size) + " bytes, expected " + std::to_string(kMerlFileBytes) +
                   " (a 12-byte header and 3 x 90 x 90 x 180 doubles)");
  }
  // Reads exactly n bytes at `to` (the size was checked: a short read means
  // the file changed under us).
  uint64_t got = 0;
  auto read_exactly = [&](unsigned char* to, size_t n) {
    for (size_t done = 0; done < n;) {
      const ssize_t r = ::read(file.fd, to + done, n - done);
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) fail(path, std::string("cannot read: ") + std::strerror(errno));
      if (r == 0) fail(path, "ends at byte " + std::to_string(got) + ", expected " + std::to_string(kMerlFileBytes));
      done += size_t(r);
      got += uint64_t(r);
    }
  };
  unsigned char header[12];
  read_exactly(header, sizeof header);
  auto i32 = [&](size_t at) {
    return int32_t(uint32_t(header[at]) | uint32_t(header[at + 1]) << 8 | uint32_t(header[at + 2]) << 16 |
                   uint32_t(header[at + 3]) << 24);
  };
  const int32_t dims[3] = {i32(0), i32(4), i32(8)};
  if (dims[0] != int32_t(kMerlThetaH) || dims[1] != int32_t(kMerlThetaD) || dims[2] != int32_t(kMerlPhiD)) {
    fail(path, "dimensions " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " +
                   std::to_string(dims[2]) + ", expected 90 x 90 x 180");
  }
  MerlBrdf brdf;
  brdf.rgb.resize(3 * size_t(kMerlSamples));
  constexpr uint32_t kChunk = 8100;  // samples per read (divides kMerlSamples)
  std::vector<unsigned char> chunk(size_t(kChunk) * 8);
  for (uint32_t c = 0; c < 3; ++c) {
    for (uint32_t k0 = 0; k0 < kMerlSamples; k0 += kChunk) {
      read_exactly(chunk.data(), chunk.size());
      for (uint32_t j = 0; j < kChunk; ++j) {
        const uint32_t k = k0 + j;
        uint64_t bits;
        std::memcpy(&bits, chunk.data() + size_t(j) * 8, 8);
        if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap64(bits);
        const double v = std::bit_cast<double>(bits);
        if (!std::isfinite(v)) {
          fail(path, std::string(kChannel[c]) + " " + sample_name(k) + " is " + (std::isnan(v) ? "NaN" : "infinite"));
        }
        const float f = v > 0 ? float(v * kMerlScale[c]) : 0.0f;
        if (!std::isfinite(f))
          fail(path, std::string(kChannel[c]) + " " + sample_name(k) + " is too large for a float");
        brdf.rgb[3 * size_t(k) + c] = f;
      }
    }
  }
  return brdf;
}

void write_merl(const fs::path& path, const MerlBrdf& brdf) {
  if (brdf.rgb.size() != 3 * size_t(kMerlSamples)) {
    fail(path, "cannot write " + std::to_string(brdf.rgb.size()) + " values, expected " +
                   std::to_string(3 * size_t(kMerlSamples)));
  }
  std::vector<unsigned char> bytes(kMerlFileBytes);
  const uint32_t dims[3] = {kMerlThetaH, kMerlThetaD, kMerlPhiD};
  for (int d = 0; d < 3; ++d)
    for (int b = 0; b < 4; ++b) bytes[size_t(4 * d + b)] = uint8_t(dims[d] >> (8 * b));
  for (uint32_t c = 0; c < 3; ++c) {
    unsigned char* block = bytes.data() + 12 + size_t(c) * 8 * kMerlSamples;
    for (uint32_t k = 0; k < kMerlSamples; ++k) {
      uint64_t bits = std::bit_cast<uint64_t>(double(brdf.rgb[3 * size_t(k) + c]) / kMerlScale[c]);
      if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap64(bits);
      std::memcpy(block + size_t(k) * 8, &bits, 8);
    }
  }
  try {
    files::write_file(path.string(), bytes.data(), bytes.size());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("merl: ") + e.what());
  }
}

std::array<glm::dvec3, 2> merl_sample_directions(uint32_t k) {
  const uint32_t ih = k / (kMerlPhiD * kMerlThetaD), id = k / kMerlPhiD % kMerlThetaD, ip = k % kMerlPhiD;
  const double s = double(ih) / kMerlThetaH;
  const double theta_h = s * s * (0.5 * kPi);
  const double theta_d = double(id) / kMerlThetaD * (0.5 * kPi);
  const double phi_d = double(ip) / kMerlPhiD * kPi;
  // wi in the frame of h, wo its mirror image about h; both rotated by
  // theta_h about the binormal (the inverse of the reference code's
  // rotation by -theta_h; phi_h = 0).
  const glm::dvec3 d(std::sin(theta_d) * std::cos(phi_d), std::sin(theta_d) * std::sin(phi_d), std::cos(theta_d));
  const double ch = std::cos(theta_h), sh = std::sin(theta_h);
  auto rotate = [&](glm::dvec3 v) { return glm::dvec3(v.x * ch + v.z * sh, v.y, v.z * ch - v.x * sh); };
  return {rotate(d), rotate(glm::dvec3(-d.x, -d.y, d.z))};
}

MerlBrdf tabulate_merl(const std::function<glm::dvec3(glm::dvec3 wi, glm::dvec3 wo)>& brdf) {
  MerlBrdf out;
  out.rgb.assign(3 * size_t(kMerlSamples), 0.0f);
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, kMerlSamples, kMerlPhiD),
                    [&](const tbb::blocked_range<uint32_t>& r) {
                      for (uint32_t k = r.begin(); k != r.end(); ++k) {
                        const auto [wi, wo] = merl_sample_directions(k);
                        if (!(wi.z > 0) || !(wo.z > 0)) continue;
                        const glm::dvec3 f = brdf(wi, wo);
                        for (int c = 0; c < 3; ++c) {
                          if (!(f[c] >= 0) || !std::isfinite(f[c])) {
                            throw std::invalid_argument("merl: tabulate: the BRDF is " + std::to_string(f[c]) +
                                                        " in channel " + kChannel[c] + " at " + sample_name(k));
                          }
                          out.rgb[3 * size_t(k) + size_t(c)] = float(f[c]);
                        }
                      }
                    });
  return out;
}

uint32_t merl_sampling_floats() {
  return Merl::SVO_MERL_BINS * Merl{nullptr}.svo_dist2d_floats(Merl::SVO_MERL_NU, Merl::SVO_MERL_NV);
}

std::array<uint32_t, 2> append_merl_tables(const MerlBrdf& brdf, std::vector<float>& tables) {
  if (brdf.rgb.size() != 3 * size_t(kMerlSamples)) {
    throw std::invalid_argument("merl: tables: " + std::to_string(brdf.rgb.size()) + " values, expected " +
                                std::to_string(3 * size_t(kMerlSamples)));
  }
  for (size_t i = 0; i < brdf.rgb.size(); ++i) {
    if (!(brdf.rgb[i] >= 0) || !std::isfinite(brdf.rgb[i])) {
      throw std::invalid_argument("merl: tables: " + std::string(kChannel[i % 3]) + " " + sample_name(uint32_t(i / 3)) +
                                  " is " + std::to_string(brdf.rgb[i]));
    }
  }
  if (tables.size() + brdf.rgb.size() + merl_sampling_floats() > std::numeric_limits<uint32_t>::max()) {
    throw std::invalid_argument("merl: tables: the shading tables would outgrow 32-bit offsets");
  }
  const uint32_t nu = Merl::SVO_MERL_NU, nv = Merl::SVO_MERL_NV, bins = Merl::SVO_MERL_BINS;
  // Per elevation bin of wo (at its centre), the luminance of
  // f cos(theta) sin(theta) averaged over 4 x 4 points per cell, so that
  // lobes narrower than a cell still weigh what they hold (Bagher et al.
  // 2013, section 3.3: tabulated CDFs inverted numerically).
  constexpr int kSub = 4;
  Merl reader{brdf.rgb.data()};
  std::vector<std::vector<double>> cells(bins, std::vector<double>(size_t(nu) * nv, 0.0));
  tbb::parallel_for(uint32_t(0), bins, [&](uint32_t b) {
    const double theta_o = (b + 0.5) / bins * (0.5 * kPi);
    const glm::vec3 wo(float(std::sin(theta_o)), 0.0f, float(std::cos(theta_o)));
    std::vector<double>& f = cells[b];
    for (uint32_t v = 0; v < nv; ++v) {
      for (uint32_t u = 0; u < nu; ++u) {
        double sum = 0;
        for (int sv = 0; sv < kSub; ++sv) {
          const double theta = (v + (sv + 0.5) / kSub) / nv * (0.5 * kPi);
          for (int su = 0; su < kSub; ++su) {
            const double phi = (u + (su + 0.5) / kSub) / nu * (2 * kPi);
            const glm::vec3 wi(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                               float(std::cos(theta)));
            const glm::vec3 rgb = Merl{reader}.svo_merl_eval(0u, wi, wo);
            const double lum = 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
            sum += std::max(lum, 0.0) * std::cos(theta) * std::sin(theta);
          }
        }
        f[v * nu + u] = sum / (kSub * kSub);
      }
    }
    // A floor of 1% of the mean, spread uniformly over solid angle (a cell's
    // share is its mean sin(theta) over the hemisphere's, 2/pi), so that
    // every direction above the surface has pdf > 0 (all of it where f = 0
    // everywhere).
    double mean = 0;
    for (double x : f) mean += x;
    mean /= double(f.size());
    const double floor = mean > 0 ? 0.01 * mean : 1.0;
    for (uint32_t v = 0; v < nv; ++v) {
      const double t0 = double(v) / nv * (0.5 * kPi), t1 = double(v + 1) / nv * (0.5 * kPi);
      const double mean_sin = (std::cos(t0) - std::cos(t1)) / (t1 - t0);
      for (uint32_t u = 0; u < nu; ++u) f[v * nu + u] += floor * mean_sin / (2 / kPi);
    }
  });
  const uint32_t values = uint32_t(tables.size());
  tables.insert(tables.end(), brdf.rgb.begin(), brdf.rgb.end());
  const uint32_t sampling = uint32_t(tables.size());
  for (uint32_t b = 0; b < bins; ++b) append_dist2d(cells[b], nu, nv, tables);
  return {values, sampling};
}

}  // namespace svo::render
