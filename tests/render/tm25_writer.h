// Writes IES TM-25-13 ray files for the tests and the fuzz seeds, in the
// layout import_tm25 reads (render/src/tm25.cpp, docs/luminaire_tm25.md).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace svo::testing {

struct Tm25Ray {
  float x, y, z, kx, ky, kz, flux;
  float tri_x = 0.0f, tri_z = 0.0f;  // written when Tm25File::tristimulus
};

struct Tm25File {
  std::vector<Tm25Ray> rays;
  bool photometric = false;  // the flux column: luminous (lm) or radiant (W)
  bool tristimulus = false;  // X and Z columns (photometric only)
  std::string name = "test source";
  // Written as is when set (a lie), else rays.size().
  int64_t count_override = -1;
  // Fixed-header description block (9 x 4000 bytes) left out (the fuzz
  // target's compact inputs); the importer needs it.
  bool compact = false;
  // One spectral table of this many points when > 0 (spectral identifier 3).
  int32_t spectrum_points = 0;
};

// A Lambertian square of side `side` at z = z0 with radiance L0: origins
// stratified on the square, directions cosine-weighted (stratified too),
// each ray carrying L0 pi A / N.
inline Tm25File lambertian(float L0, float side, uint32_t n_side, uint32_t dirs, float z0 = 0.0f) {
  constexpr float pi = 3.14159265358979f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0.0f, 1.0f);
  Tm25File file;
  const uint32_t n = n_side * n_side * dirs;
  const float flux = L0 * pi * side * side / float(n);
  const uint32_t d_side = uint32_t(std::lround(std::sqrt(double(dirs))));
  for (uint32_t j = 0; j < n_side; ++j) {
    for (uint32_t i = 0; i < n_side; ++i) {
      for (uint32_t d = 0; d < dirs; ++d) {
        const float x = ((float(i) + uni(rng)) / float(n_side) - 0.5f) * side;
        const float y = ((float(j) + uni(rng)) / float(n_side) - 0.5f) * side;
        const float r1 = (float(d % d_side) + uni(rng)) / float(d_side);
        const float r2 = (float(d / d_side % d_side) + uni(rng)) / float(d_side);
        const float sin_t = std::sqrt(r1), phi = 2.0f * pi * r2;
        file.rays.push_back({x, y, z0, sin_t * std::cos(phi), sin_t * std::sin(phi), std::sqrt(1.0f - r1), flux});
      }
    }
  }
  return file;
}

inline std::vector<uint8_t> encode_tm25(const Tm25File& file) {
  std::vector<uint8_t> out(256 + 32, 0);
  auto put32 = [&](size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) out[at + k] = uint8_t(v >> (8 * k));
  };
  auto putf = [&](size_t at, float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    put32(at, bits);
  };
  std::memcpy(out.data(), "TM25", 4);
  put32(4, 2013);
  put32(8, 0);  // simulation
  double total = 0.0;
  for (const auto& r : file.rays) total += r.flux;
  putf(12, file.photometric ? float(total) : 0.0f);
  putf(16, file.photometric ? 0.0f : float(total));
  const uint64_t count = file.count_override >= 0 ? uint64_t(file.count_override) : file.rays.size();
  put32(20, uint32_t(count));
  put32(24, uint32_t(count >> 32));
  std::memcpy(&out[28], "2025-01-01T00:00:00Z", 20);
  put32(60, file.spectrum_points > 0 ? 3 : 0);
  putf(64, 550.0f);
  putf(68, 380.0f);
  putf(72, 780.0f);
  put32(76, file.spectrum_points > 0 ? 1 : 0);
  const int flags[8] = {1, 1, file.photometric ? 0 : 1, 0, file.photometric ? 1 : 0, 0, file.tristimulus ? 1 : 0, 0};
  for (int k = 0; k < 8; ++k) put32(256 + 4 * k, uint32_t(flags[k]));
  auto append32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
  };
  auto appendf = [&](float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    append32(bits);
  };
  if (!file.compact) {
    std::vector<uint8_t> text(9 * 4000, 0);
    for (size_t k = 0; k < file.name.size() && k < 999; ++k) text[4 * k] = uint8_t(file.name[k]);
    out.insert(out.end(), text.begin(), text.end());
  }
  if (file.spectrum_points > 0) {
    const size_t start = out.size();
    append32(uint32_t(file.spectrum_points));
    for (int32_t k = 0; k < file.spectrum_points; ++k) {
      appendf(380.0f + 400.0f * float(k) / float(file.spectrum_points));
      appendf(1.0f);
    }
    while ((out.size() - start) % 32 != 0) out.push_back(0);
  }
  for (const auto& r : file.rays) {
    for (float v : {r.x, r.y, r.z, r.kx, r.ky, r.kz, r.flux}) appendf(v);
    if (file.tristimulus) {
      appendf(r.tri_x);
      appendf(r.tri_z);
    }
  }
  return out;
}

}  // namespace svo::testing
