// Smith's microsurface model with Gaussian heights and slopes, and the
// view/light-dependent attribute of Heitz & Neyret 2012 (DESIGN section 5).
// Conventions: a direction w is given in the local frame of the mean normal
// (w.z = cos theta); slope variances are per axis of that frame (vec2), equal
// for an isotropic surface; sigma_h is the height standard deviation.
#ifndef SVO_SMITH_GLSL
#define SVO_SMITH_GLSL
#include "erf.glsl"

// Lambda saturates here: the direction is at or below the mean plane and
// nothing is visible (V = g^Lambda = 0). Finite so that sums and ratios of
// Lambdas stay finite; 1e30 + 1e30 is still far from float overflow.
SVO_CONST float SVO_LAMBDA_MAX = 1.0e30f;

// Height CDF, Heitz & Neyret Eq. 5: g(h) = 1 - erfc(h / (sqrt(2) sigma_h)) / 2,
// evaluated as erfc(-x) / 2, accurate in both tails. sigma_h = 0 is a step
// (g(0) = 1/2).
SVO_FN float svo_height_cdf(float h, float sigma_h) {
  if (!(sigma_h > 0.0f)) return h > 0.0f ? 1.0f : (h < 0.0f ? 0.0f : 0.5f);
  return 0.5f * svo_erfc(-h / (SVO_SQRT2 * sigma_h));
}

// s(h) = 2 g(h) - 1 = erf(h / (sqrt(2) sigma_h)): the centred sigmoid of (H5bis).
SVO_FN float svo_height_sigmoid(float h, float sigma_h) {
  if (!(sigma_h > 0.0f)) return h > 0.0f ? 1.0f : (h < 0.0f ? -1.0f : 0.0f);
  return svo_erf(h / (SVO_SQRT2 * sigma_h));
}

// Smith Lambda as a function of a = mu / (sqrt(2) sigma), Heitz & Neyret Eq. 6:
//   Lambda = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2.
// The two terms cancel as a grows (the naive form is 34x off at a = 4 in
// float), so a >= 2 uses the continued fraction of erfcx,
//   sqrt(pi) erfcx(a) = 1 / (a + t),  t = (1/2) / (a + (2/2) / (a + (3/2) / ...)),
// which turns the difference into exp(-a^2) t / (2 sqrt(pi) a (a + t)), with no
// cancellation (16 terms at a = 2: relative error 1.4e-7; fewer beyond).
// Returns a value in [0, SVO_LAMBDA_MAX]; a <= 0 (or NaN) means fully masked.
SVO_FN float svo_smith_lambda_a(float a) {
  if (!(a > 0.0f)) return SVO_LAMBDA_MAX;
  if (a >= 10.0f) return 0.0f;  // below 1e-45
  float e = exp(-a * a);
  float lambda;
  if (a < SVO_ERF_SPLIT) {
    lambda = 0.5f * (e / (a * SVO_SQRT_PI) - (1.0f - svo_erf_small(a)));
  } else if (a < 2.0f) {
    lambda = 0.5f * e * (1.0f / (a * SVO_SQRT_PI) - svo_erfcx_large(a));
  } else {
    // The fraction converges faster as a grows: 16 terms below a = 3, 10
    // below 4, 8 below 6 and 6 beyond keep the truncation's relative error
    // at most the 1.4e-7 of 16 terms at a = 2, and below 1e-7 from a = 3 (a
    // double-precision check against 400 terms), with fewer of its chained
    // divisions where smooth surfaces put most directions.
    int terms = a < 3.0f ? 16 : (a < 4.0f ? 10 : (a < 6.0f ? 8 : 6));
    float t = 0.0f;
    for (int k = terms; k >= 1; --k) t = (0.5f * float(k)) / (a + t);
    lambda = e * (0.5f / SVO_SQRT_PI) * t / (a * (a + t));
  }
  return clamp(lambda, 0.0f, SVO_LAMBDA_MAX);
}

// Lambda(mu, sigma), mu = cot(theta), sigma the slope standard deviation in
// the projected direction (Eq. 6). mu <= 0: at or below the mean plane, fully
// masked. sigma = 0 with mu > 0: a smooth plane, no masking.
SVO_FN float svo_smith_lambda(float mu, float sigma) {
  if (!(mu > 0.0f)) return SVO_LAMBDA_MAX;
  if (!(sigma > 0.0f)) return 0.0f;
  return svo_smith_lambda_a(mu / (SVO_SQRT2 * sigma));
}

// Lambda from cos(theta); a cosine slightly outside [-1, 1] from rounding is clamped.
SVO_FN float svo_smith_lambda_cos(float cos_theta, float sigma) {
  float c = clamp(cos_theta, -1.0f, 1.0f);
  if (!(c > 0.0f)) return SVO_LAMBDA_MAX;
  // (1 - c)(1 + c): exact 1 - c near c = 1, where 1 - c * c would lose sin(theta).
  float sin_sigma = sqrt(max(0.0f, (1.0f - c) * (1.0f + c))) * sigma;
  if (!(sin_sigma > 0.0f)) return 0.0f;
  return svo_smith_lambda_a(c / (SVO_SQRT2 * sin_sigma));
}

// Lambda for a direction w in the mean-normal frame and per-axis slope
// variances sigma2: the projected variance is (wx^2 s2x + wy^2 s2y) / (wx^2 + wy^2),
// so a = wz / sqrt(2 (wx^2 s2x + wy^2 s2y)) needs no division by sin(theta).
SVO_FN float svo_smith_lambda_dir(vec3 w, vec2 sigma2) {
  if (!(w.z > 0.0f)) return SVO_LAMBDA_MAX;
  float d2 = 2.0f * (w.x * w.x * sigma2.x + w.y * w.y * sigma2.y);
  if (!(d2 > 0.0f)) return 0.0f;
  return svo_smith_lambda_a(w.z / sqrt(d2));
}

// Smith masking G1 = 1 / (1 + Lambda), in [0, 1].
SVO_FN float svo_smith_g1(float lambda) {
  return 1.0f / (1.0f + lambda);
}

// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(v) + Lambda(l)):
// the fraction of the surface seen from both, int g'(h) g(h)^(Lv + Ll) dh.
SVO_FN float svo_smith_g2(float lambda_v, float lambda_l) {
  return 1.0f / (1.0f + lambda_v + lambda_l);
}

// Weight of a_s in the view- and light-dependent attribute, Heitz & Neyret
// Eq. 17: 2 (L + 1) / (L + 2) - 1, written L / (L + 2) (the left form gives 0
// for L = 1e-9 and NaN for L = inf). L = Lambda(v) + Lambda(l) >= 0.
SVO_FN float svo_attribute_weight(float L) {
  if (!(L > 0.0f)) return 0.0f;
  if (L >= SVO_LAMBDA_MAX) return 1.0f;
  return L / (L + 2.0f);
}

// abar(v, l) = abar + a_s L / (L + 2) (Eq. 17): exact for a(h) = abar + a_s s(h).
SVO_FN float svo_attribute_vl(float abar, float a_s, float L) {
  return abar + a_s * svo_attribute_weight(L);
}

SVO_FN vec3 svo_attribute_vl3(vec3 abar, vec3 a_s, float L) {
  return abar + a_s * svo_attribute_weight(L);
}

#endif
