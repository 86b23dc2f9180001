// Light-field luminaires: the basis on U, the radiance of the model, the
// procedural emitters and the flux (luminaire.h). The file is
// luminaire_file.cpp, the TM-25 import tm25.cpp.
#include "svo/render/luminaire.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

namespace svo::render {

const char* luminaire_basis_name(LuminaireBasis basis) {
  return basis == LuminaireBasis::BSpline ? "bspline" : "quadratic";
}

uint32_t luminaire_basis_cells(LuminaireBasis basis) { return basis == LuminaireBasis::BSpline ? 3u : 2u; }

float luminaire_basis_phi(LuminaireBasis basis, float x) {
  const float a = std::fabs(x);
  if (basis == LuminaireBasis::Quadratic) return a < 1.0f ? 1.0f - a * a : 0.0f;
  if (a < 0.5f) return 0.75f - a * a;
  if (a < 1.5f) return 0.5f * (1.5f - a) * (1.5f - a);
  return 0.0f;
}

glm::vec2 LightField::basis_centre(uint32_t m) const {
  const uint32_t i = m % grid_w;
  const uint32_t j = m / grid_w;
  return {(float(i) - 0.5f * float(grid_w - 1)) * spacing, (float(j) - 0.5f * float(grid_h - 1)) * spacing};
}

float LightField::basis_value(uint32_t m, glm::vec2 u) const {
  const glm::vec2 x = (u - basis_centre(m)) / spacing;
  return luminaire_basis_phi(basis, x.x) * luminaire_basis_phi(basis, x.y);
}

void LightField::basis_support(uint32_t m, glm::vec2& lo, glm::vec2& hi) const {
  const float half = 0.5f * float(luminaire_basis_cells(basis)) * spacing;
  lo = basis_centre(m) - half;
  hi = basis_centre(m) + half;
}

glm::vec3 LightField::radiance(glm::vec2 u, glm::vec2 s) const {
  const glm::vec2 f = (s / extent + 0.5f) * glm::vec2(float(width), float(height));
  if (!(f.x >= 0.0f && f.y >= 0.0f && f.x < float(width) && f.y < float(height))) return glm::vec3(0.0f);
  const size_t texel = size_t(uint32_t(f.y)) * width + uint32_t(f.x);
  glm::vec3 sum(0.0f);
  for (uint32_t m = 0; m < image_count(); ++m) {
    const float phi = basis_value(m, u);
    if (phi <= 0.0f) continue;
    const float* c = &images[m][3 * texel];
    sum += phi * glm::vec3(c[0], c[1], c[2]);
  }
  return sum;
}

namespace {

LightField blank_field(uint32_t resolution, uint32_t grid, const std::string& source) {
  if (resolution < 1 || resolution > LightField::kMaxImageSide) {
    throw std::invalid_argument("luminaire: the resolution must be 1 to " + std::to_string(LightField::kMaxImageSide) +
                                ", not " + std::to_string(resolution));
  }
  if (grid < 1 || grid > LightField::kMaxGridSide) {
    throw std::invalid_argument("luminaire: the grid must be 1 to " + std::to_string(LightField::kMaxGridSide) +
                                " basis functions across, not " + std::to_string(grid));
  }
  // The loader's limit over all images (it would refuse the file).
  const uint64_t texels = uint64_t(resolution) * resolution * grid * grid;
  if (texels > LightField::kMaxTexels) {
    throw std::invalid_argument("luminaire: " + std::to_string(grid * grid) + " images of " +
                                std::to_string(resolution) + " x " + std::to_string(resolution) + " are " +
                                std::to_string(texels) + " texels, more than the limit of " +
                                std::to_string(LightField::kMaxTexels));
  }
  LightField f;
  f.width = f.height = resolution;
  f.grid_w = f.grid_h = grid;
  f.extent = glm::vec2(0.1f);  // 10 cm across
  f.delta = 0.05f;
  // The basis grid covers about as much of U as S covers of S.
  f.spacing = 0.1f / float(grid);
  f.basis = LuminaireBasis::BSpline;
  f.units = "m";
  f.metres_per_unit = 1.0f;
  f.source = source;
  f.images.assign(f.image_count(), std::vector<float>(size_t(resolution) * resolution * 3, 0.0f));
  return f;
}

}  // namespace

LightField make_panel_luminaire(uint32_t resolution, uint32_t grid, float radiance, uint32_t checks) {
  if (!(radiance > 0.0f) || !std::isfinite(radiance))
    throw std::invalid_argument("luminaire: the radiance must be > 0");
  checks = std::max(checks, 1u);
  LightField f = blank_field(resolution, grid,
                             "panel: " + std::to_string(checks) + "x" + std::to_string(checks) + " checker, radiance " +
                                 std::to_string(radiance));
  for (uint32_t y = 0; y < resolution; ++y) {
    for (uint32_t x = 0; x < resolution; ++x) {
      const bool bright = ((x * checks / resolution) + (y * checks / resolution)) % 2 == 0;
      const glm::vec3 c = radiance * (bright ? glm::vec3(1.0f, 0.95f, 0.85f) : glm::vec3(0.25f, 0.3f, 0.4f));
      for (auto& image : f.images) {
        float* t = &image[3 * (size_t(y) * resolution + x)];
        t[0] = c.x;
        t[1] = c.y;
        t[2] = c.z;
      }
    }
  }
  return f;
}

LightField make_headlight_luminaire(uint32_t resolution, uint32_t grid, float radiance, float beam, float focus) {
  if (!(radiance > 0.0f) || !std::isfinite(radiance))
    throw std::invalid_argument("luminaire: the radiance must be > 0");
  if (!(beam > 0.0f) || !(focus > 0.0f)) throw std::invalid_argument("luminaire: the beam width and focus must be > 0");
  LightField f = blank_field(resolution, grid,
                             "headlight: beam " + std::to_string(beam) + ", focus " + std::to_string(focus) + " m");
  const float sigma = beam * f.extent.x;
  for (uint32_t m = 0; m < f.image_count(); ++m) {
    // The ray from basis centre c (z = 0) to the focus (0, 0, delta + focus)
    // crosses S (z = delta) at c (1 - delta / (delta + focus)).
    const glm::vec2 c = f.basis_centre(m) * (1.0f - f.delta / (f.delta + focus));
    // A warm core and a bluish rim, as a reflector's colour fringes.
    for (uint32_t y = 0; y < resolution; ++y) {
      for (uint32_t x = 0; x < resolution; ++x) {
        const glm::vec2 s = (glm::vec2(float(x), float(y)) + 0.5f) / float(resolution) * f.extent - 0.5f * f.extent;
        const float r2 = glm::dot(s - c, s - c) / (sigma * sigma);
        const float core = std::exp(-0.5f * r2);
        const float rim = 0.15f * std::exp(-0.5f * r2 / 6.0f);
        float* t = &f.images[m][3 * (size_t(y) * resolution + x)];
        t[0] = radiance * (core + 0.6f * rim);
        t[1] = radiance * (0.92f * core + 0.8f * rim);
        t[2] = radiance * (0.75f * core + 1.0f * rim);
      }
    }
  }
  return f;
}

LightField make_led_luminaire(uint32_t resolution, uint32_t grid, float radiance, uint32_t leds, float die,
                              float focus) {
  if (!(radiance > 0.0f) || !std::isfinite(radiance))
    throw std::invalid_argument("luminaire: the radiance must be > 0");
  if (!(die > 0.0f) || !(focus > 0.0f)) throw std::invalid_argument("luminaire: the die width and focus must be > 0");
  if (leds < 1 || leds > 8) throw std::invalid_argument("luminaire: 1 to 8 dies across, not " + std::to_string(leds));
  LightField f = blank_field(resolution, grid,
                             "led: " + std::to_string(leds) + "x" + std::to_string(leds) + " dies of " +
                                 std::to_string(die) + ", foci " + std::to_string(focus) + " m ahead");
  const float sigma = die * f.extent.x;
  for (uint32_t m = 0; m < f.image_count(); ++m) {
    const glm::vec2 c = f.basis_centre(m);
    for (uint32_t k = 0; k < leds * leds; ++k) {
      // Die k's focus lies beside the axis, the dies' foci 0.6 extents apart:
      // together they light a pattern of spots ahead.
      const glm::vec2 g = (glm::vec2(float(k % leds), float(k / leds)) - 0.5f * float(leds - 1)) * 0.6f * f.extent.x;
      const glm::vec2 spot = c + (g - c) * (f.delta / (f.delta + focus));
      // Cool white dies, a little warmer towards the array's edge.
      const float warm = float(k % leds) / float(std::max(leds - 1, 1u));
      const glm::vec3 tint(0.9f + 0.1f * warm, 0.95f, 1.0f - 0.15f * warm);
      for (uint32_t y = 0; y < resolution; ++y) {
        for (uint32_t x = 0; x < resolution; ++x) {
          const glm::vec2 s = (glm::vec2(float(x), float(y)) + 0.5f) / float(resolution) * f.extent - 0.5f * f.extent;
          const float r2 = glm::dot(s - spot, s - spot) / (sigma * sigma);
          if (r2 > 30.0f) continue;
          const float v = radiance * std::exp(-0.5f * r2);
          float* t = &f.images[m][3 * (size_t(y) * resolution + x)];
          t[0] += v * tint.x;
          t[1] += v * tint.y;
          t[2] += v * tint.z;
        }
      }
    }
  }
  return f;
}

double light_field_flux(const LightField& field, uint32_t samples_per_texel) {
  // dPhi = L cos^2(theta) dA_u dA_s / r^2 = L cos^4(theta) / delta^2 dA_u dA_s.
  const uint32_t k = std::max(samples_per_texel, 1u);
  const glm::dvec2 texel = glm::dvec2(field.extent) / glm::dvec2(field.width, field.height);
  const double d2 = double(field.delta) * field.delta;
  const uint32_t cells = luminaire_basis_cells(field.basis);
  const uint32_t nu = cells * 4;  // quadrature points per axis of each basis support
  double flux = 0.0;
  for (uint32_t m = 0; m < field.image_count(); ++m) {
    glm::vec2 lo, hi;
    field.basis_support(m, lo, hi);
    const glm::dvec2 du = glm::dvec2(hi - lo) / double(nu);
    for (uint32_t y = 0; y < field.height; ++y) {
      for (uint32_t x = 0; x < field.width; ++x) {
        const float* c = &field.images[m][3 * (size_t(y) * field.width + x)];
        const double lum = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        if (lum <= 0.0) continue;
        double sum = 0.0;
        for (uint32_t sy = 0; sy < k; ++sy) {
          for (uint32_t sx = 0; sx < k; ++sx) {
            const glm::dvec2 s =
                (glm::dvec2(x, y) + (glm::dvec2(sx, sy) + 0.5) / double(k)) * texel - 0.5 * glm::dvec2(field.extent);
            for (uint32_t j = 0; j < nu; ++j) {
              for (uint32_t i = 0; i < nu; ++i) {
                const glm::dvec2 u = glm::dvec2(lo) + (glm::dvec2(i, j) + 0.5) * du;
                const double phi = field.basis_value(m, glm::vec2(u));
                if (phi <= 0.0) continue;
                const glm::dvec2 d = s - u;
                const double r2 = glm::dot(d, d) + d2;
                sum += phi * d2 / (r2 * r2);  // cos^4 / delta^2 = delta^2 / r^4
              }
            }
          }
        }
        flux += lum * sum * du.x * du.y * texel.x * texel.y / double(k * k);
      }
    }
  }
  return flux;
}

}  // namespace svo::render
