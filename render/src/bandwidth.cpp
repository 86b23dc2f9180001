#include "svo/render/bandwidth.h"

#include <fftw3.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/geometric.hpp>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace svo::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A pixel whose wavelet energy is below (kConstantFloor x the largest
// amplitude)^2 is locally constant: the rounding of the box sums is ~1e-7 of it.
constexpr double kConstantFloor = 1e-5;

[[noreturn]] void bad(const char* fn, const std::string& why) {
  throw std::invalid_argument(std::string(fn) + ": " + why);
}

void check_image(std::span<const float> image, uint32_t width, uint32_t height, const char* fn) {
  if (width == 0 || height == 0 || image.empty()) {
    bad(fn, "empty image (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
                std::to_string(image.size()) + " values)");
  }
  if (image.size() != size_t(width) * height) {
    bad(fn, std::to_string(image.size()) + " values for a " + std::to_string(width) + "x" + std::to_string(height) +
                " image (" + std::to_string(size_t(width) * height) + " expected)");
  }
  for (size_t i = 0; i < image.size(); ++i) {
    if (!std::isfinite(image[i])) {
      bad(fn, std::string(std::isnan(image[i]) ? "NaN" : "Inf") + " at pixel (" + std::to_string(i % width) + ", " +
                  std::to_string(i / width) + ")");
    }
  }
}

// Sum of v[clamp(t, 0, n - 1)] over t in [lo, lo + len): v given by its
// prefix sums P[0..n] (P[k] at p[k * stride]); edge replication.
double clamped_sum(const double* p, size_t stride, int64_t n, int64_t lo, int64_t len) {
  const int64_t hi = lo + len;
  double s = 0.0;
  if (lo < 0) s += double(std::min<int64_t>(hi, 0) - lo) * (p[stride] - p[0]);
  if (hi > n) s += double(hi - std::max<int64_t>(lo, n)) * (p[size_t(n) * stride] - p[size_t(n - 1) * stride]);
  const int64_t a = std::clamp<int64_t>(lo, 0, n), b = std::clamp<int64_t>(hi, 0, n);
  if (b > a) s += p[size_t(b) * stride] - p[size_t(a) * stride];
  return s;
}

// Sum of v[t mod n] over t in [lo, lo + len), v given by its prefix sums.
double periodic_sum(const double* p, size_t stride, int64_t n, int64_t lo, int64_t len) {
  const int64_t start = ((lo % n) + n) % n, q = len / n, r = len % n;
  double s = double(q) * p[size_t(n) * stride];
  if (start + r <= n) {
    s += p[size_t(start + r) * stride] - p[size_t(start) * stride];
  } else {
    s += (p[size_t(n) * stride] - p[size_t(start) * stride]) + p[size_t(start + r - n) * stride];
  }
  return s;
}

double line_sum(const double* p, size_t stride, int64_t n, int64_t lo, int64_t len, bool wrap) {
  return wrap ? periodic_sum(p, stride, n, lo, len) : clamped_sum(p, stride, n, lo, len);
}

// The per-pixel energy of one band (Haar support s = 2^level) averaged over
// the band's shifts (wavelet_bandwidth's contract), added to `energy`
// (width * height); returns the band's largest amplitude.
double band_energy(const std::vector<float>& f, int64_t w, int64_t h, int64_t s, bool wrap, float* energy) {
  const int64_t half = s / 2;
  // Wavelet origins (top-left corners) whose support covers a pixel.
  const int64_t ox0 = wrap ? 0 : -(s - 1), nox = wrap ? w : w + s - 1;
  const int64_t oy0 = -(s - 1), noy = h + s - 1;
  // Half-width row sums at the corners ox and ox + half, as column prefix sums.
  const int64_t nx = wrap ? w : nox + half;
  std::vector<double> row_prefix(size_t(w) + 1);
  std::vector<double> col_prefix(size_t(h + 1) * size_t(nx), 0.0);
  for (int64_t y = 0; y < h; ++y) {
    for (int64_t x = 0; x < w; ++x) row_prefix[size_t(x + 1)] = row_prefix[size_t(x)] + f[size_t(y * w + x)];
    const double* above = &col_prefix[size_t(y * nx)];
    double* here = &col_prefix[size_t((y + 1) * nx)];
    for (int64_t k = 0; k < nx; ++k) here[k] = above[k] + line_sum(row_prefix.data(), 1, w, ox0 + k, half, wrap);
  }
  auto quadrant = [&](int64_t oy, int64_t ox) {  // the half x half sum at (ox, oy)
    const int64_t k = wrap ? ((ox % w) + w) % w : ox - ox0;
    return clamped_sum(&col_prefix[size_t(k)], size_t(nx), h, oy, half);
  };
  // Squared amplitudes summed over the box of origins covering each pixel:
  // along x into boxed (noy x w), then along y into `energy`.
  const double inv_area = 1.0 / double(s * s);
  double band_max = 0.0;
  std::vector<double> g_prefix(size_t(nox) + 1);
  std::vector<double> boxed_prefix(size_t(noy + 1) * size_t(w), 0.0);
  for (int64_t j = 0; j < noy; ++j) {
    const int64_t oy = oy0 + j;
    for (int64_t i = 0; i < nox; ++i) {
      const int64_t ox = ox0 + i;
      const double a = quadrant(oy, ox), b = quadrant(oy, ox + half);
      const double c = quadrant(oy + half, ox), d = quadrant(oy + half, ox + half);
      const double ah = (b + d - a - c) * inv_area, av = (c + d - a - b) * inv_area, ad = (a + d - b - c) * inv_area;
      band_max = std::max({band_max, std::abs(ah), std::abs(av), std::abs(ad)});
      g_prefix[size_t(i + 1)] = g_prefix[size_t(i)] + (ah * ah + av * av + ad * ad);
    }
    const double* above = &boxed_prefix[size_t(j * w)];
    double* here = &boxed_prefix[size_t((j + 1) * w)];
    for (int64_t x = 0; x < w; ++x) {
      const double sum = wrap ? periodic_sum(g_prefix.data(), 1, w, x - s + 1, s)
                              : g_prefix[size_t(x + s)] - g_prefix[size_t(x)];  // origins x - s + 1 .. x
      here[x] = above[x] + sum;
    }
  }
  for (int64_t y = 0; y < h; ++y) {
    for (int64_t x = 0; x < w; ++x) {  // origins y - s + 1 .. y: rows y .. y + s - 1 of boxed
      const double sum = boxed_prefix[size_t((y + s) * w + x)] - boxed_prefix[size_t(y * w + x)];
      energy[size_t(y * w + x)] = float(std::max(sum, 0.0) * inv_area);
    }
  }
  return band_max;
}

std::vector<float> wavelet_bandwidth_unpadded(std::vector<float> f, uint32_t width, uint32_t height,
                                              const WaveletOptions& options) {
  const int64_t w = width, h = height;
  const size_t n = size_t(w) * size_t(h);
  std::vector<float> out(n, 0.0f);
  const uint32_t longest = std::max(width, height);
  const int levels = longest <= 1 ? 0 : int(std::bit_width(longest - 1));  // ceil(log2(longest))
  if (levels == 0) return out;
  // Details do not see a constant; taking one off makes a constant image exactly 0.
  const float offset = f[0];
  for (float& v : f) v -= offset;
  std::vector<float> energy(static_cast<size_t>(levels) * n);
  std::vector<double> band_max(static_cast<size_t>(levels));
  for (int i = 1; i <= levels; ++i) {
    band_max[size_t(i - 1)] = band_energy(f, w, h, int64_t(1) << i, options.wrap_x, &energy[size_t(i - 1) * n]);
  }
  const double largest = *std::max_element(band_max.begin(), band_max.end());
  if (!(largest > 0.0)) return out;
  std::vector<bool> significant(static_cast<size_t>(levels));
  for (int i = 0; i < levels; ++i) significant[size_t(i)] = band_max[size_t(i)] >= options.epsilon * largest;  // Eq. 7
  const double floor = (kConstantFloor * largest) * (kConstantFloor * largest);
  for (size_t p = 0; p < n; ++p) {
    double total = 0.0;
    for (int i = 0; i < levels; ++i) {
      if (significant[size_t(i)]) total += energy[size_t(i) * n + p];
    }
    if (!(total > floor)) continue;
    double cumulative = 0.0;
    const double target = double(options.percentile) * total;
    for (int i = levels; i >= 1; --i) {  // coarse to fine
      if (!significant[size_t(i - 1)]) continue;
      const double e = energy[size_t(i - 1) * n + p];
      if (cumulative + e >= target || i == 1) {
        // Where the percentile falls inside band i, log-linear over its octave;
        // reported one octave lower (the header's "Value").
        const double t = e > 0.0 ? std::clamp((target - cumulative) / e, 0.0, 1.0) : 1.0;
        out[p] = float(std::ldexp(std::exp2(t), -(i + 2)));
        break;
      }
      cumulative += e;
    }
  }
  return out;
}

// The largest pixels per radian of a row of a map whose rows span `theta_range`
// radians (height rows) and columns 2 pi (width columns), at the row's centre.
double pixels_per_radian(uint32_t row, uint32_t width, uint32_t height, double theta_range) {
  const double step = theta_range / double(height);
  const double sin_floor = std::sin(0.5 * step);
  const double sin_t = std::max(std::sin((double(row) + 0.5) * step), sin_floor);
  return std::max(1.0 / step, double(width) / (2.0 * kPi * sin_t));
}

float luminance(const float* c) { return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2]; }

// FFTW's planner is not thread-safe; execution on fresh arrays is.
std::mutex& fftw_planner_mutex() {
  static std::mutex m;
  return m;
}

}  // namespace

std::vector<float> wavelet_bandwidth(std::span<const float> image, uint32_t width, uint32_t height,
                                     const WaveletOptions& options) {
  constexpr const char* fn = "wavelet_bandwidth";
  check_image(image, width, height, fn);
  if (!(options.epsilon > 0.0f && options.epsilon < 1.0f))
    bad(fn, "epsilon " + std::to_string(options.epsilon) + " outside (0, 1)");
  if (!(options.percentile > 0.0f && options.percentile <= 1.0f)) {
    bad(fn, "percentile " + std::to_string(options.percentile) + " outside (0, 1]");
  }
  if (!options.zero_pad) return wavelet_bandwidth_unpadded({image.begin(), image.end()}, width, height, options);
  if (width > (1u << 30) || height > (1u << 30)) bad(fn, "image too large to pad");
  // Sec. 2.3: the image in the middle of a zero frame twice its size, the result cropped back.
  const uint32_t pw = 2 * width, ph = 2 * height, x0 = width / 2, y0 = height / 2;
  std::vector<float> padded(size_t(pw) * ph, 0.0f);
  for (uint32_t y = 0; y < height; ++y) {
    std::copy_n(&image[size_t(y) * width], width, &padded[size_t(y + y0) * pw + x0]);
  }
  const std::vector<float> full = wavelet_bandwidth_unpadded(std::move(padded), pw, ph, options);
  std::vector<float> out(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y) std::copy_n(&full[size_t(y + y0) * pw + x0], width, &out[size_t(y) * width]);
  return out;
}

EnvironmentBandwidth environment_bandwidth(const Environment& env, uint32_t out_width) {
  constexpr const char* fn = "environment_bandwidth";
  const uint32_t w = env.width, h = env.height;
  if (w == 0 || h == 0 || env.rgb.empty()) bad(fn, "empty map (" + std::to_string(w) + "x" + std::to_string(h) + ")");
  if (env.rgb.size() != size_t(w) * h * 3) {
    bad(fn,
        std::to_string(env.rgb.size()) + " floats for a " + std::to_string(w) + "x" + std::to_string(h) + " RGB map");
  }
  if (out_width < 2 || !std::has_single_bit(out_width) || out_width > w) {
    bad(fn, "out_width " + std::to_string(out_width) + " is not a power of two in [2, " + std::to_string(w) + "]");
  }
  std::vector<float> lum(size_t(w) * h);
  for (size_t t = 0; t < lum.size(); ++t) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(env.rgb[t * 3 + size_t(c)])) {
        bad(fn, "NaN or Inf at texel (" + std::to_string(t % w) + ", " + std::to_string(t / w) + ")");
      }
    }
    lum[t] = luminance(&env.rgb[t * 3]);
  }
  WaveletOptions options;
  options.wrap_x = true;
  const std::vector<float> cycles = wavelet_bandwidth(lum, w, h, options);
  EnvironmentBandwidth out;
  out.width = out_width;
  out.height = out_width / 2;
  out.cycles_per_radian.assign(size_t(out.width) * out.height, 0.0f);
  for (uint32_t y = 0; y < h; ++y) {
    const double scale = pixels_per_radian(y, w, h, kPi);  // Sec. 2.3: 2 pi / (2^I_w lambda_max) per radian
    const uint32_t ty = uint32_t(uint64_t(y) * out.height / h);
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t tx = uint32_t(uint64_t(x) * out.width / w);
      float& t = out.cycles_per_radian[size_t(ty) * out.width + tx];
      t = std::max(t, float(double(cycles[size_t(y) * w + x]) * scale));
    }
  }
  return out;
}

AreaLightBandwidth area_light_bandwidth(const AreaLight& light) {
  validate_area_light(light);
  const uint32_t k =
      std::max(1u, (32u + std::max(light.width, light.height) - 1u) / std::max(light.width, light.height));
  AreaLightBandwidth out;
  out.width = light.width * k;
  out.height = light.height * k;
  std::vector<float> lum(size_t(out.width) * out.height);
  for (uint32_t y = 0; y < out.height; ++y) {
    for (uint32_t x = 0; x < out.width; ++x) {
      lum[size_t(y) * out.width + x] = luminance(&light.rgb[3 * (size_t(y / k) * light.width + x / k)]);
    }
  }
  WaveletOptions options;
  options.zero_pad = true;
  out.cycles_per_unit = wavelet_bandwidth(lum, out.width, out.height, options);
  const double texel = std::min(double(glm::length(light.edge_u)) / out.width,  //
                                double(glm::length(light.edge_v)) / out.height);
  for (float& c : out.cycles_per_unit) c = float(double(c) / texel);
  return out;
}

std::vector<float> brdf_bandwidth(const Material& material) {
  constexpr uint32_t kFine = 8 * kBrdfBandwidthSlice;  // each slice at 8x the table's resolution
  const MaterialEvaluator evaluator(material);
  std::vector<float> out(size_t(kBrdfBandwidthTheta) * kBrdfBandwidthSlice * kBrdfBandwidthSlice, 0.0f);
  std::vector<float> slice(size_t(kFine) * kFine);
  std::vector<double> scale(size_t(kFine) * kFine);
  const double unit = 0.5 * double(kFine);  // pixels per unit of the disk's radius
  for (uint32_t ti = 0; ti < kBrdfBandwidthTheta; ++ti) {
    const double theta_v = (double(ti) + 0.5) * (0.5 * kPi) / double(kBrdfBandwidthTheta);
    const glm::vec3 wv(float(std::sin(theta_v)), 0.0f, float(std::cos(theta_v)));
    for (uint32_t row = 0; row < kFine; ++row) {
      for (uint32_t col = 0; col < kFine; ++col) {
        // The equal-area disk: outside it, the nearest point of its rim.
        const double x = (double(col) + 0.5) / unit - 1.0, y = (double(row) + 0.5) / unit - 1.0;
        const double r = std::min(std::hypot(x, y), 1.0);
        const double theta = 2.0 * std::asin(r / std::sqrt(2.0)), phi = std::atan2(y, x);
        const glm::vec3 wl(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                           float(std::cos(theta)));
        const glm::vec3 f = evaluator.brdf(glm::vec3(1.0f), wl, wv);
        const float v = (0.2126f * f.x + 0.7152f * f.y + 0.0722f * f.z) * wl.z;
        slice[size_t(row) * kFine + col] = std::isfinite(v) ? v : 0.0f;
        // The largest pixels per radian: the azimuthal direction's, unit /
        // (sqrt(2) cos(theta / 2)).
        scale[size_t(row) * kFine + col] = unit / (std::sqrt(2.0) * std::cos(0.5 * theta));
      }
    }
    const std::vector<float> cycles = wavelet_bandwidth(slice, kFine, kFine);
    const uint32_t pool = kFine / kBrdfBandwidthSlice;
    for (uint32_t row = 0; row < kFine; ++row) {
      for (uint32_t col = 0; col < kFine; ++col) {
        const size_t at = size_t(row) * kFine + col;
        float& t = out[(size_t(ti) * kBrdfBandwidthSlice + row / pool) * kBrdfBandwidthSlice + col / pool];
        t = std::max(t, float(double(cycles[at]) * scale[at]));
      }
    }
  }
  return out;
}

std::vector<float> windowed_fft_bandwidth(std::span<const float> image, uint32_t width, uint32_t height,
                                          uint32_t window, uint32_t stride, float epsilon) {
  constexpr const char* fn = "windowed_fft_bandwidth";
  check_image(image, width, height, fn);
  if (window < 4 || window % 2 != 0 || window > 4096)
    bad(fn, "window " + std::to_string(window) + " is not even in [4, 4096]");
  if (stride == 0) bad(fn, "stride 0");
  if (!(epsilon >= 0.0f && epsilon < 1.0f)) bad(fn, "epsilon " + std::to_string(epsilon) + " outside [0, 1)");
  const uint32_t bins = window / 2 + 1;
  struct FftwFree {
    void operator()(void* p) const { fftwf_free(p); }
  };
  std::unique_ptr<float, FftwFree> in(static_cast<float*>(fftwf_malloc(sizeof(float) * window * window)));
  std::unique_ptr<fftwf_complex, FftwFree> spectrum(
      static_cast<fftwf_complex*>(fftwf_malloc(sizeof(fftwf_complex) * window * bins)));
  if (!in || !spectrum) throw std::bad_alloc();
  struct PlanFree {
    void operator()(fftwf_plan p) const {
      std::lock_guard<std::mutex> lock(fftw_planner_mutex());
      fftwf_destroy_plan(p);
    }
  };
  std::unique_ptr<std::remove_pointer_t<fftwf_plan>, PlanFree> plan;
  {
    std::lock_guard<std::mutex> lock(fftw_planner_mutex());
    plan.reset(fftwf_plan_dft_r2c_2d(int(window), int(window), in.get(), spectrum.get(), FFTW_ESTIMATE));
  }
  if (!plan) bad(fn, "FFTW could not plan a " + std::to_string(window) + "x" + std::to_string(window) + " transform");
  std::vector<double> hann(window);
  for (uint32_t i = 0; i < window; ++i) hann[i] = 0.5 - 0.5 * std::cos(2.0 * kPi * double(i) / double(window));
  double hann_sum = 0.0;
  for (uint32_t j = 0; j < window; ++j) {
    for (uint32_t i = 0; i < window; ++i) hann_sum += hann[i] * hann[j];
  }
  const uint32_t cx_count = (width + stride - 1) / stride, cy_count = (height + stride - 1) / stride;
  std::vector<float> centre_value(size_t(cx_count) * cy_count, 0.0f);
  std::vector<double> rings(size_t(std::lround(0.5 * std::sqrt(2.0) * window)) + 1);
  auto pixel = [&](int64_t x, int64_t y) {
    x = std::clamp<int64_t>(x, 0, int64_t(width) - 1);
    y = std::clamp<int64_t>(y, 0, int64_t(height) - 1);
    return double(image[size_t(y) * width + size_t(x)]);
  };
  for (uint32_t cy = 0; cy < cy_count; ++cy) {
    for (uint32_t cx = 0; cx < cx_count; ++cx) {
      const int64_t px = std::min<int64_t>(int64_t(cx) * stride + stride / 2, int64_t(width) - 1);
      const int64_t py = std::min<int64_t>(int64_t(cy) * stride + stride / 2, int64_t(height) - 1);
      const int64_t x0 = px - window / 2, y0 = py - window / 2;
      double mean = 0.0, magnitude = 0.0;  // Hann-weighted, so that the windowed signal has no DC
      for (uint32_t j = 0; j < window; ++j) {
        for (uint32_t i = 0; i < window; ++i) {
          const double v = hann[i] * hann[j] * pixel(x0 + i, y0 + j);
          mean += v;
          magnitude += v * v;
        }
      }
      mean /= hann_sum;
      for (uint32_t j = 0; j < window; ++j) {
        for (uint32_t i = 0; i < window; ++i) {
          in.get()[j * window + i] = float(hann[i] * hann[j] * (pixel(x0 + i, y0 + j) - mean));
        }
      }
      fftwf_execute(plan.get());
      std::fill(rings.begin(), rings.end(), 0.0);
      // Eq. 7's epsilon in power: bins whose amplitude is below epsilon of
      // the window's largest do not count (a faint broadband floor, such as
      // noise, would otherwise hold the 95th percentile near Nyquist).
      double peak = 0.0;
      for (uint32_t k = 0; k < window * bins; ++k) {
        const fftwf_complex& c = spectrum.get()[k];
        peak = std::max(peak, double(c[0]) * c[0] + double(c[1]) * c[1]);
      }
      const double floor = epsilon * epsilon * peak;
      double total = 0.0;
      for (uint32_t ky = 0; ky < window; ++ky) {
        const uint32_t fy = std::min(ky, window - ky);  // |fy| in bins
        for (uint32_t kx = 0; kx < bins; ++kx) {
          const fftwf_complex& c = spectrum.get()[ky * bins + kx];
          const double bin = double(c[0]) * c[0] + double(c[1]) * c[1];
          if (bin < floor) continue;
          // r2c holds kx in [0, window/2]; the others are their conjugates.
          const double weight = (kx == 0 || kx == window / 2) ? 1.0 : 2.0;
          const double power = weight * bin;
          rings[size_t(std::lround(std::sqrt(double(kx) * kx + double(fy) * fy)))] += power;
          total += power;
        }
      }
      float value = 0.0f;
      // Parseval: the spectrum's power is window^2 x the windowed signal's; below
      // float rounding of it, the window is constant.
      if (total > 1e-10 * double(window) * window * magnitude) {
        double cumulative = 0.0;
        for (uint32_t r = 0; r < rings.size(); ++r) {
          cumulative += rings[r];
          if (cumulative >= 0.95 * total) {
            value = float(r) / float(window);
            break;
          }
        }
      }
      centre_value[size_t(cy) * cx_count + cx] = value;
    }
  }
  std::vector<float> out(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x)
      out[size_t(y) * width + x] = centre_value[size_t(y / stride) * cx_count + x / stride];
  }
  return out;
}

}  // namespace svo::render
