// Chi-square goodness-of-fit test of a sampler of directions against the
// density it claims (after pbrt-v3/v4's and Mitsuba 3's chi2 tests), for
// the BRDF lobes, measured BRDFs and environment maps.
//
// The sphere is cut into bins of (cos theta, phi) (theta from +z, phi from +x
// towards +y). The sampler draws `samples` directions from independent
// uniform u; the expected count of a bin is `samples` times the integral of
// the pdf over it (midpoint rule in theta and phi, with the sin(theta)
// Jacobian, so that a pdf with a 1/sin(theta) factor, as lat-long tables
// have, integrates without a singularity). Bins expecting fewer than
// `min_expected` samples are pooled into one (smallest first, until the pool
// expects enough). A small p-value rejects the hypothesis that the samples
// follow the pdf.
//
// Usage:
//   svo::test::ChiSquareResult r = svo::test::chi_square_test(sample, pdf, {});
//   EXPECT_TRUE(r.passed(0.01)) << r.summary();
//   EXPECT_NEAR(r.pdf_integral, 1.0, 0.01);   // a sampler that always returns a direction
// With several tests in one suite, divide the significance among them
// (Sidak: 1 - (1 - 0.01)^(1/n)), as pbrt does.
//
// The pdf should be piecewise smooth; a step of the pdf inside a bin costs
// the midpoint rule up to jump / (2 integration_points) of the bin's mass:
// raise integration_points for tabulated pdfs and many samples.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace svo::test {

// Q(a, x) = Gamma(a, x) / Gamma(a), the regularized upper incomplete gamma
// function for a > 0, x >= 0 (the series of P below x = a + 1, Lentz's
// continued fraction of Q above; relative error about 1e-14).
inline double regularized_gamma_q(double a, double x) {
  if (!(a > 0) || !(x >= 0)) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0) return 1;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1) {
    // P(a, x) = x^a e^-x / Gamma(a + 1) * sum_n x^n / ((a + 1) ... (a + n)).
    double term = 1 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-16) break;
    }
    return std::max(0.0, 1 - sum * std::exp(log_prefix));
  }
  // Q(a, x) = x^a e^-x / Gamma(a) * 1 / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...)).
  const double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
  for (int n = 1; n < 100000; ++n) {
    const double an = -n * (n - a);
    b += 2;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1) < 1e-16) break;
  }
  return std::min(1.0, std::exp(log_prefix) * h);
}

// The probability that a chi-square variable of `dof` degrees of freedom
// reaches `statistic` or more (1 for dof < 1).
inline double chi_square_p_value(double statistic, int dof) {
  if (dof < 1) return 1;
  return regularized_gamma_q(0.5 * dof, 0.5 * std::max(statistic, 0.0));
}

// The significance of each of n tests so that all of them pass with
// probability 1 - alpha when every sampler is right (Sidak's correction).
inline double sidak_significance(double alpha, int n) { return 1 - std::pow(1 - alpha, 1.0 / n); }

struct ChiSquareOptions {
  int cos_theta_bins = 40;     // over cos(theta) in [-1, 1]
  int phi_bins = 80;           // over phi in [0, 2 pi)
  int integration_points = 8;  // midpoints per bin and axis (theta, phi)
  uint64_t samples = 1000000;  // calls of `sample`
  uint64_t seed = 1;           // of the uniform numbers (std::mt19937_64)
  double min_expected = 5;     // bins expecting fewer samples are pooled
};

struct ChiSquareResult {
  double statistic = 0;
  int dof = 0;
  double p_value = 0;
  double pdf_integral = 0;  // of the pdf over the sphere (1 for a sampler that always returns a direction)
  uint64_t no_sample = 0;   // calls that returned no direction
  std::string error;        // non-empty: the test fails whatever the p-value (the reason)
  int cos_theta_bins = 0, phi_bins = 0;
  std::vector<double> observed;  // per bin, cos theta bin major: [i * phi_bins + j]
  std::vector<double> expected;

  bool passed(double significance) const { return error.empty() && p_value >= significance; }

  // One line: the statistic, dof, p-value, integral, and the bins that
  // contribute most (observed vs expected), for a failure message.
  std::string summary() const {
    std::ostringstream s;
    s << "chi2 " << statistic << ", dof " << dof << ", p-value " << p_value << ", pdf integral " << pdf_integral
      << ", no sample " << no_sample;
    if (!error.empty()) s << "; error: " << error;
    std::vector<size_t> order(observed.size());
    std::iota(order.begin(), order.end(), size_t(0));
    auto contribution = [&](size_t k) {
      const double d = observed[k] - expected[k];
      return expected[k] > 0 ? d * d / expected[k] : (observed[k] > 0 ? 1e300 : 0.0);
    };
    std::partial_sort(order.begin(), order.begin() + std::min<size_t>(5, order.size()), order.end(),
                      [&](size_t a, size_t b) { return contribution(a) > contribution(b); });
    s << "; worst bins (cos theta bin, phi bin: observed/expected):";
    for (size_t n = 0; n < std::min<size_t>(5, order.size()); ++n) {
      const size_t k = order[n];
      s << " (" << k / size_t(phi_bins) << ", " << k % size_t(phi_bins) << ": " << observed[k] << "/" << expected[k]
        << ")";
    }
    return s.str();
  }
};

// `sample(u)`: a direction (any length > 0) for u uniform in [0, 1)^2, or
// none (counted in no_sample; its probability is what the pdf's integral
// lacks). `pdf(dir)`: the density over solid angle (1/sr) of a unit `dir`,
// finite and >= 0. The result's error is set when a direction is not
// finite, a pdf value is negative or not finite, or samples land in bins
// whose expected count is 0 (more than samples * 1e-5 of them).
inline ChiSquareResult chi_square_test(const std::function<std::optional<glm::dvec3>(glm::dvec2 u)>& sample,
                                       const std::function<double(glm::dvec3 dir)>& pdf,
                                       const ChiSquareOptions& options = {}) {
  constexpr double kPi = 3.14159265358979323846;
  const int nc = options.cos_theta_bins, np = options.phi_bins, m = options.integration_points;
  ChiSquareResult r;
  r.cos_theta_bins = nc;
  r.phi_bins = np;
  r.observed.assign(size_t(nc) * size_t(np), 0.0);
  r.expected.assign(size_t(nc) * size_t(np), 0.0);

  // Observed counts.
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (uint64_t n = 0; n < options.samples; ++n) {
    const double u0 = uniform(rng), u1 = uniform(rng);
    const std::optional<glm::dvec3> dir = sample(glm::dvec2(u0, u1));
    if (!dir) {
      ++r.no_sample;
      continue;
    }
    const double len = std::sqrt(dir->x * dir->x + dir->y * dir->y + dir->z * dir->z);
    if (!std::isfinite(len) || !(len > 0)) {
      if (r.error.empty()) {
        r.error = "sample " + std::to_string(n) + " is not a finite non-zero direction";
      }
      continue;
    }
    const double c = std::clamp(dir->z / len, -1.0, 1.0);
    double phi = std::atan2(dir->y, dir->x);
    if (phi < 0) phi += 2 * kPi;
    const int i = std::clamp(int((c + 1) * 0.5 * nc), 0, nc - 1);
    const int j = std::clamp(int(phi / (2 * kPi) * np), 0, np - 1);
    r.observed[size_t(i) * size_t(np) + size_t(j)] += 1;
  }

  // Expected counts: the pdf integrated over each bin in (theta, phi).
  for (int i = 0; i < nc; ++i) {
    const double theta_hi = std::acos(std::clamp(-1 + 2.0 * i / nc, -1.0, 1.0));
    const double theta_lo = std::acos(std::clamp(-1 + 2.0 * (i + 1) / nc, -1.0, 1.0));
    const double dt = (theta_hi - theta_lo) / m;
    for (int j = 0; j < np; ++j) {
      const double dp = 2 * kPi / np / m;
      double sum = 0;
      for (int a = 0; a < m; ++a) {
        const double theta = theta_lo + (a + 0.5) * dt;
        const double st = std::sin(theta), ct = std::cos(theta);
        for (int b = 0; b < m; ++b) {
          const double phi = 2 * kPi * j / np + (b + 0.5) * dp;
          const double p = pdf(glm::dvec3(st * std::cos(phi), st * std::sin(phi), ct));
          if (!(p >= 0) || !std::isfinite(p)) {
            if (r.error.empty()) {
              r.error =
                  "pdf " + std::to_string(p) + " at theta " + std::to_string(theta) + ", phi " + std::to_string(phi);
            }
            continue;
          }
          sum += p * st;
        }
      }
      const double mass = sum * dt * dp;
      r.pdf_integral += mass;
      r.expected[size_t(i) * size_t(np) + size_t(j)] = mass * double(options.samples);
    }
  }

  // The statistic over bins expecting enough samples, the others pooled.
  std::vector<size_t> order(r.expected.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return r.expected[a] < r.expected[b]; });
  double pooled_observed = 0, pooled_expected = 0;
  int cells = 0;
  for (size_t k : order) {
    const double o = r.observed[k], e = r.expected[k];
    if (e <= 0) {
      if (o > double(options.samples) * 1e-5 && r.error.empty()) {
        r.error = std::to_string(uint64_t(o)) + " samples in bin (" + std::to_string(k / size_t(np)) + ", " +
                  std::to_string(k % size_t(np)) + ") where the pdf integrates to 0";
      }
      pooled_observed += o;
    } else if (e < options.min_expected || (pooled_expected > 0 && pooled_expected < options.min_expected)) {
      pooled_observed += o;
      pooled_expected += e;
    } else {
      r.statistic += (o - e) * (o - e) / e;
      ++cells;
    }
  }
  if (pooled_expected > 0) {
    r.statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
    ++cells;
  } else if (pooled_observed > double(options.samples) * 1e-5 && r.error.empty()) {
    r.error = std::to_string(uint64_t(pooled_observed)) + " samples where the pdf integrates to 0";
  }
  r.dof = cells - 1;
  r.p_value = chi_square_p_value(r.statistic, r.dof);
  return r;
}

}  // namespace svo::test
