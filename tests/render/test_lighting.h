// An environment map for the lighting tests: a blue sky over a dark ground,
// a small sun-like patch (radiance 40), a band of black rows below the
// horizon and black poles (the empty rows a sampler must never draw from),
// unless `black_rows` is false (pictures compared by relMSE, which a black
// background seen through different footprints would dominate).
#pragma once

#include <cmath>

#include "svo/render/merl.h"
#include "svo/render/shading.h"

namespace svo::test {

inline render::Environment sky(uint32_t w = 64, uint32_t h = 32, bool black_rows = true) {
  render::Environment env;
  env.width = w;
  env.height = h;
  env.source = "test-sky";
  env.rgb.resize(size_t(w) * h * 3);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      glm::vec3 c = y < h / 2 ? glm::vec3(0.3f, 0.5f, 0.9f) : glm::vec3(0.1f, 0.08f, 0.05f);
      if (black_rows && y >= h / 2 && y < h / 2 + 2) c = glm::vec3(0);  // empty rows
      if (black_rows && (y == 0 || y == h - 1)) c = glm::vec3(0);       // black poles
      if (x >= w / 4 && x < w / 4 + 3 && y >= h / 5 && y < h / 5 + 2) c = glm::vec3(40.0f, 36.0f, 30.0f);
      for (int k = 0; k < 3; ++k) env.rgb[(size_t(y) * w + x) * 3 + k] = c[k];
    }
  }
  render::validate_environment(env);
  return env;
}

// A latitude-longitude map of `stripes` bright (2) and dark (0.1) stripes
// in longitude: high angular frequencies everywhere.
inline render::Environment stripes(uint32_t stripes, uint32_t w = 256, uint32_t h = 128) {
  render::Environment env;
  env.width = w;
  env.height = h;
  env.source = "test-stripes";
  env.rgb.resize(size_t(w) * h * 3);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k) env.rgb[(size_t(y) * w + x) * 3 + k] = (x * 2 * stripes / w) % 2 ? 2.0f : 0.1f;
  render::validate_environment(env);
  return env;
}

// A measured material: a MERL table of one half-vector SG of the given
// sharpness and amplitude over a Lambert floor `floor` / pi (grey), its
// diffuse part 0 (the table holds all of it).
inline render::Material sg_merl_material(double sharpness, double amplitude, double floor) {
  render::Material m;
  m.name = "sg-merl";
  m.kind = render::BrdfKind::Merl;
  m.diffuse = glm::vec3(0.0f);
  m.merl = std::make_shared<const render::MerlBrdf>(render::tabulate_merl([=](glm::dvec3 wi, glm::dvec3 wo) {
    const glm::dvec3 h = glm::normalize(wi + wo);
    return glm::dvec3(floor / M_PI + amplitude * std::exp(sharpness * (h.z - 1)));
  }));
  return m;
}

}  // namespace svo::test
