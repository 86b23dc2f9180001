// The environment pre-convolved with normalised spherical Gaussians and
// the clamped cosine (shading.h, PreconvolvedEnvironment).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "svo/render/shading.h"

namespace svo::render {

namespace {

constexpr float kSharpest = 4096.0f;

// A latitude-longitude map and its texels' directions: row y at polar angle
// pi (y + 1/2) / height, column x at longitude 2 pi (x + 1/2) / width.
struct LatLong {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;
  std::vector<float> cos_theta, sin_theta;  // per row
  void directions() {
    cos_theta.resize(height);
    sin_theta.resize(height);
    for (uint32_t y = 0; y < height; ++y) {
      const double theta = M_PI * (y + 0.5) / height;
      cos_theta[y] = float(std::cos(theta));
      sin_theta[y] = float(std::sin(theta));
    }
  }
};

// The overlaps of n target cells with m source cells over the same span:
// for each target cell, (source index, share of the source cell inside it).
std::vector<std::vector<std::pair<uint32_t, double>>> overlaps(uint32_t m, uint32_t n) {
  std::vector<std::vector<std::pair<uint32_t, double>>> out(n);
  for (uint32_t t = 0; t < n; ++t) {
    const double a = double(t) * m / n, b = double(t + 1) * m / n;
    for (uint32_t s = uint32_t(a); s < m && double(s) < b; ++s) {
      const double share = std::min(b, double(s + 1)) - std::max(a, double(s));
      if (share > 1e-12) out[t].push_back({s, share});
    }
  }
  return out;
}

// The map resampled to width x height (at most its own) by area: each
// target texel the mean of the source over its extent, weighted by solid
// angle (sin theta), so that a bright texel keeps its place.
LatLong resample(const Environment& env, uint32_t width, uint32_t height) {
  const auto across = overlaps(env.width, width), down = overlaps(env.height, height);
  std::vector<double> rows(size_t(env.height) * width * 3, 0.0);  // columns resampled
  for (uint32_t y = 0; y < env.height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      double total = 0;
      for (const auto& [s, share] : across[x]) {
        for (int k = 0; k < 3; ++k)
          rows[(size_t(y) * width + x) * 3 + k] += share * env.rgb[(size_t(y) * env.width + s) * 3 + k];
        total += share;
      }
      for (int k = 0; k < 3; ++k) rows[(size_t(y) * width + x) * 3 + k] /= total;
    }
  LatLong out;
  out.width = width;
  out.height = height;
  out.rgb.assign(size_t(width) * height * 3, 0.0f);
  for (uint32_t y = 0; y < height; ++y) {
    double total = 0;
    std::vector<double> sum(size_t(width) * 3, 0.0);
    for (const auto& [s, share] : down[y]) {
      const double w = share * std::sin(M_PI * (s + 0.5) / env.height);
      for (size_t i = 0; i < sum.size(); ++i) sum[i] += w * rows[size_t(s) * width * 3 + i];
      total += w;
    }
    for (size_t i = 0; i < sum.size(); ++i) out.rgb[size_t(y) * width * 3 + i] = float(sum[i] / total);
  }
  out.directions();
  return out;
}

// One level: `src` convolved with the kernel k(cos) (> 0 only where cos >
// cos_max), normalised by the kernel's sum, on src's own grid. The weights
// of a pair of rows depend only on the columns' difference, so they are
// tabled once per pair and the columns run over a row padded with its wrap.
template <class Kernel>
PreconvolvedEnvironment::Level convolve(const LatLong& src, float sharpness, double cos_max, Kernel kernel) {
  const uint32_t width = src.width, height = src.height;
  PreconvolvedEnvironment::Level level;
  level.width = width;
  level.height = height;
  level.sharpness = sharpness;
  level.rgb.assign(size_t(width) * height * 3, 0.0f);
  const double theta_max = std::acos(std::clamp(cos_max, -1.0, 1.0));
  const double dphi = 2.0 * M_PI / width;
  const int half_width = int(width / 2);
  // Each row padded by half its width on both sides (the wrap).
  const size_t padded = size_t(width) + 2 * size_t(half_width) + 1;
  std::vector<float> rows(size_t(height) * padded * 3);
  for (uint32_t j = 0; j < height; ++j)
    for (size_t i = 0; i < padded; ++i) {
      const size_t x = (i + size_t(width) * 4 - size_t(half_width)) % width;
      for (int k = 0; k < 3; ++k) rows[(j * padded + i) * 3 + k] = src.rgb[(size_t(j) * width + x) * 3 + k];
    }
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, height), [&](const tbb::blocked_range<uint32_t>& range) {
    std::vector<double> sum(size_t(width) * 3);
    std::vector<float> weights;
    for (uint32_t y = range.begin(); y != range.end(); ++y) {
      const double theta = M_PI * (y + 0.5) / height;
      const double co = src.cos_theta[y], so = src.sin_theta[y];
      const int first = std::max(0, int(std::floor((theta - theta_max) / M_PI * height)) - 1);
      const int last = std::min(int(height) - 1, int(std::ceil((theta + theta_max) / M_PI * height)) + 1);
      std::fill(sum.begin(), sum.end(), 0.0);
      double total = 0;
      for (int j = first; j <= last; ++j) {
        const double cj = src.cos_theta[j], sj = src.sin_theta[j];
        // The column offsets within the support: cos(k dphi) >= (cos_max - co cj) / (so sj).
        const double c = (cos_max - co * cj) / std::max(so * sj, 1e-300);
        if (c > 1.0) continue;
        const int reach = c <= -1.0 ? half_width : std::min(half_width, int(std::ceil(std::acos(c) / dphi)) + 1);
        weights.assign(size_t(2 * reach + 1), 0.0f);
        for (int k = -reach; k <= reach; ++k) {
          // Offsets past half the width come round the other way: once only.
          if (2 * half_width == int(width) && k == half_width && reach == half_width) continue;
          const double d = co * cj + so * sj * std::cos(k * dphi);
          if (d > cos_max) weights[size_t(k + reach)] = float(kernel(d) * sj);
        }
        double row_total = 0;
        for (float w : weights) row_total += w;
        if (!(row_total > 0)) continue;
        total += row_total;
        const float* row = &rows[size_t(j) * padded * 3];
        for (uint32_t x = 0; x < width; ++x) {
          const float* at = row + (size_t(x) + size_t(half_width) - size_t(reach)) * 3;
          float r = 0, g = 0, b = 0;
          for (size_t k = 0; k < weights.size(); ++k) {
            r += weights[k] * at[3 * k];
            g += weights[k] * at[3 * k + 1];
            b += weights[k] * at[3 * k + 2];
          }
          sum[3 * x] += r, sum[3 * x + 1] += g, sum[3 * x + 2] += b;
        }
      }
      // Every column of a row has the same weights, hence the same total.
      float* o = &level.rgb[size_t(y) * width * 3];
      for (size_t i = 0; i < size_t(width) * 3; ++i) o[i] = total > 0 ? float(sum[i] / total) : 0.0f;
    }
  });
  return level;
}

}  // namespace

PreconvolvedEnvironment preconvolve_environment(const Environment& env) {
  validate_environment(env);
  PreconvolvedEnvironment pre;
  // A level of sharpness lambda has about two texels per lobe deviation
  // 1/sqrt(lambda): 4 pi sqrt(lambda) across, at least 8, at most the
  // map's; the map is resampled to it by area and convolved there. The
  // kernel is cut where it falls under e^-9.2 = 1e-4 of its peak. The
  // sharpest level is 4096 (a deviation of 0.9 degrees): a Phong lobe of
  // exponent e reflects with sharpness e / (4 n.v), so that is a mirror.
  auto size_for = [&](double across) {
    const uint32_t w = std::min(env.width, std::max(8u, uint32_t(std::ceil(across))));
    const uint32_t h = std::min(env.height, std::max(4u, (w + 1) / 2));
    return std::pair<uint32_t, uint32_t>{w, h};
  };
  for (float lambda = 1.0f;; lambda *= 2.0f) {
    const auto [w, h] = size_for(4.0 * M_PI * std::sqrt(double(lambda)));
    const double cos_max = std::max(-1.0, 1.0 - 9.2 / lambda);
    pre.levels.push_back(convolve(resample(env, w, h), lambda, cos_max - 1e-9,
                                  [lambda](double d) { return std::exp(double(lambda) * (d - 1.0)); }));
    if (w >= env.width || lambda >= kSharpest) break;
  }
  // The clamped cosine: as smooth as the SG of sharpness 2 (the diffuse
  // lobe's fit is 2.133).
  const auto [w, h] = size_for(4.0 * M_PI * std::sqrt(2.0));
  pre.irradiance = convolve(resample(env, w, h), 0.0f, 0.0, [](double d) { return d; });
  return pre;
}

}  // namespace svo::render
