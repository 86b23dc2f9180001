#include "svo/voxelizer/heightmap_scene.h"

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "common/shared_math.h"

namespace svo::voxelizer {

HeightMap read_height_map(const std::string& path, int size) {
  OIIO::ImageBuf image(path);
  if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    std::string why = image.geterror();
    throw std::runtime_error(path + ": cannot read: " + (why.empty() ? std::string("unknown error") : why));
  }
  const OIIO::ImageSpec& spec = image.spec();
  if (spec.width < 2 || spec.height < 2 || spec.nchannels < 1) {
    throw std::runtime_error(path + ": a height map needs at least 2x2 pixels, got " + std::to_string(spec.width) +
                             "x" + std::to_string(spec.height));
  }
  // The stored values, not decoded from sRGB: a height map is not a colour.
  std::vector<float> lum(size_t(spec.width) * size_t(spec.height));
  std::vector<float> pixel(size_t(spec.nchannels));
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
      image.getpixel(x + spec.x, y + spec.y, pixel.data(), spec.nchannels);
      float v = spec.nchannels >= 3 ? 0.2126f * pixel[0] + 0.7152f * pixel[1] + 0.0722f * pixel[2] : pixel[0];
      if (!std::isfinite(v))
        throw std::runtime_error(path + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite");
      lum[size_t(y) * size_t(spec.width) + size_t(x)] = v;
    }
  }
  const int longer = std::max(spec.width, spec.height);
  const int factor = size > 0 ? std::max(1, (longer + size - 1) / size) : 1;
  HeightMap map;
  map.width = std::max(2, spec.width / factor);
  map.height = std::max(2, spec.height / factor);
  map.values.assign(size_t(map.width) * size_t(map.height), 0.0f);
  // Output sample (i, j) averages the source block [x0, x1) x [y0, y1).
  auto range = [](int k, int out, int in) {
    int lo = int(int64_t(k) * in / out), hi = int(int64_t(k + 1) * in / out);
    return std::pair<int, int>{lo, std::max(hi, lo + 1)};
  };
  for (int j = 0; j < map.height; ++j) {
    auto [y0, y1] = range(j, map.height, spec.height);
    for (int i = 0; i < map.width; ++i) {
      auto [x0, x1] = range(i, map.width, spec.width);
      double sum = 0;
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) sum += lum[size_t(y) * size_t(spec.width) + size_t(x)];
      }
      // Row 0 of the map is the image's bottom row (y = -1).
      map.values[size_t(map.height - 1 - j) * size_t(map.width) + size_t(i)] =
          float(sum / double((y1 - y0) * (x1 - x0)));
    }
  }
  return map;
}

namespace {

// 2-point Gauss-Legendre nodes on [0, 1].
constexpr double kGauss[2] = {0.5 - 0.28867513459481287, 0.5 + 0.28867513459481287};

}  // namespace

HeightmapScene::HeightmapScene(HeightMap map, float amplitude, glm::vec3 abar, glm::vec3 a_s)
    : map_(std::move(map)), amplitude_(amplitude), abar_(abar), a_s_(a_s) {
  if (map_.width < 2 || map_.height < 2 || map_.values.size() != size_t(map_.width) * size_t(map_.height)) {
    throw std::invalid_argument("heightmap: needs at least 2x2 samples");
  }
  if (!(amplitude > 0) || !std::isfinite(amplitude)) {
    throw std::invalid_argument("heightmap: amplitude " + std::to_string(amplitude) + " is not > 0");
  }
  for (float& v : map_.values) v *= amplitude;
  // The area mean of the bilinear surface (exact with the Gauss points), then centred.
  double sum = 0;
  for (int cj = 0; cj + 1 < map_.height; ++cj) {
    for (int ci = 0; ci + 1 < map_.width; ++ci) {
      sum += 0.25 * (map_.at(ci, cj) + map_.at(ci + 1, cj) + map_.at(ci, cj + 1) + map_.at(ci + 1, cj + 1));
    }
  }
  const float mean = float(sum / double((map_.width - 1) * (map_.height - 1)));
  for (float& v : map_.values) v -= mean;
  sigma_h_ = 1.0f;  // statistics() needs a scale for s(h); the real one is set next
  SurfaceStatistics s = statistics(glm::vec2(-1), glm::vec2(1));
  sigma_h_ = float(std::sqrt(s.height_variance + s.mean_height * s.mean_height));
  // Lipschitz bound of max(z - H, sides, bottom): sqrt(1 + max |grad H|^2).
  const float dx = 2.0f / float(map_.width - 1), dy = 2.0f / float(map_.height - 1);
  float max_g2 = 0;
  for (int cj = 0; cj + 1 < map_.height; ++cj) {
    for (int ci = 0; ci + 1 < map_.width; ++ci) {
      float gx = std::max(std::abs(map_.at(ci + 1, cj) - map_.at(ci, cj)),
                          std::abs(map_.at(ci + 1, cj + 1) - map_.at(ci, cj + 1))) /
                 dx;
      float gy = std::max(std::abs(map_.at(ci, cj + 1) - map_.at(ci, cj)),
                          std::abs(map_.at(ci + 1, cj + 1) - map_.at(ci + 1, cj))) /
                 dy;
      max_g2 = std::max(max_g2, gx * gx + gy * gy);
    }
  }
  lipschitz_ = std::sqrt(1.0f + max_g2);
  for (float v : map_.values) max_height_ = std::max(max_height_, std::abs(v));
}

void HeightmapScene::locate(float x, float y, int& ci, int& cj, float& u, float& v) const {
  float fx = (std::clamp(x, -1.0f, 1.0f) + 1.0f) * 0.5f * float(map_.width - 1);
  float fy = (std::clamp(y, -1.0f, 1.0f) + 1.0f) * 0.5f * float(map_.height - 1);
  ci = std::min(int(fx), map_.width - 2);
  cj = std::min(int(fy), map_.height - 2);
  u = fx - float(ci);
  v = fy - float(cj);
}

float HeightmapScene::height(float x, float y) const {
  int ci, cj;
  float u, v;
  locate(x, y, ci, cj, u, v);
  float h00 = map_.at(ci, cj), h10 = map_.at(ci + 1, cj), h01 = map_.at(ci, cj + 1), h11 = map_.at(ci + 1, cj + 1);
  return (h00 * (1 - u) + h10 * u) * (1 - v) + (h01 * (1 - u) + h11 * u) * v;
}

glm::vec2 HeightmapScene::gradient(float x, float y) const {
  // Flat beyond the map's edges (the height is clamped there).
  int ci, cj;
  float u, v;
  locate(x, y, ci, cj, u, v);
  float h00 = map_.at(ci, cj), h10 = map_.at(ci + 1, cj), h01 = map_.at(ci, cj + 1), h11 = map_.at(ci + 1, cj + 1);
  const float sx = 0.5f * float(map_.width - 1), sy = 0.5f * float(map_.height - 1);
  glm::vec2 g(((h10 - h00) * (1 - v) + (h11 - h01) * v) * sx, ((h01 - h00) * (1 - u) + (h11 - h10) * u) * sy);
  if (std::abs(x) > 1.0f) g.x = 0;
  if (std::abs(y) > 1.0f) g.y = 0;
  return g;
}

SurfaceStatistics HeightmapScene::statistics(glm::vec2 lo, glm::vec2 hi) const {
  lo = glm::max(lo, glm::vec2(-1));
  hi = glm::min(hi, glm::vec2(1));
  if (!(hi.x > lo.x && hi.y > lo.y)) throw std::invalid_argument("heightmap statistics: empty region");
  const double dx = 2.0 / double(map_.width - 1), dy = 2.0 / double(map_.height - 1);
  // Gauss points of every cell that fall inside the region, each weighted by a quarter of the cell's area.
  struct Sample {
    double h, gx, gy;
  };
  std::vector<Sample> samples;
  for (int cj = 0; cj + 1 < map_.height; ++cj) {
    for (int ci = 0; ci + 1 < map_.width; ++ci) {
      for (double gv : kGauss) {
        for (double gu : kGauss) {
          double x = -1.0 + (ci + gu) * dx, y = -1.0 + (cj + gv) * dy;
          if (x < lo.x || x > hi.x || y < lo.y || y > hi.y) continue;
          glm::vec2 g = gradient(float(x), float(y));
          samples.push_back({height(float(x), float(y)), g.x, g.y});
        }
      }
    }
  }
  SurfaceStatistics s;
  if (samples.empty()) throw std::invalid_argument("heightmap statistics: the region holds no sample");
  const double n = double(samples.size());
  s.area = n * 0.25 * dx * dy;
  glm::dvec2 mean_g(0);
  for (const auto& p : samples) s.mean_height += p.h / n, mean_g += glm::dvec2(p.gx, p.gy) / n;
  double m2 = 0, m3 = 0, m4 = 0;
  for (const auto& p : samples) {
    double d = p.h - s.mean_height;
    m2 += d * d / n, m3 += d * d * d / n, m4 += d * d * d * d / n;
    s.slope_variance += glm::dvec2((p.gx - mean_g.x) * (p.gx - mean_g.x), (p.gy - mean_g.y) * (p.gy - mean_g.y)) / n;
  }
  s.height_variance = m2;
  s.skewness = m2 > 0 ? m3 / std::pow(m2, 1.5) : 0.0;
  s.excess_kurtosis = m2 > 0 ? m4 / (m2 * m2) - 3.0 : 0.0;
  // Colour: a(h) = abar + a_s s(h); abar its mean, a_s = sum s (a - abar) / sum s^2.
  glm::dvec3 num(0);
  double den = 0;
  for (const auto& p : samples) {
    double sh = svo::math::svo_height_sigmoid(float(p.h), sigma_h_);
    s.abar += (glm::dvec3(abar_) + glm::dvec3(a_s_) * sh) / n;
  }
  for (const auto& p : samples) {
    double sh = svo::math::svo_height_sigmoid(float(p.h), sigma_h_);
    glm::dvec3 a = glm::dvec3(abar_) + glm::dvec3(a_s_) * sh;
    num += sh * (a - s.abar);
    den += sh * sh;
  }
  s.a_s = den > 0 ? num / den : glm::dvec3(0);
  return s;
}

// max(z - H(x, y), sides, bottom), as HeightfieldScene: Lipschitz with
// sqrt(1 + max |grad H|^2); the voxelizer projects onto the zero set.
glm::vec4 HeightmapScene::distance_gradient(glm::vec3 p) const {
  glm::vec2 g = gradient(p.x, p.y);
  glm::vec4 best(-g.x, -g.y, 1.0f, p.z - height(p.x, p.y));
  float side_x = std::abs(p.x) - 1.0f, side_y = std::abs(p.y) - 1.0f, bottom = kBottom - p.z;
  if (side_x > best.w) best = glm::vec4(p.x < 0 ? -1.0f : 1.0f, 0, 0, side_x);
  if (side_y > best.w) best = glm::vec4(0, p.y < 0 ? -1.0f : 1.0f, 0, side_y);
  if (bottom > best.w) best = glm::vec4(0, 0, -1.0f, bottom);
  return best;
}

glm::vec3 HeightmapScene::colour(glm::vec3 q) const {
  return abar_ + a_s_ * svo::math::svo_height_sigmoid(height(q.x, q.y), sigma_h_);
}

Box HeightmapScene::bounds() const {
  float top = std::max(-kBottom, max_height_ + 0.01f);
  return {glm::vec3(-1.0f, -1.0f, -top), glm::vec3(1.0f, 1.0f, top)};
}

}  // namespace svo::voxelizer
