// Spherical Gaussians (Tokuyoshi 2015, DESIGN 10.5; issue 19): evaluation,
// product, the exact product integral in a form that does not overflow,
// Iwasaki's approximate product integral, convolution with the smoothing
// kernel of sharpness kappa (Eq. 10), and the lobe-aware weights of Eq. 11
// and Eq. 12 with the normal-aware weight of Eq. 4 as their baseline.
//
// An SG is G(w) = amplitude exp(sharpness (w . axis - 1)), axis unit,
// sharpness >= 0. Its integral over the sphere is
// 2 pi amplitude (1 - exp(-2 sharpness)) / sharpness, and the product of
// two is an SG again: with u = l1 axis1 + l2 axis2,
// G1 G2 = a1 a2 exp(|u| - l1 - l2) G(w, u / |u|, |u|). The exact product
// integral is usually written 4 pi a1 a2 sinh(|u|) / (|u| exp(l1 + l2)),
// whose sinh and exp overflow float past about 88; here it is
// 2 pi a1 a2 exp(|u| - l1 - l2) (1 - exp(-2 |u|)) / |u|, where
// |u| - l1 - l2 <= 0 (the triangle inequality) and (1 - exp(-2x)) / x is
// taken from its series near 0: finite for every sharpness.
#ifndef SVO_SG_GLSL
#define SVO_SG_GLSL
#include "prelude.glsl"

struct SvoSG {
  vec3 axis;        // unit
  float sharpness;  // lambda >= 0
  float amplitude;  // mu
};

SVO_FN SvoSG svo_sg(vec3 axis, float sharpness, float amplitude) {
  SvoSG g;
  g.axis = axis;
  g.sharpness = sharpness;
  g.amplitude = amplitude;
  return g;
}

SVO_FN float svo_sg_eval(SvoSG g, vec3 w) { return g.amplitude * exp(g.sharpness * (dot(w, g.axis) - 1.0f)); }

// (1 - exp(-2 x)) / x for x >= 0, accurate to float rounding everywhere
// (the series 2 - 2x + 4x^2/3 - 2x^3/3 + 4x^4/15 below x = 0.03).
SVO_FN float svo_sg_one_minus_exp2(float x) {
  if (x < 0.03f) return 2.0f + x * (-2.0f + x * (4.0f / 3.0f + x * (-2.0f / 3.0f + x * (4.0f / 15.0f))));
  return (1.0f - exp(-2.0f * x)) / x;
}

// The integral of g over the sphere.
SVO_FN float svo_sg_integral(SvoSG g) {
  return 2.0f * SVO_PI * g.amplitude * svo_sg_one_minus_exp2(g.sharpness);
}

// x . y - 1 for unit x, y, as -|x - y|^2 / 2: no cancellation when they
// are close (where sharp lobes need it).
SVO_FN float svo_sg_cos_minus_one(vec3 x, vec3 y) {
  vec3 d = x - y;
  return -0.5f * dot(d, d);
}

// |u| and |u| - la - lb for u = la axis_a + lb axis_b, the second without
// cancellation: with s = la + lb, r = la lb / s^2 and q = 1 + 2 r (x . y - 1),
// |u| = s sqrt(q) and |u| - s = 2 s r (x . y - 1) / (sqrt(q) + 1). Ratios
// keep every product finite; sharpness is taken up to 1e37.
SVO_FN vec2 svo_sg_sum_length(SvoSG a, SvoSG b) {
  float la = min(a.sharpness, 1.0e37f);
  float lb = min(b.sharpness, 1.0e37f);
  float s = la + lb;
  if (!(s > 0.0f)) return vec2(0.0f);
  float r = (la / s) * (lb / s);
  float c = 2.0f * r * svo_sg_cos_minus_one(a.axis, b.axis);
  float q = sqrt(max(1.0f + c, 0.0f));
  return vec2(s * q, s * (c / (q + 1.0f)));
}

// The product a b as one SG (its axis along a's where the two cancel).
SVO_FN SvoSG svo_sg_product(SvoSG a, SvoSG b) {
  vec2 n = svo_sg_sum_length(a, b);
  float s = min(a.sharpness, 1.0e37f) + min(b.sharpness, 1.0e37f);
  vec3 u = s > 0.0f ? (min(a.sharpness, 1.0e37f) / s) * a.axis + (min(b.sharpness, 1.0e37f) / s) * b.axis : a.axis;
  float len = length(u);
  SvoSG g;
  g.axis = len > 0.0f ? u / len : a.axis;
  g.sharpness = n.x;
  g.amplitude = a.amplitude * b.amplitude * exp(n.y);
  return g;
}

// The exact integral of a b over the sphere ([TS06], in the stable form).
SVO_FN float svo_sg_product_integral(SvoSG a, SvoSG b) {
  vec2 n = svo_sg_sum_length(a, b);
  return 2.0f * SVO_PI * a.amplitude * b.amplitude * exp(n.y) * svo_sg_one_minus_exp2(n.x);
}

// Iwasaki et al.'s approximate product integral [IDN12]: the product's
// sharpness taken as l1 + l2 where the lobes are sharp, i.e.
// 2 pi a1 a2 G(axis1, axis2, l1 l2 / (l1 + l2)) / (l1 + l2).
SVO_FN float svo_sg_product_integral_approx(SvoSG a, SvoSG b) {
  float la = min(a.sharpness, 1.0e37f);
  float lb = min(b.sharpness, 1.0e37f);
  float s = la + lb;
  if (!(s > 0.0f)) return 4.0f * SVO_PI * a.amplitude * b.amplitude;
  float l = s * ((la / s) * (lb / s));
  return 2.0f * SVO_PI * a.amplitude * b.amplitude * exp(l * svo_sg_cos_minus_one(a.axis, b.axis)) / s;
}

// Eq. 10: g convolved with the smoothing kernel G(., ., kappa) (Iwasaki's
// product integral): sharpness l kappa / (l + kappa), amplitude
// 2 pi mu / (l + kappa). kappa = +inf (any value above 3e38) leaves g as it is.
SVO_FN SvoSG svo_sg_smooth(SvoSG g, float kappa) {
  if (!(kappa < 3.0e38f)) return g;
  float s = g.sharpness + kappa;
  SvoSG r;
  r.axis = g.axis;
  r.sharpness = s > 0.0f ? kappa * (g.sharpness / s) : 0.0f;
  r.amplitude = s > 0.0f ? 2.0f * SVO_PI * g.amplitude / s : g.amplitude;
  return r;
}

// Eq. 11 for one lobe per pixel: the normalised exact product integral of
// the two (smoothed) lobes, alpha_ij / sqrt(alpha_ii alpha_jj), in [0, 1],
// raised to beta. Amplitudes cancel.
SVO_FN float svo_sg_similarity(SvoSG a, SvoSG b) {
  SvoSG ua = svo_sg(a.axis, a.sharpness, 1.0f);
  SvoSG ub = svo_sg(b.axis, b.sharpness, 1.0f);
  float ab = svo_sg_product_integral(ua, ub);
  float aa = svo_sg_product_integral(ua, ua);
  float bb = svo_sg_product_integral(ub, ub);
  float norm = sqrt(aa) * sqrt(bb);  // not sqrt(aa bb): that underflows for sharp lobes
  return norm > 0.0f ? clamp(ab / norm, 0.0f, 1.0f) : 0.0f;
}
SVO_FN float svo_weight_eq11(SvoSG a, SvoSG b, float beta) { return pow(svo_sg_similarity(a, b), beta); }

// Eq. 12: one lobe per pixel with Iwasaki's product integral,
// (2 sqrt(li lj) / (li + lj))^beta G(axis_i, axis_j, beta li lj / (li + lj)).
// Two diffuse lobes (equal sharpness) give the normal-aware weight of
// sharpness beta l / 2 (the paper's supplement).
SVO_FN float svo_weight_eq12(SvoSG a, SvoSG b, float beta) {
  float la = min(a.sharpness, 1.0e37f);
  float lb = min(b.sharpness, 1.0e37f);
  float s = la + lb;
  if (!(s > 0.0f)) return 1.0f;
  float r = (la / s) * (lb / s);  // li lj / (li + lj)^2
  return pow(2.0f * sqrt(r), beta) * exp(beta * (s * r) * svo_sg_cos_minus_one(a.axis, b.axis));
}

// Eq. 4, the baseline: the normal-aware weight G(n_i, n_j, 1 / sigma_n^2).
SVO_FN float svo_weight_normal(vec3 ni, vec3 nj, float sigma_n2) {
  return exp(svo_sg_cos_minus_one(ni, nj) / max(sigma_n2, 1.0e-30f));
}

#endif
