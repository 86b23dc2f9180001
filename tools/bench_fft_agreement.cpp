#include "bench_fft_agreement.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "svo/render/bandwidth.h"

namespace svo::tools::bench {

namespace {

constexpr uint32_t kWindow = 32;  // the FFT's window, pixels
constexpr uint32_t kStride = 8;   // between the FFT's window centres

bool covered(float c) { return c >= 0.999f; }

// A summed-area table of `f(i)` over a size x size image: (size + 1)^2.
template <class F>
std::vector<double> summed_area(uint32_t size, F f) {
  const size_t w = size + 1;
  std::vector<double> s(w * w, 0.0);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x)
      s[(y + 1) * w + x + 1] = f(size_t(y) * size + x) + s[y * w + x + 1] + s[(y + 1) * w + x] - s[y * w + x];
  return s;
}

double box_sum(const std::vector<double>& s, uint32_t size, size_t x0, size_t y0, size_t x1, size_t y1) {
  const size_t w = size + 1;
  return s[y1 * w + x1] - s[y0 * w + x1] - s[y1 * w + x0] + s[y0 * w + x0];
}

}  // namespace

double rank_correlation(const std::vector<double>& x, const std::vector<double>& y) {
  auto ranks = [](const std::vector<double>& v) {
    std::vector<size_t> idx(v.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
    std::vector<double> r(v.size());
    for (size_t i = 0; i < idx.size();) {
      size_t j = i;
      while (j + 1 < idx.size() && v[idx[j + 1]] == v[idx[i]]) ++j;
      for (size_t k = i; k <= j; ++k) r[idx[k]] = 0.5 * double(i + j);
      i = j + 1;
    }
    return r;
  };
  const auto rx = ranks(x), ry = ranks(y);
  const double mx = std::accumulate(rx.begin(), rx.end(), 0.0) / double(rx.size());
  const double my = std::accumulate(ry.begin(), ry.end(), 0.0) / double(ry.size());
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < rx.size(); ++i) {
    sxy += (rx[i] - mx) * (ry[i] - my);
    sxx += (rx[i] - mx) * (rx[i] - mx);
    syy += (ry[i] - my) * (ry[i] - my);
  }
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0;
}

std::vector<double> window_mean(const std::vector<float>& v, const std::vector<float>& coverage, uint32_t size,
                                uint32_t window) {
  const auto sum = summed_area(size, [&](size_t i) { return covered(coverage[i]) ? double(v[i]) : 0.0; });
  const auto count = summed_area(size, [&](size_t i) { return covered(coverage[i]) ? 1.0 : 0.0; });
  const int half = int(window / 2);
  std::vector<double> out(size_t(size) * size, 0.0);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const size_t x0 = size_t(std::max(int(x) - half, 0)), x1 = std::min<size_t>(x + half, size);
      const size_t y0 = size_t(std::max(int(y) - half, 0)), y1 = std::min<size_t>(y + half, size);
      const double c = box_sum(count, size, x0, y0, x1, y1);
      out[size_t(y) * size + x] = c > 0 ? box_sum(sum, size, x0, y0, x1, y1) / c : 0.0;
    }
  return out;
}

FftAgreement fft_agreement(const render::Frame& image, const std::vector<float>& bp,
                           const std::vector<double>& bp_window, const std::vector<float>& coverage, uint32_t size) {
  const size_t n = size_t(size) * size;
  std::vector<float> lum(n);
  for (size_t i = 0; i < n; ++i)
    lum[i] = 0.2126f * image.colour[i].r + 0.7152f * image.colour[i].g + 0.0722f * image.colour[i].b;
  const std::vector<float> fft = render::windowed_fft_bandwidth(lum, size, size, kWindow, kStride);
  FftAgreement r;
  r.shown.assign(n, -1);
  std::vector<double> xs, ys, xw;
  for (size_t i = 0; i < n; ++i) {
    if (!covered(coverage[i])) continue;
    r.shown[i] = fft[i];
    xs.push_back(bp[i]);
    ys.push_back(fft[i]);
    xw.push_back(bp_window[i]);
  }
  r.rho = rank_correlation(xs, ys);
  r.rho_window = rank_correlation(xw, ys);
  // Pixels whose whole window is covered surface: no silhouette and no
  // background in the FFT's window.
  const auto open = summed_area(size, [&](size_t i) { return covered(coverage[i]) ? 0.0 : 1.0; });
  const uint32_t half = kWindow / 2;
  std::vector<double> xi, yi;
  for (uint32_t y = half; y + half < size; ++y)
    for (uint32_t x = half; x + half < size; ++x) {
      if (box_sum(open, size, x - half, y - half, x + half, y + half) != 0) continue;
      xi.push_back(bp[size_t(y) * size + x]);
      yi.push_back(fft[size_t(y) * size + x]);
    }
  r.rho_interior = xi.size() > 2 ? rank_correlation(xi, yi) : 0.0;
  r.interior = xi.size();
  return r;
}

}  // namespace svo::tools::bench
