// Procedural detail octaves (issue 6): gradient noise that displaces a
// surface along its normal below the octree's stored resolution, and the
// rule that decides, for a footprint of radius r, which octaves are drawn
// explicitly and which only count as statistics (height variance, slope
// variance, colour correlation). The voxelizer (C++), the renderer (GLSL and
// C++) and the reference all call these functions, so the detail the octree
// folds into its statistics is exactly the detail the tracer draws.
//
// Octave k (k = 0 .. octaves - 1) has wavelength lambda_k = wavelength 2^-k
// and amplitude a_k = amplitude gain^k; it adds a_k n(p / lambda_k + o_k)
// to the height, n the gradient noise below (zero mean, variance
// SVO_NOISE_VARIANCE, per-axis derivative variance SVO_NOISE_SLOPE_VARIANCE,
// both over a uniform p; tests/numerics/detail_test.cpp measures them).
//
// Explicit weight e_k(r): 1 when lambda_k >= 8 r, 0 when lambda_k <= 4 r
// (SVO_DETAIL_DRAWN_FROM radii), a smoothstep in log2(lambda_k / 4r)
// between. An octave that is a fraction e explicit draws e a_k n and keeps (1 - e^2) a_k^2 of its variances as
// statistics, so that explicit and statistical parts always add up to the
// octave's own variance: the appearance cannot jump where an octave changes
// from one to the other.
#ifndef SVO_DETAIL_GLSL
#define SVO_DETAIL_GLSL
#include "prelude.glsl"

// Variance of svo_gradient_noise's value and of each of its partial
// derivatives over a uniform position (Monte Carlo, 2^24 points).
SVO_CONST float SVO_NOISE_VARIANCE = 0.03654f;
SVO_CONST float SVO_NOISE_SLOPE_VARIANCE = 0.2486f;
// Bound on |n| and on |grad n|, for Lipschitz bounds and margins.
SVO_CONST float SVO_NOISE_MAX = 1.0f;
SVO_CONST float SVO_NOISE_MAX_GRADIENT = 3.5f;
// Bound on n's second derivative along any unit direction (the largest of
// 2^23 random samples is 10.0; tests/numerics/detail_test.cpp).
SVO_CONST float SVO_NOISE_MAX_CURVATURE = 14.0f;
// An octave is drawn (in part) for a footprint of radius r once its
// wavelength exceeds this many radii, and whole from twice that. Drawing
// from 8 radii instead halved the cone elements in the shell and, at 256^3
// and 64 x 64, took a third of the deep zoom's excess frame-to-frame change
// away; at 512^3 and 128 x 128 it did not, and it left octaves the finest
// voxels could draw as statistics: relMSE against the ground truth rose by
// a third from zoom 2.5 to 40 (docs/RESULTS.md, "Deep zoom").
SVO_CONST float SVO_DETAIL_DRAWN_FROM = 4.0f;

struct SvoDetail {
  uint octaves;     // 0: no detail
  uint seed;
  float amplitude;  // of octave 0, scene units
  float wavelength;  // of octave 0, scene units
  float gain;       // amplitude ratio of consecutive octaves
};

SVO_FN uint svo_hash(uint x) {
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// A pseudo-random gradient in [-1, 1]^3 for lattice corner c.
SVO_FN vec3 svo_corner_gradient(ivec3 c, uint seed) {
  uint h = svo_hash(uint(c.x) + svo_hash(uint(c.y) + svo_hash(uint(c.z) + seed)));
  return vec3(float(h & 1023u), float((h >> 10u) & 1023u), float((h >> 20u) & 1023u)) * (2.0f / 1023.0f) - 1.0f;
}

// Gradient noise (Perlin's, with quintic fades and random gradients):
// (d n / dp, n) at p.
SVO_FN vec4 svo_gradient_noise(vec3 p, uint seed) {
  vec3 i = floor(p);
  vec3 f = p - i;
  ivec3 c = ivec3(i);
  vec3 u = f * f * f * (f * (f * 6.0f - 15.0f) + 10.0f);
  vec3 du = 30.0f * f * f * (f * (f - 2.0f) + 1.0f);
  vec3 ga = svo_corner_gradient(c, seed);
  vec3 gb = svo_corner_gradient(c + ivec3(1, 0, 0), seed);
  vec3 gc = svo_corner_gradient(c + ivec3(0, 1, 0), seed);
  vec3 gd = svo_corner_gradient(c + ivec3(1, 1, 0), seed);
  vec3 ge = svo_corner_gradient(c + ivec3(0, 0, 1), seed);
  vec3 gf = svo_corner_gradient(c + ivec3(1, 0, 1), seed);
  vec3 gg = svo_corner_gradient(c + ivec3(0, 1, 1), seed);
  vec3 gh = svo_corner_gradient(c + ivec3(1, 1, 1), seed);
  float va = dot(ga, f);
  float vb = dot(gb, f - vec3(1.0f, 0.0f, 0.0f));
  float vc = dot(gc, f - vec3(0.0f, 1.0f, 0.0f));
  float vd = dot(gd, f - vec3(1.0f, 1.0f, 0.0f));
  float ve = dot(ge, f - vec3(0.0f, 0.0f, 1.0f));
  float vf = dot(gf, f - vec3(1.0f, 0.0f, 1.0f));
  float vg = dot(gg, f - vec3(0.0f, 1.0f, 1.0f));
  float vh = dot(gh, f - vec3(1.0f, 1.0f, 1.0f));
  // n = sum of corner values weighted by products of fades, expanded.
  float kx = vb - va;
  float ky = vc - va;
  float kz = ve - va;
  float kxy = va - vb - vc + vd;
  float kyz = va - vc - ve + vg;
  float kzx = va - vb - ve + vf;
  float kxyz = -va + vb + vc - vd + ve - vf - vg + vh;
  float n = va + u.x * kx + u.y * ky + u.z * kz + u.x * u.y * kxy + u.y * u.z * kyz + u.z * u.x * kzx +
            u.x * u.y * u.z * kxyz;
  // The corner values' own gradients, blended the same way ...
  vec3 g = ga + u.x * (gb - ga) + u.y * (gc - ga) + u.z * (ge - ga) + u.x * u.y * (ga - gb - gc + gd) +
           u.y * u.z * (ga - gc - ge + gg) + u.z * u.x * (ga - gb - ge + gf) +
           u.x * u.y * u.z * (-ga + gb + gc - gd + ge - gf - gg + gh);
  // ... plus the derivatives of the fades.
  g += du * vec3(kx + u.y * kxy + u.z * kzx + u.y * u.z * kxyz, ky + u.z * kyz + u.x * kxy + u.z * u.x * kxyz,
                 kz + u.x * kzx + u.y * kyz + u.x * u.y * kxyz);
  return vec4(g, n);
}

SVO_FN float svo_detail_wavelength(SvoDetail d, uint k) { return d.wavelength * exp2(-float(k)); }

SVO_FN float svo_detail_amplitude(SvoDetail d, uint k) { return d.amplitude * pow(d.gain, float(k)); }

// Fraction of an octave of wavelength `lambda` drawn explicitly for a
// footprint of radius r (r <= 0: all of it).
SVO_FN float svo_detail_weight(float lambda, float r) {
  if (!(r > 0.0f)) return 1.0f;
  float x = clamp(log2(lambda / (SVO_DETAIL_DRAWN_FROM * r)), 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

// Rows of a fixed rotation (0.7 rad about (1, 2, 3)): the noise lattice is
// turned away from the axes, so that a surface aligned with them (a plane)
// does not slice every octave at the same place in its cells, where the
// noise's variance would differ from its average over space.
SVO_CONST vec3 SVO_DETAIL_ROW0 = vec3(0.781639174f, -0.482929284f, 0.394739798f);
SVO_CONST vec3 SVO_DETAIL_ROW1 = vec3(0.550117231f, 0.832030134f, -0.071392499f);
SVO_CONST vec3 SVO_DETAIL_ROW2 = vec3(-0.293957878f, 0.272956339f, 0.916015067f);

// (gradient, value) of octave k's displacement a_k n(R p / lambda_k + o_k).
SVO_FN vec4 svo_detail_octave(SvoDetail d, uint k, vec3 p) {
  float lambda = svo_detail_wavelength(d, k);
  float a = svo_detail_amplitude(d, k);
  vec3 q = vec3(dot(SVO_DETAIL_ROW0, p), dot(SVO_DETAIL_ROW1, p), dot(SVO_DETAIL_ROW2, p));
  vec3 offset = vec3(0.37f, 0.71f, 0.13f) * float(k) + 0.5f;
  vec4 gn = svo_gradient_noise(q / lambda + offset, d.seed + k * 0x9E3779B9u);
  vec3 g = gn.x * SVO_DETAIL_ROW0 + gn.y * SVO_DETAIL_ROW1 + gn.z * SVO_DETAIL_ROW2;  // R^T grad n
  return vec4(g * (a / lambda), gn.w * a);
}

// The displacement drawn at footprint r beyond what is drawn at footprint
// r_stored >= r, and how far it can move along a ray.
struct SvoDetailSample {
  vec4 displacement;  // (gradient, value): sum of (e_k(r) - e_k(r_stored)) times octave k
  vec4 change;        // bounds on |value(p + s dir) - value(p)| for the four distances s
  vec4 change2;       // the same for the four distances s2
};

// Octaves already whole at r_stored, or still none at r, cost nothing. For
// each octave the change over a distance s is bounded three ways, and the
// least bound taken: its amplitude bound plus its value at p (the fine
// octaves), its slope bound
// times s (the Lipschitz bound), and its own slope along `dir` at p times s
// plus half its curvature bound times s^2 (the coarse octaves, whose slope
// at p is usually far below the bound). A grazing ray in the shell the
// octaves can reach then steps several times farther than the sum of the
// slope bounds allows.
SVO_FN SvoDetailSample svo_detail_displacement_along(SvoDetail d, vec3 p, float r, float r_stored, vec3 dir,
                                                      vec4 s, vec4 s2) {
  SvoDetailSample res;
  res.displacement = vec4(0.0f);
  res.change = vec4(0.0f);
  res.change2 = vec4(0.0f);
  for (uint k = 0u; k < d.octaves; ++k) {
    float lambda = svo_detail_wavelength(d, k);
    float w = svo_detail_weight(lambda, r) - svo_detail_weight(lambda, r_stored);
    if (lambda <= SVO_DETAIL_DRAWN_FROM * r) break;  // this octave and all finer ones: statistics only
    if (!(w > 0.0f)) continue;
    vec4 o = w * svo_detail_octave(d, k, p);
    res.displacement += o;
    float a = w * svo_detail_amplitude(d, k);
    float along = abs(dot(vec3(o), dir));
    float curvature = 0.5f * a * SVO_NOISE_MAX_CURVATURE / (lambda * lambda);
    float slope = a * SVO_NOISE_MAX_GRADIENT / lambda;
    vec4 cap = vec4(a * SVO_NOISE_MAX + abs(o.w));
    res.change += min(cap, min(s * slope, s * along + curvature * s * s));
    res.change2 += min(cap, min(s2 * slope, s2 * along + curvature * s2 * s2));
  }
  return res;
}

// (gradient, value) of the displacement drawn at footprint r beyond what is
// drawn at footprint r_stored >= r.
SVO_FN vec4 svo_detail_displacement(SvoDetail d, vec3 p, float r, float r_stored) {
  return svo_detail_displacement_along(d, p, r, r_stored, vec3(0.0f), vec4(0.0f), vec4(0.0f)).displacement;
}

// Variances that move from statistics to explicit drawing between footprints
// r_stored and r <= r_stored: (height variance, per-axis slope variance).
// With r = 0 it is all the statistics the octree holds at r_stored.
SVO_FN vec2 svo_detail_moved_variance(SvoDetail d, float r, float r_stored) {
  vec2 sum = vec2(0.0f);
  for (uint k = 0u; k < d.octaves; ++k) {
    float lambda = svo_detail_wavelength(d, k);
    float e = svo_detail_weight(lambda, r);
    float e0 = svo_detail_weight(lambda, r_stored);
    float a = svo_detail_amplitude(d, k);
    float moved = (e * e - e0 * e0) * a * a;
    sum += moved * vec2(SVO_NOISE_VARIANCE, SVO_NOISE_SLOPE_VARIANCE / (lambda * lambda));
  }
  return sum;
}

// Bounds on what is drawn at footprint r beyond footprint r_stored:
// (largest |displacement|, largest |gradient|), over whole octaves (those
// with lambda_k > 4 r and not whole at r_stored), without a loop: octave
// k's amplitude is amplitude gain^k and its slope (amplitude / wavelength)
// (2 gain)^k.
SVO_FN float svo_detail_series(float q, float k0, float k1) {
  if (!(k1 > k0)) return 0.0f;
  if (abs(q - 1.0f) < 1.0e-4f) return k1 - k0;
  return (pow(q, k1) - pow(q, k0)) / (q - 1.0f);
}

// Octaves drawn at all at footprint r: those with lambda_k > 4 r.
SVO_FN float svo_detail_drawn(SvoDetail d, float r) {
  float n = float(d.octaves);
  return r > 0.0f ? clamp(ceil(log2(d.wavelength / (SVO_DETAIL_DRAWN_FROM * r))), 0.0f, n) : n;
}

SVO_FN vec2 svo_detail_bounds(SvoDetail d, float r, float r_stored) {
  float n = float(d.octaves);
  float k1 = svo_detail_drawn(d, r);
  float k0 = clamp(floor(log2(d.wavelength / (2.0f * SVO_DETAIL_DRAWN_FROM * r_stored))) + 1.0f, 0.0f, n);
  return vec2(d.amplitude * SVO_NOISE_MAX * svo_detail_series(d.gain, k0, k1),
              d.amplitude / d.wavelength * SVO_NOISE_MAX_GRADIENT * svo_detail_series(2.0f * d.gain, k0, k1));
}

// Colour-height covariance c = a_s sigma_h sqrt(pi) / 3 is what adds up when
// independent height components with linear colour join (a_s is the
// regression of colour on erf(h / (sqrt(2) sigma_h)) over Gaussian heights):
// moving variance `moved` of heights whose colour changes by `colour_slope`
// per unit height between statistics and explicit drawing changes c by
// colour_slope moved. The a_s of a voxel whose height variance goes from
// var to var + moved (moved may be negative).
SVO_FN vec3 svo_detail_fold_a_s(vec3 a_s, float var, float moved, vec3 colour_slope) {
  float var1 = var + moved;
  if (!(var1 > 1.0e-4f * max(var, 1.0e-30f))) return vec3(0.0f);
  vec3 c = a_s * sqrt(max(var, 0.0f)) + (3.0f / SVO_SQRT_PI) * colour_slope * moved;
  return c / sqrt(var1);
}

#endif
