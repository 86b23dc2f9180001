// Beckmann (Gaussian slope) microfacet BRDF whose slope variance is the
// micro-BRDF's plus the voxel's (Heitz & Neyret section 5.5: convolving two
// Gaussians adds variances), with the matching Smith masking of smith.glsl.
// Directions are in the mean-normal frame; sigma2 holds per-axis slope
// variances (alpha^2 = 2 sigma^2 per axis).
#ifndef SVO_BECKMANN_GLSL
#define SVO_BECKMANN_GLSL
#include "smith.glsl"

// Slope variances below this are raised to it, so that a mirror keeps a
// finite peak (D(n) <= 1 / (2 pi 1e-8)): a lobe of about 0.006 degrees.
SVO_CONST float SVO_MIN_SLOPE_VARIANCE = 1.0e-8f;

// sigma^2 = sigma_n^2 + sigma_rho^2, floored at SVO_MIN_SLOPE_VARIANCE.
SVO_FN vec2 svo_total_slope_variance(vec2 sigma_n2, vec2 sigma_rho2) {
  return max(sigma_n2 + sigma_rho2, vec2(SVO_MIN_SLOPE_VARIANCE));
}

// Beckmann NDF for a unit micronormal m: D(m) = P22(-mx/mz, -my/mz) / mz^4 with
// P22 the 2D Gaussian slope density; int D(m) m.z dm = 1. Zero below the plane.
SVO_FN float svo_beckmann_d(vec3 m, vec2 sigma2) {
  if (!(m.z > 0.0f)) return 0.0f;
  vec2 s2 = max(sigma2, vec2(SVO_MIN_SLOPE_VARIANCE));
  float z2 = m.z * m.z;
  float e = (m.x * m.x / s2.x + m.y * m.y / s2.y) / (2.0f * z2);
  return svo_exp_neg(e) / (2.0f * SVO_PI * sqrt(s2.x * s2.y) * z2 * z2);
}

// The cosine factor of a Lambertian micro-surface whose slopes have
// variances sigma2 (per axis of the frame of v and l, mean zero): the mean
// over the slopes of max(l.m, 0) (v.m) / (m.n), the light a facet m receives
// times the share of the view it takes, divided by v.n; no masking. To first
// order in the slopes, l.m is Gaussian with mean l.z and variance
// s^2 = l.x^2 sx^2 + l.y^2 sy^2, and the view weight (v.m) / (m.n v.z) is
// 1 + Y with cov(l.m, Y) = lean = (sx^2 l.x v.x + sy^2 l.y v.y) / v.z, so
//   E[max(l.m, 0) (1 + Y)] = l.z Phi(z) + s phi(z) + lean Phi(z), z = l.z / s
// (Stein's lemma for the last term): tilted facets face the light less on
// average, the facets the viewer sees more of lean towards it, and near and
// past the terminator (l.z <= s) the facets that still face the light keep
// the mean above zero, where the clamped l.z goes dark (a coarse voxel's
// mean normal turned from the light showed as a dark band across a
// defocused sphere, docs/RESULTS.md Fig. 4). Far from the terminator it is
// (l.z + lean) times 1 / sqrt(1 + sx^2 + sy^2), which stands for the facets'
// normalisation (the same to first order, positive for any slopes). v.z is
// floored at 0.25 where the expansion would blow up at grazing views.
// Beyond slope variance 0.1 per axis the expansion undershoots (facets
// facing away from v drop out of the true mean: at variance 1 it would give
// half the true value), so the variances are capped there: the factor then
// lies between the clamped l.z and the true mean (Monte Carlo, variances
// 0.02 to 3). The macro-normal Lambert term of paper Eq. 13 is max(l.z, 0).
SVO_CONST float SVO_ROUGH_LAMBERT_MAX_VARIANCE = 0.1f;

SVO_FN float svo_rough_lambert(vec3 v, vec3 l, vec2 sigma2_in) {
  vec2 sigma2 = min(sigma2_in, vec2(SVO_ROUGH_LAMBERT_MAX_VARIANCE));
  float shrink = 1.0f / sqrt(1.0f + sigma2.x + sigma2.y);
  float lean = (sigma2.x * l.x * v.x + sigma2.y * l.y * v.y) / max(v.z, 0.25f);
  float s = sqrt(l.x * l.x * sigma2.x + l.y * l.y * sigma2.y);
  if (!(s > 1.0e-6f * abs(l.z))) return max((l.z + lean) * shrink, 0.0f);
  float z = l.z / s;
  float lit = 0.5f * svo_erfc(-z / SVO_SQRT2);          // Phi(z): the facets facing the light
  float density = 0.398942280f * svo_exp_neg(0.5f * z * z);  // phi(z)
  return max((l.z * lit + s * density + lean * lit) * shrink, 0.0f);
}

// The variances svo_specular_brdf uses: sigma2 floored as the NDF's.
SVO_FN vec2 svo_specular_variance(vec2 sigma2) {
  return max(sigma2, vec2(SVO_MIN_SLOPE_VARIANCE));
}

// svo_specular_brdf given lambda_v = svo_smith_lambda_dir(v, s2) with s2 =
// svo_specular_variance(sigma2): a shading point with several lights
// computes the view's once.
SVO_FN float svo_specular_brdf_view(vec3 v, vec3 l, vec2 s2, float lambda_v) {
  if (!(v.z > 0.0f) || !(l.z > 0.0f)) return 0.0f;
  vec3 h = v + l;
  float hl = length(h);
  if (!(hl > 0.0f)) return 0.0f;
  h = h / hl;
  float g2 = svo_smith_g2(lambda_v, svo_smith_lambda_dir(l, s2));
  return svo_beckmann_d(h, s2) * g2 / (4.0f * v.z * l.z);
}

// Cook-Torrance specular lobe without Fresnel:
//   f(v, l) = D(h) G2(v, l) / (4 (n.v) (n.l)),
// height-correlated Smith G2 with the same (floored) variances as D.
// Zero when v or l is at or below the mean plane; symmetric in v and l.
SVO_FN float svo_specular_brdf(vec3 v, vec3 l, vec2 sigma2) {
  vec2 s2 = svo_specular_variance(sigma2);
  return svo_specular_brdf_view(v, l, s2, v.z > 0.0f ? svo_smith_lambda_dir(v, s2) : 0.0f);
}

#endif
