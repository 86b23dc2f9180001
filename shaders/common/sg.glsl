// Spherical Gaussians (Tokuyoshi 2015, DESIGN 10.5; issue 19): evaluation,
// product, the exact product integral in a form that does not overflow,
// Iwasaki's approximate product integral, convolution with the smoothing
// kernel of sharpness kappa (Eq. 10), and the lobe-aware weights of Eq. 11
// and Eq. 12 with the normal-aware weight of Eq. 4 as their baseline;
// anisotropic SGs (Xu et al. 2013): evaluation, smoothing, the approximate
// product integral of two (with a Jacobi eigen-solver) and Eq. 13.
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
#include "frame.glsl"
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
  if (!(r > 0.0f)) return beta > 0.0f ? 0.0f : 1.0f;
  // One exp: (2 sqrt(r))^beta = exp(beta log(4 r) / 2). r is kept at the
  // smallest normal float: the log of a denormal differs between hosts (a
  // GPU may flush it), and the weight there is below 1e-19 anyway.
  float rn = max(r, 1.17549435e-38f);
  return exp(beta * (0.5f * log(4.0f * rn) + (s * r) * svo_sg_cos_minus_one(a.axis, b.axis)));
}

// Eq. 4, the baseline: the normal-aware weight G(n_i, n_j, 1 / sigma_n^2).
SVO_FN float svo_weight_normal(vec3 ni, vec3 nj, float sigma_n2) {
  return exp(svo_sg_cos_minus_one(ni, nj) / max(sigma_n2, 1.0e-30f));
}

// ---------------------------------------------------------------------------
// Lobes on the fly (Wang et al. 2009; Tokuyoshi's supplement). The NDF as
// an SG about the normal in half-vector space: Beckmann and GGX near their
// peak, exp(-tan^2 / alpha^2) ~ exp(-theta^2 / alpha^2), sharpness
// 2 / alpha^2; the Phong NDF cos^e, sharpness e. An SG's angular variance
// is 1 / sharpness per axis, so a voxel's slope variance sigma^2 (per axis)
// widens it to 1 / (1 / l + sigma^2), as the forward pass adds variances.
SVO_FN float svo_ndf_sharpness(uint kind, float alpha2, float exponent, float sigma2) {
  float l = kind == 3u ? max(exponent, 0.0f) : 2.0f / max(alpha2, 1.0e-8f);  // 3: SVO_BRDF_PHONG
  return l / (1.0f + l * max(sigma2, 0.0f));
}

// The reflection lobe of a half-vector SG of sharpness lh about the unit
// normal n, seen from the unit direction v (towards the eye): axis
// reflect(-v, n), sharpness lh / (4 |n . v|) (the half-vector to
// reflected-direction Jacobian), |n . v| kept above 0.1 so that grazing
// views do not give a lobe of zero width.
SVO_FN SvoSG svo_reflection_lobe(vec3 n, vec3 v, float lh) {
  float c = dot(n, v);
  SvoSG g;
  g.axis = normalize(2.0f * c * n - v);
  g.sharpness = lh / (4.0f * max(abs(c), 0.1f));
  g.amplitude = 1.0f;
  return g;
}

// The diffuse lobe: the clamped cosine about n as one SG (sharpness 2.133,
// the least-squares fit).
SVO_FN SvoSG svo_diffuse_lobe(vec3 n) { return svo_sg(n, 2.133f, 1.0f); }

// ---------------------------------------------------------------------------
// Anisotropic spherical Gaussians (Xu et al. 2013), as Tokuyoshi's section
// 4.2 uses them: A(w) = amplitude max(w . z, 0) exp(-lx (w . x)^2 - ly (w . y)^2)
// for an orthonormal frame (x, y, z) and bandwidths lx, ly >= 0.

struct SvoASG {
  vec3 x;
  vec3 y;
  vec3 z;  // the lobe axis
  float lx;
  float ly;
  float amplitude;
};

SVO_FN SvoASG svo_asg(vec3 x, vec3 y, vec3 z, float lx, float ly, float amplitude) {
  SvoASG g;
  g.x = x;
  g.y = y;
  g.z = z;
  g.lx = lx;
  g.ly = ly;
  g.amplitude = amplitude;
  return g;
}

SVO_FN float svo_asg_eval(SvoASG g, vec3 w) {
  float u = dot(w, g.x);
  float v = dot(w, g.y);
  return g.amplitude * max(dot(w, g.z), 0.0f) * exp(-g.lx * u * u - g.ly * v * v);
}

// The ASG convolved with the SG kernel G(., ., kappa) (Xu's approximation,
// Tokuyoshi's section 4.2): bandwidths l kappa / (2 l + kappa), amplitude
// times 2 pi / sqrt((2 lx + kappa)(2 ly + kappa)); kappa = +inf leaves it.
SVO_FN SvoASG svo_asg_smooth(SvoASG g, float kappa) {
  if (!(kappa < 3.0e38f)) return g;
  SvoASG r = g;
  float sx = 2.0f * g.lx + kappa;
  float sy = 2.0f * g.ly + kappa;
  r.lx = sx > 0.0f ? kappa * (g.lx / sx) : 0.0f;
  r.ly = sy > 0.0f ? kappa * (g.ly / sy) : 0.0f;
  r.amplitude = sx > 0.0f && sy > 0.0f ? g.amplitude * 2.0f * SVO_PI / (sqrt(sx) * sqrt(sy)) : g.amplitude;
  return r;
}

// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations
// (Rutishauser's stable formulas), which keeps float's relative accuracy
// where Cardano's closed form loses it (the banding of the paper's Fig. 19):
// `values` ascending, `vectors` the matching unit columns.
struct SvoEigen3 {
  vec3 values;
  mat3 vectors;
};

SVO_FN SvoEigen3 svo_eigen_symmetric3(mat3 a) {
  mat3 v = mat3(1.0f);
  for (int sweep = 0; sweep < 6; ++sweep) {
    for (int k = 0; k < 3; ++k) {
      int p = k == 2 ? 1 : 0;
      int q = k == 0 ? 1 : 2;
      float apq = a[q][p];
      float scale = abs(a[p][p]) + abs(a[q][q]);
      if (!(abs(apq) > 1.0e-9f * scale) || apq == 0.0f) continue;
      float theta = (a[q][q] - a[p][p]) / (2.0f * apq);
      float t = (theta >= 0.0f ? 1.0f : -1.0f) / (abs(theta) + sqrt(theta * theta + 1.0f));
      float c = 1.0f / sqrt(t * t + 1.0f);
      float s = t * c;
      mat3 j = mat3(1.0f);
      j[p][p] = c;
      j[q][q] = c;
      j[q][p] = s;
      j[p][q] = -s;
      a = transpose(j) * a * j;
      v = v * j;
    }
  }
  // Sort ascending (three compares, columns swapped along).
  vec3 e = vec3(a[0][0], a[1][1], a[2][2]);
  if (e.y < e.x) {
    e = vec3(e.y, e.x, e.z);
    v = mat3(v[1], v[0], v[2]);
  }
  if (e.z < e.y) {
    e = vec3(e.x, e.z, e.y);
    v = mat3(v[0], v[2], v[1]);
  }
  if (e.y < e.x) {
    e = vec3(e.y, e.x, e.z);
    v = mat3(v[1], v[0], v[2]);
  }
  SvoEigen3 r;
  r.values = e;
  r.vectors = v;
  return r;
}

// The approximate integral over the sphere of the product of two ASGs, by
// Laplace's method on F(w) = log(w . z1) + log(w . z2) - w^T A w, with
// A = lx1 x1 x1^T + ly1 y1 y1^T + lx2 x2 x2^T + ly2 y2 y2^T (the product is
// exp(F) where both cosines are positive). As in Xu et al. and Tokuyoshi,
// the peak starts at A's smallest eigenvector v0 (w^T A w = e0 + (e1 - e0)
// (w . v1)^2 + (e2 - e0)(w . v2)^2 for unit w), turned towards z1 + z2;
// where one cosine is negative there (the case the paper names: z1 . z2 < 0
// with lx = ly puts v0 across the bisector) it starts at the bisector.
// Newton steps on the sphere then move it to F's maximum, where -Hess F =
// P (2 A + z1 z1^T / c1^2 + z2 z2^T / c2^2) P + (2 - 2 w^T A w) P
// (P: the tangent plane). The integral is c1 c2 exp(-w^T A w) pi /
// sqrt(det B), B = -Hess F / 2 - I / 2: Laplace's 2 pi / sqrt(det(-Hess F))
// with the next order of the sphere's measure and of the cosines (exact to
// O(1 / l^2) for two aligned isotropic lobes). Bandwidths below 10 are low
// frequency, where this and every closed form of ASG products err.
SVO_FN mat3 svo_asg_exponent(SvoASG a, SvoASG b) {
  return a.lx * outerProduct(a.x, a.x) + a.ly * outerProduct(a.y, a.y) + b.lx * outerProduct(b.x, b.x) +
         b.ly * outerProduct(b.y, b.y);
}

// u^T (A + za za^T / (2 ca^2) + zb zb^T / (2 cb^2)) v: -Hess F / 2 off the
// sphere's own term, at a point whose cosines are ca, cb.
SVO_FN float svo_asg_form(mat3 m, vec3 za, vec3 zb, float ca, float cb, vec3 u, vec3 v) {
  return dot(u, m * v) + 0.5f * (dot(u, za) * dot(v, za) / (ca * ca) + dot(u, zb) * dot(v, zb) / (cb * cb));
}

// -Hess F / 2 - I / 2 in the tangent frame f at w: (tt, bb, tb).
SVO_FN vec3 svo_asg_curvature(mat3 m, vec3 za, vec3 zb, vec3 w, SvoFrame f) {
  float ca = max(dot(w, za), 1.0e-4f);
  float cb = max(dot(w, zb), 1.0e-4f);
  float diag = 0.5f - dot(w, m * w);
  return vec3(svo_asg_form(m, za, zb, ca, cb, f.t, f.t) + diag, svo_asg_form(m, za, zb, ca, cb, f.b, f.b) + diag,
              svo_asg_form(m, za, zb, ca, cb, f.t, f.b));
}

SVO_FN float svo_asg_product_integral(SvoASG a, SvoASG b) {
  mat3 m = svo_asg_exponent(a, b);
  SvoEigen3 e = svo_eigen_symmetric3(m);
  vec3 mid = a.z + b.z;
  vec3 w = e.vectors[0];
  if (dot(w, length(mid) > 1.0e-6f ? mid : a.z) < 0.0f) w = -w;
  if (!(dot(w, a.z) > 0.0f && dot(w, b.z) > 0.0f)) {
    if (!(length(mid) > 1.0e-6f)) return 0.0f;  // opposite axes: the supports meet on a circle only
    w = normalize(mid);
  }
  for (int i = 0; i < 8; ++i) {
    SvoFrame f = svo_tangent_frame(w);
    float ca = max(dot(w, a.z), 1.0e-4f);
    float cb = max(dot(w, b.z), 1.0e-4f);
    vec3 g = a.z / ca + b.z / cb - 2.0f * (m * w);
    vec2 gt = vec2(dot(f.t, g), dot(f.b, g));
    // Newton: (-Hess F) d = grad F, -Hess F = 2 (B + I / 2).
    vec3 h = 2.0f * svo_asg_curvature(m, a.z, b.z, w, f) + vec3(1.0f, 1.0f, 0.0f);
    float det = h.x * h.y - h.z * h.z;
    vec2 d = det > 0.0f && h.x > 0.0f ? vec2(h.y * gt.x - h.z * gt.y, h.x * gt.y - h.z * gt.x) / det
                                      : 0.05f * gt / (length(gt) + 1.0f);
    float len = length(d);
    if (len > 0.3f) d *= 0.3f / len;
    w = normalize(w + d.x * f.t + d.y * f.b);
  }
  float ca = dot(w, a.z);
  float cb = dot(w, b.z);
  if (!(ca > 0.0f && cb > 0.0f)) return 0.0f;
  vec3 c = svo_asg_curvature(m, a.z, b.z, w, svo_tangent_frame(w));
  // Its eigenvalues, each kept above 1e-3 (a lobe flatter than that is not a lobe).
  float tr = 0.5f * (c.x + c.y);
  float disc = sqrt(max(0.25f * (c.x - c.y) * (c.x - c.y) + c.z * c.z, 0.0f));
  float bx = max(tr - disc, 1.0e-3f);
  float by = max(tr + disc, 1.0e-3f);
  return a.amplitude * b.amplitude * SVO_PI * exp(-dot(w, m * w)) * ca * cb / (sqrt(bx) * sqrt(by));
}

// Eq. 13 for one lobe per pixel: the normalised approximate product
// integral of the two (smoothed) ASGs, raised to beta.
SVO_FN float svo_weight_eq13(SvoASG a, SvoASG b, float beta) {
  SvoASG ua = a;
  SvoASG ub = b;
  ua.amplitude = 1.0f;
  ub.amplitude = 1.0f;
  float norm = sqrt(svo_asg_product_integral(ua, ua)) * sqrt(svo_asg_product_integral(ub, ub));
  float q = norm > 0.0f ? clamp(svo_asg_product_integral(ua, ub) / norm, 0.0f, 1.0f) : 0.0f;
  return pow(q, beta);
}

#endif
