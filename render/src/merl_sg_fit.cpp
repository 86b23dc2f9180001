// A measured BRDF's specular lobe as a few spherical Gaussians in
// half-vector space (Tokuyoshi 2015, section 4.1: measured BRDFs are fitted
// once, in preprocessing, for the lobe-aware weight of Eq. 11).
//
// The data: the luminance of the samples with theta_d index 0..5 (all
// phi_d averaged) per theta_h bin, as a function of x = 1 - cos theta_h.
// The model: floor + sum_k mu_k exp(-lambda_k x), everything non-negative,
// least squares weighted by each bin's solid angle. The search: exact NNLS
// (every support enumerated) over every set of up to 3 sharpness values of
// a log-spaced dictionary, then coordinate-wise golden-section steps in
// log-sharpness with the amplitudes re-solved; a lobe is kept only if it
// lowers the squared error by more than kMinGain of the data's own norm.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "svo/render/merl.h"

namespace svo::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
// theta_d indices 0 .. kFitThetaD - 1 (0 to 5 degrees).
constexpr uint32_t kFitThetaD = 6;
constexpr double kMinSharpness = 1e-2, kMaxSharpness = 1e5;
// The dictionary: kDictionary sharpness values from 1 to 1e5, log-spaced
// (neighbours 20 % apart).
constexpr int kDictionary = 64;
constexpr double kDictionaryMin = 1.0;
// One more lobe must lower the weighted squared error by this fraction of
// the data's weighted squared norm (an RMS gain of about 0.3 %).
constexpr double kMinGain = 1e-5;
constexpr int kMaxLobes = 3;
// Columns: up to kMaxLobes lobes and the constant.
constexpr int kMaxColumns = kMaxLobes + 1;

// The fitted profile: per theta_h bin with data, x = 1 - cos theta_h, the
// weight (the bin's solid angle over 2 pi, times the fraction of its samples
// that were observed) and the mean luminance.
struct Profile {
  std::vector<double> x, weight, value;
  double norm2 = 0;  // sum weight value^2
};

double luminance(const float* rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

// The lower edge of theta_h bin i (the table's sample angle); bin 90 is the horizon.
double theta_h_of(uint32_t i) {
  const double s = double(i) / kMerlThetaH;
  return s * s * (0.5 * kPi);
}

Profile merl_profile(const MerlBrdf& brdf) {
  if (brdf.rgb.size() != 3 * size_t(kMerlSamples)) {
    throw std::invalid_argument("merl: SG fit: " + std::to_string(brdf.rgb.size()) + " values, expected " +
                                std::to_string(3 * size_t(kMerlSamples)));
  }
  Profile p;
  for (uint32_t ih = 0; ih < kMerlThetaH; ++ih) {
    double sum = 0;
    uint32_t used = 0;
    for (uint32_t id = 0; id < kFitThetaD; ++id) {
      for (uint32_t ip = 0; ip < kMerlPhiD; ++ip) {
        const uint32_t k = ip + kMerlPhiD * (id + kMerlThetaD * ih);
        const auto [wi, wo] = merl_sample_directions(k);
        if (!(wi.z > 0) || !(wo.z > 0)) continue;
        // Missing: the format's -1 (read as 0, all channels), or a value no
        // BRDF has.
        const float* f = &brdf.rgb[3 * size_t(k)];
        if (!(f[0] >= 0 && f[1] >= 0 && f[2] >= 0) || !std::isfinite(f[0]) || !std::isfinite(f[1]) ||
            !std::isfinite(f[2]) || (f[0] == 0 && f[1] == 0 && f[2] == 0)) {
          continue;
        }
        sum += luminance(f);
        ++used;
      }
    }
    if (used == 0) continue;
    // h = normalize(wi + wo) of the bin's first sample (every sample of the
    // bin has the same h); 1 - h.z as (h.x^2 + h.y^2) / (1 + h.z), without
    // cancellation near the pole.
    const auto [wi, wo] = merl_sample_directions(kMerlPhiD * kMerlThetaD * ih);
    const glm::dvec3 h = glm::normalize(wi + wo);
    // The bin's solid angle over 2 pi: cos t0 - cos t1 = 2 sin((t1 + t0) / 2) sin((t1 - t0) / 2).
    const double t0 = theta_h_of(ih), t1 = theta_h_of(ih + 1);
    const double solid = 2 * std::sin(0.5 * (t1 + t0)) * std::sin(0.5 * (t1 - t0));
    const double mean = sum / used;
    p.x.push_back((h.x * h.x + h.y * h.y) / (1 + h.z));
    p.weight.push_back(solid * double(used) / double(kFitThetaD * kMerlPhiD));
    p.value.push_back(mean);
    p.norm2 += p.weight.back() * mean * mean;
  }
  return p;
}

// Non-negative least squares on the normal equations of m <= kMaxColumns
// columns (gram[i][j], rhs[i], yy = |y|^2): every support is solved
// (Cholesky; a support whose columns are numerically dependent is skipped,
// a smaller one covers it) and the feasible one of least error wins, which
// is the exact NNLS optimum. Returns the squared error; x gets the solution.
double nnls_normal(int m, const double (&gram)[kMaxColumns][kMaxColumns], const double* rhs, double yy, double* x) {
  double best = yy;
  std::fill(x, x + m, 0.0);
  for (uint32_t mask = 1; mask < (1u << m); ++mask) {
    int idx[kMaxColumns], n = 0;
    for (int i = 0; i < m; ++i) {
      if (mask & (1u << i)) idx[n++] = i;
    }
    double l[kMaxColumns][kMaxColumns] = {};
    bool ok = true;
    for (int i = 0; i < n && ok; ++i) {
      for (int j = 0; j <= i; ++j) {
        double s = gram[idx[i]][idx[j]];
        for (int k = 0; k < j; ++k) s -= l[i][k] * l[j][k];
        if (i == j) {
          // Relative pivot: the columns' Gram diagonal is of order 1 or 0.
          if (!(s > 1e-13 * std::max(gram[idx[i]][idx[i]], 1e-300)))
            ok = false;
          else
            l[i][i] = std::sqrt(s);
        } else {
          l[i][j] = s / l[j][j];
        }
      }
    }
    if (!ok) continue;
    double z[kMaxColumns], c[kMaxColumns];
    for (int i = 0; i < n; ++i) {
      double s = rhs[idx[i]];
      for (int k = 0; k < i; ++k) s -= l[i][k] * z[k];
      z[i] = s / l[i][i];
    }
    for (int i = n - 1; i >= 0; --i) {
      double s = z[i];
      for (int k = i + 1; k < n; ++k) s -= l[k][i] * c[k];
      c[i] = s / l[i][i];
    }
    bool feasible = true;
    double err = yy;
    for (int i = 0; i < n; ++i) {
      feasible = feasible && c[i] > 0;
      err -= c[i] * rhs[idx[i]];
    }
    if (!feasible || !std::isfinite(err)) continue;
    err = std::max(err, 0.0);
    if (err < best) {
      best = err;
      std::fill(x, x + m, 0.0);
      for (int i = 0; i < n; ++i) x[idx[i]] = c[i];
    }
  }
  return best;
}

// A fit: the lobes' sharpness and amplitudes, the floor, the weighted squared error.
struct Fit {
  std::vector<double> sharpness, amplitude;
  double floor = 0;
  double error = 0;
};

// The NNLS fit of the given sharpness values (and the floor) to the
// profile, its error computed from the residual itself.
Fit solve(const Profile& p, const std::vector<double>& sharpness) {
  const int lobes = int(sharpness.size()), m = lobes + 1;
  const size_t bins = p.x.size();
  // Columns sqrt(weight) phi_j, scaled to unit norm (the last the constant).
  std::vector<double> col(size_t(m) * bins);
  double norm[kMaxColumns];
  for (int j = 0; j < m; ++j) {
    double n2 = 0;
    for (size_t i = 0; i < bins; ++i) {
      const double phi = j < lobes ? std::exp(-sharpness[size_t(j)] * p.x[i]) : 1.0;
      col[size_t(j) * bins + i] = std::sqrt(p.weight[i]) * phi;
      n2 += col[size_t(j) * bins + i] * col[size_t(j) * bins + i];
    }
    norm[j] = std::sqrt(n2);
    const double inv = norm[j] > 0 ? 1 / norm[j] : 0;
    for (size_t i = 0; i < bins; ++i) col[size_t(j) * bins + i] *= inv;
  }
  double gram[kMaxColumns][kMaxColumns] = {}, rhs[kMaxColumns] = {}, coef[kMaxColumns];
  for (int a = 0; a < m; ++a) {
    for (size_t i = 0; i < bins; ++i) rhs[a] += col[size_t(a) * bins + i] * std::sqrt(p.weight[i]) * p.value[i];
    for (int b = 0; b <= a; ++b) {
      double s = 0;
      for (size_t i = 0; i < bins; ++i) s += col[size_t(a) * bins + i] * col[size_t(b) * bins + i];
      gram[a][b] = gram[b][a] = s;
    }
  }
  nnls_normal(m, gram, rhs, p.norm2, coef);
  Fit f;
  f.sharpness = sharpness;
  f.amplitude.resize(size_t(lobes));
  for (int j = 0; j < m; ++j) {
    const double a = norm[j] > 0 ? coef[j] / norm[j] : 0;
    if (j < lobes)
      f.amplitude[size_t(j)] = a;
    else
      f.floor = a;
  }
  for (size_t i = 0; i < bins; ++i) {
    double model = f.floor;
    for (int j = 0; j < lobes; ++j) model += f.amplitude[size_t(j)] * std::exp(-sharpness[size_t(j)] * p.x[i]);
    const double r = p.value[i] - model;
    f.error += p.weight[i] * r * r;
  }
  return f;
}

// The dictionary's sharpness values.
std::array<double, kDictionary> dictionary() {
  std::array<double, kDictionary> d;
  for (int i = 0; i < kDictionary; ++i) {
    d[size_t(i)] = kDictionaryMin * std::pow(kMaxSharpness / kDictionaryMin, double(i) / (kDictionary - 1));
  }
  return d;
}

// The best set of `n` dictionary values (exhaustively, NNLS on the
// precomputed normal equations of the dictionary's unit columns).
std::vector<double> best_dictionary_set(const Profile& p, int n) {
  const auto dict = dictionary();
  constexpr int kCols = kDictionary + 1;  // the last is the constant
  const size_t bins = p.x.size();
  std::vector<double> col(size_t(kCols) * bins);
  for (int j = 0; j < kCols; ++j) {
    double n2 = 0;
    for (size_t i = 0; i < bins; ++i) {
      const double phi = j < kDictionary ? std::exp(-dict[size_t(j)] * p.x[i]) : 1.0;
      col[size_t(j) * bins + i] = std::sqrt(p.weight[i]) * phi;
      n2 += col[size_t(j) * bins + i] * col[size_t(j) * bins + i];
    }
    const double inv = n2 > 0 ? 1 / std::sqrt(n2) : 0;
    for (size_t i = 0; i < bins; ++i) col[size_t(j) * bins + i] *= inv;
  }
  std::vector<double> gram(size_t(kCols) * kCols), rhs(kCols, 0.0);
  for (int a = 0; a < kCols; ++a) {
    for (size_t i = 0; i < bins; ++i) rhs[size_t(a)] += col[size_t(a) * bins + i] * std::sqrt(p.weight[i]) * p.value[i];
    for (int b = 0; b <= a; ++b) {
      double s = 0;
      for (size_t i = 0; i < bins; ++i) s += col[size_t(a) * bins + i] * col[size_t(b) * bins + i];
      gram[size_t(a) * kCols + size_t(b)] = gram[size_t(b) * kCols + size_t(a)] = s;
    }
  }
  double best = INFINITY;
  int best_set[kMaxLobes] = {};
  // The n-sets of dictionary indices in lexicographic order (a < b < c, the
  // unused ones kDictionary - 1 + their place); ties keep the first (deterministic).
  const int last = kDictionary - 1;
  for (int a = 0; a <= last; ++a) {
    for (int b = n >= 2 ? a + 1 : last + 1; b <= (n >= 2 ? last : last + 1); ++b) {
      for (int c = n >= 3 ? b + 1 : last + 2; c <= (n >= 3 ? last : last + 2); ++c) {
        const int set[kMaxLobes] = {a, b, c};
        int idx[kMaxColumns];
        for (int i = 0; i < n; ++i) idx[i] = set[i];
        idx[n] = kDictionary;
        double g[kMaxColumns][kMaxColumns], r[kMaxColumns], x[kMaxColumns];
        for (int i = 0; i <= n; ++i) {
          r[i] = rhs[size_t(idx[i])];
          for (int j = 0; j <= n; ++j) g[i][j] = gram[size_t(idx[i]) * kCols + size_t(idx[j])];
        }
        const double err = nnls_normal(n + 1, g, r, p.norm2, x);
        if (err < best) {
          best = err;
          std::copy(set, set + kMaxLobes, best_set);
        }
      }
    }
  }
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(dict[size_t(best_set[i])]);
  return out;
}

// Coordinate-wise golden-section search in log-sharpness, each lobe within
// two dictionary steps of where it stands per sweep; never worse than `f`.
Fit refine(const Profile& p, Fit f) {
  const double step = std::log(kMaxSharpness / kDictionaryMin) / (kDictionary - 1);
  const double lo_limit = std::log(kMinSharpness), hi_limit = std::log(kMaxSharpness);
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int sweep = 0; sweep < 8; ++sweep) {
    const double before = f.error;
    for (size_t j = 0; j < f.sharpness.size(); ++j) {
      std::vector<double> s = f.sharpness;
      auto eval = [&](double t) {
        s[j] = std::exp(t);
        return solve(p, s);
      };
      const double t = std::log(f.sharpness[j]);
      double a = std::max(t - 2 * step, lo_limit), b = std::min(t + 2 * step, hi_limit);
      double c = b - g * (b - a), d = a + g * (b - a);
      Fit fc = eval(c), fd = eval(d);
      for (int it = 0; it < 40; ++it) {
        if (fc.error <= fd.error) {
          b = d, d = c, fd = fc;
          c = b - g * (b - a);
          fc = eval(c);
        } else {
          a = c, c = d, fc = fd;
          d = a + g * (b - a);
          fd = eval(d);
        }
      }
      const Fit& best = fc.error <= fd.error ? fc : fd;
      if (best.error < f.error) f = best;
    }
    if (!(f.error < before * (1 - 1e-9))) break;
  }
  return f;
}

// The best fit with exactly `n` lobe positions: from the best dictionary
// set and from `previous` (n - 1 lobes, refined) plus the best dictionary
// value, both refined; the better one.
Fit fit_lobes(const Profile& p, int n, const Fit& previous) {
  Fit from_dictionary = refine(p, solve(p, best_dictionary_set(p, n)));
  Fit greedy;
  greedy.error = INFINITY;
  for (double s : dictionary()) {
    std::vector<double> sharpness = previous.sharpness;
    sharpness.push_back(s);
    Fit f = solve(p, sharpness);
    if (f.error < greedy.error) greedy = f;
  }
  greedy = refine(p, greedy);
  return greedy.error < from_dictionary.error ? greedy : from_dictionary;
}

}  // namespace

std::vector<MerlSgLobe> fit_merl_sg(const MerlBrdf& brdf, int max_lobes) {
  if (max_lobes < 1 || max_lobes > kMaxLobes) {
    throw std::invalid_argument("merl: SG fit: max_lobes " + std::to_string(max_lobes) + " is outside 1.." +
                                std::to_string(kMaxLobes));
  }
  const Profile p = merl_profile(brdf);
  if (p.x.empty() || !(p.norm2 > 0) || !std::isfinite(p.norm2)) return {};
  Fit fit = solve(p, {});
  for (int n = 1; n <= max_lobes; ++n) {
    Fit next = fit_lobes(p, n, fit);
    if (!(next.error < fit.error - kMinGain * p.norm2)) break;
    fit = std::move(next);
  }
  std::vector<MerlSgLobe> lobes;
  for (size_t j = 0; j < fit.sharpness.size(); ++j) {
    const float s = float(std::clamp(fit.sharpness[j], kMinSharpness, kMaxSharpness));
    const float a = float(fit.amplitude[j]);
    if (a > 0 && std::isfinite(a)) lobes.push_back({s, a});
  }
  std::sort(lobes.begin(), lobes.end(), [](const MerlSgLobe& x, const MerlSgLobe& y) {
    return x.sharpness != y.sharpness ? x.sharpness > y.sharpness : x.amplitude > y.amplitude;
  });
  return lobes;
}

double merl_sg_fit_error(const MerlBrdf& brdf, const std::vector<MerlSgLobe>& lobes) {
  const Profile p = merl_profile(brdf);
  // The floor: the weighted mean of what the lobes leave, at least 0 (the
  // best floor for these lobes).
  std::vector<double> model(p.x.size(), 0.0);
  double sum_w = 0, sum_r = 0;
  for (size_t i = 0; i < p.x.size(); ++i) {
    for (const MerlSgLobe& l : lobes) model[i] += double(l.amplitude) * std::exp(-double(l.sharpness) * p.x[i]);
    sum_w += p.weight[i];
    sum_r += p.weight[i] * (p.value[i] - model[i]);
  }
  const double floor = sum_w > 0 ? std::max(sum_r / sum_w, 0.0) : 0.0;
  double err = 0;
  for (size_t i = 0; i < p.x.size(); ++i) {
    const double r = p.value[i] - model[i] - floor;
    err += p.weight[i] * r * r;
  }
  if (!(p.norm2 > 0)) return err > 0 ? INFINITY : 0.0;
  return std::sqrt(err / p.norm2);
}

}  // namespace svo::render
