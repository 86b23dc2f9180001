// The luminaires' tables for shaders/common/luminaire.glsl (whose header
// comment gives the layout), their frames and the option names.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "svo/render/luminaire.h"

namespace svo::render {

namespace {

template <typename E, size_t N>
E parse_name(const std::string& name, const std::array<const char*, N>& names, const char* what) {
  std::string list;
  for (size_t i = 0; i < N; ++i) {
    if (name == names[i]) return E(i);
    list += (i ? ", " : "") + std::string(names[i]);
  }
  throw std::invalid_argument(std::string(what) + " '" + name + "' is not one of " + list);
}

constexpr std::array<const char*, 4> kSamplers{"restricted", "uniform", "global", "box"};
constexpr std::array<const char*, 4> kSearches{"secant", "binary", "illinois", "classic"};
constexpr std::array<const char*, 4> kVisibilities{"none", "cells", "samples", "cells-on-u"};
constexpr std::array<const char*, 2> kSequences{"halton", "random"};

float bits(uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

constexpr uint32_t kHeader = 8, kBlock = 32;

}  // namespace

const char* luminaire_sampler_name(LuminaireSampler s) { return kSamplers[size_t(s)]; }
const char* luminaire_search_name(LuminaireSearch s) { return kSearches[size_t(s)]; }
const char* luminaire_visibility_name(LuminaireVisibility v) { return kVisibilities[size_t(v)]; }
const char* luminaire_sequence_name(LuminaireSequence s) { return kSequences[size_t(s)]; }
LuminaireSampler parse_luminaire_sampler(const std::string& n) {
  return parse_name<LuminaireSampler>(n, kSamplers, "sampler");
}
LuminaireSearch parse_luminaire_search(const std::string& n) {
  return parse_name<LuminaireSearch>(n, kSearches, "search");
}
LuminaireVisibility parse_luminaire_visibility(const std::string& n) {
  return parse_name<LuminaireVisibility>(n, kVisibilities, "visibility");
}
LuminaireSequence parse_luminaire_sequence(const std::string& n) {
  return parse_name<LuminaireSequence>(n, kSequences, "sequence");
}

LuminaireFrame luminaire_frame(const LightField& field, const LuminairePlacement& placement) {
  const glm::vec3 axis = placement.aim - placement.at;
  const float len = glm::length(axis);
  if (!(len > 0.0f) || !std::isfinite(len)) {
    throw std::invalid_argument("luminaire: the point it aims at must differ from where it stands");
  }
  LuminaireFrame f;
  f.centre = placement.at;
  f.z = axis / len;
  // x across S, level when the axis is not vertical; y = z x x.
  const glm::vec3 up = std::fabs(f.z.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  f.x = glm::normalize(glm::cross(up, f.z));
  f.y = glm::cross(f.z, f.x);
  f.scale = placement.size > 0.0f ? placement.size / std::max(field.extent.x, field.extent.y) : field.metres_per_unit;
  return f;
}

std::vector<float> build_luminaire_tables(const LuminaireOptions& options) {
  if (options.luminaires.size() > LuminaireOptions::kMaxLuminaires) {
    throw std::invalid_argument("at most " + std::to_string(LuminaireOptions::kMaxLuminaires) + " luminaires");
  }
  const uint32_t count = uint32_t(options.luminaires.size());
  std::vector<float> t(kHeader + kBlock * std::max(count, 1u), 0.0f);
  t[0] = bits(count);
  t[1] = bits(uint32_t(options.sampler));
  t[2] = bits(uint32_t(options.search) | (std::min(options.search_depth, 255u) << 8));
  t[3] = bits(uint32_t(options.visibility) | (uint32_t(options.sequence) << 8));
  t[4] = bits(std::max(options.spp, 1u));
  t[5] = bits(options.kmax);
  t[6] = bits(options.seed);
  const bool by_cell =
      options.visibility == LuminaireVisibility::Cells || options.visibility == LuminaireVisibility::CellsOnU;
  uint64_t state = 0;  // the entries of a pixel's state (luminaire.glsl)
  for (uint32_t l = 0; l < count; ++l) {
    const LightField& field = *options.luminaires[l].field;
    validate_light_field(field);
    const LuminaireFrame frame = luminaire_frame(field, options.luminaires[l].placement);
    const uint32_t w = field.width, h = field.height, M = field.image_count();
    const uint32_t n = luminaire_basis_cells(field.basis);
    const glm::vec2 extent = field.extent * frame.scale;
    const double texel_area = double(extent.x) * extent.y / (double(w) * h);
    const uint64_t stride = (w + 1) + uint64_t(w) * (h + 1) + 3ull * w * h + 2ull * (w + 1) * (h + 1) + 3;
    const uint64_t images = t.size();
    const uint64_t cells = images + stride * M;
    const uint32_t cw = field.grid_w + n - 1, ch = field.grid_h + n - 1;
    const uint64_t image_cdf = cells + 2ull * cw * ch;
    const uint64_t end = image_cdf + M + 1;
    if (end >= (1ull << 32) / sizeof(float)) throw std::invalid_argument("luminaire: the light fields are too large");
    t.resize(end, 0.0f);
    float* b = &t[kHeader + kBlock * l];
    const glm::vec3 v[4] = {frame.centre, frame.x, frame.y, frame.z};
    for (int a = 0; a < 4; ++a) {
      b[4 * a + 0] = v[a].x;
      b[4 * a + 1] = v[a].y;
      b[4 * a + 2] = v[a].z;
    }
    b[3] = field.delta * frame.scale;
    b[7] = field.spacing * frame.scale;
    b[11] = bits(uint32_t(field.basis));
    b[15] = float(texel_area);
    b[16] = extent.x;
    b[17] = extent.y;
    b[18] = bits(w);
    b[19] = bits(h);
    b[20] = bits(field.grid_w);
    b[21] = bits(field.grid_h);
    b[22] = bits(uint32_t(images));
    b[23] = bits(uint32_t(stride));
    b[24] = bits(uint32_t(cells));
    b[26] = bits(uint32_t(image_cdf));
    b[27] = bits(n);
    b[28] = bits(uint32_t(state));
    state += 2 + (by_cell ? uint64_t(cw) * ch : 0);

    std::vector<double> energy(M, 0.0);
    std::vector<glm::vec2> half_way(M, glm::vec2(0.5f * w, 0.5f * h));
    std::vector<double> lum(size_t(w) * h), column(w), sat(size_t(w + 1) * (h + 1));
    for (uint32_t m = 0; m < M; ++m) {
      const std::vector<float>& image = field.images[m];
      float* o = &t[images + stride * m];
      float* marginal = o;
      float* cond = o + w + 1;
      float* colour = cond + uint64_t(w) * (h + 1);
      float* sat_hi = colour + 3ull * w * h;
      float* sat_lo = sat_hi + uint64_t(w + 1) * (h + 1);
      float* tail = sat_lo + uint64_t(w + 1) * (h + 1);
      for (size_t i = 0; i < lum.size(); ++i) {
        lum[i] = 0.2126 * image[3 * i] + 0.7152 * image[3 * i + 1] + 0.0722 * image[3 * i + 2];
        for (int c = 0; c < 3; ++c) colour[3 * i + c] = image[3 * i + c];
      }
      // Each column's CDF over rows; an empty column is uniform (never
      // drawn: no mass in the marginal). Every texel of luminance > 0 gets
      // at least kFloor of its column's mean texel, and every lit column
      // kFloor of the mean lit column, so that a float CDF near 1 still
      // rises over the dimmest texel (pdf > 0 wherever C_m > 0; the
      // estimator divides by the CDFs' own density, so this costs no bias).
      constexpr double kFloor = 1e-3;
      for (uint32_t x = 0; x < w; ++x) {
        double sum = 0.0;
        uint32_t lit = 0;
        for (uint32_t y = 0; y < h; ++y) {
          sum += lum[size_t(y) * w + x];
          lit += lum[size_t(y) * w + x] > 0.0 ? 1 : 0;
        }
        column[x] = sum;
        const double floor = lit ? kFloor * sum / lit : 0.0;
        double all_rows = 0.0;
        for (uint32_t y = 0; y < h; ++y)
          all_rows += lum[size_t(y) * w + x] > 0.0 ? std::max(lum[size_t(y) * w + x], floor) : 0.0;
        float* c = cond + uint64_t(x) * (h + 1);
        double run = 0.0;
        c[0] = 0.0f;
        for (uint32_t y = 0; y < h; ++y) {
          run += lum[size_t(y) * w + x] > 0.0 ? std::max(lum[size_t(y) * w + x], floor) : 0.0;
          c[y + 1] = all_rows > 0.0 ? float(run / all_rows) : float(y + 1) / float(h);
        }
        c[h] = 1.0f;
      }
      double total = 0.0;
      uint32_t lit_columns = 0;
      for (uint32_t x = 0; x < w; ++x) {
        total += column[x];
        lit_columns += column[x] > 0.0 ? 1 : 0;
      }
      const double column_floor = lit_columns ? kFloor * total / lit_columns : 0.0;
      double all_columns = 0.0;
      for (uint32_t x = 0; x < w; ++x) all_columns += column[x] > 0.0 ? std::max(column[x], column_floor) : 0.0;
      double run = 0.0;
      marginal[0] = 0.0f;
      for (uint32_t x = 0; x < w; ++x) {
        run += column[x] > 0.0 ? std::max(column[x], column_floor) : 0.0;
        marginal[x + 1] = all_columns > 0.0 ? float(run / all_columns) : float(x + 1) / float(w);
      }
      marginal[w] = 1.0f;
      // The summed-area table, in double, split into a coarse hi (a
      // multiple of the quantum q, below 2^13 q) and the rest.
      for (uint32_t y = 0; y <= h; ++y) {
        for (uint32_t x = 0; x <= w; ++x) {
          double s = 0.0;
          if (x > 0 && y > 0) {
            s = lum[size_t(y - 1) * w + (x - 1)] * texel_area + sat[size_t(y - 1) * (w + 1) + x] +
                sat[size_t(y) * (w + 1) + x - 1] - sat[size_t(y - 1) * (w + 1) + x - 1];
          }
          sat[size_t(y) * (w + 1) + x] = s;
        }
      }
      const double all = sat.back();
      const double q = all > 0.0 ? std::ldexp(1.0, std::ilogb(all) + 1 - 12) : 1.0;
      for (size_t i = 0; i < sat.size(); ++i) {
        const double hi = std::round(sat[i] / q) * q;
        sat_hi[i] = float(hi);
        sat_lo[i] = float(sat[i] - hi);
      }
      energy[m] = all;
      tail[0] = float(all);
      // The half-way point of both CDFs (section 6.2's reference position).
      if (total > 0.0) {
        uint32_t x = 0;
        while (x + 1 < w && marginal[x + 1] < 0.5f) ++x;
        const float fx = marginal[x + 1] > marginal[x] ? (0.5f - marginal[x]) / (marginal[x + 1] - marginal[x]) : 0.5f;
        const float* c = cond + uint64_t(x) * (h + 1);
        uint32_t y = 0;
        while (y + 1 < h && c[y + 1] < 0.5f) ++y;
        const float fy = c[y + 1] > c[y] ? (0.5f - c[y]) / (c[y + 1] - c[y]) : 0.5f;
        half_way[m] = glm::vec2(float(x) + std::clamp(fx, 0.0f, 1.0f), float(y) + std::clamp(fy, 0.0f, 1.0f));
      }
      tail[1] = half_way[m].x;
      tail[2] = half_way[m].y;
    }
    // Cells: the mean half-way point of the images whose basis overlaps them.
    for (uint32_t b2 = 0; b2 < ch; ++b2) {
      for (uint32_t a = 0; a < cw; ++a) {
        glm::vec2 sum(0.0f);
        uint32_t k = 0;
        for (uint32_t j = (b2 >= n - 1 ? b2 - (n - 1) : 0); j <= std::min(b2, field.grid_h - 1); ++j) {
          for (uint32_t i = (a >= n - 1 ? a - (n - 1) : 0); i <= std::min(a, field.grid_w - 1); ++i) {
            sum += half_way[j * field.grid_w + i];
            ++k;
          }
        }
        const glm::vec2 p = k ? sum / float(k) : glm::vec2(0.5f * w, 0.5f * h);
        t[cells + 2 * (uint64_t(b2) * cw + a)] = p.x;
        t[cells + 2 * (uint64_t(b2) * cw + a) + 1] = p.y;
      }
    }
    double all = 0.0;
    for (double e : energy) all += e;
    b[25] = float(all);
    double run = 0.0;
    t[image_cdf] = 0.0f;
    for (uint32_t m = 0; m < M; ++m) {
      run += energy[m];
      t[image_cdf + m + 1] = all > 0.0 ? float(run / all) : float(m + 1) / float(M);
    }
    t[image_cdf + M] = 1.0f;
  }
  t[7] = bits(uint32_t(state));
  return t;
}

}  // namespace svo::render
