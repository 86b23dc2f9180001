// The bandwidth operators of Bagher et al. 2013 (DESIGN 10.3): Fig. 4's 2x2
// matrices, the one-bounce propagation of Eq. 3-4, the image-space
// bandwidth of Eq. 6, the pyramid level of Eq. 11, the variance term of
// Eq. 9 and our band-limit from the voxels' slope variance. Pure math: the
// tests call these (shared_math.h) and bandwidth.glsl builds on them.
//
// A bandwidth nu = (nu_s, nu_a) gives the half-sides of the rectangle
// [-nu_s, nu_s] x [-nu_a, nu_a] that holds the local light field's spectrum
// around a ray: nu_s in cycles per scene unit, nu_a in cycles per radian.
// A linear operator M maps that rectangle to a parallelogram; we keep the
// parallelogram's bounding rectangle, whose half-sides are |M| nu with |M|
// the entry-wise absolute values of M. (Applied to the corner (nu_s, nu_a)
// as the paper writes it, T_d and S would give negative bandwidths.) So:
//   T_d = [1 0; -d 1]       -> (nu_s, |d| nu_s + nu_a)      transport over d
//   C_c = [1 c; 0 1]        -> (nu_s + |c| nu_a, nu_a)      curvature shear
//   P_i = [cos_i 0; 0 1]    -> (cos_i nu_s, nu_a)           incident reparametrisation
//   P_x = [1/cos_x 0; 0 1]  -> (nu_s / cos_x, nu_a)         outgoing reparametrisation
//   S   = [1 0; 0 -1]       -> nu                           mirror
//   B_{t,rho} nu = (nu_s + t, min(rho, nu_a))               BRDF band-limit, texture
#ifndef SVO_BANDWIDTH_OPS_GLSL
#define SVO_BANDWIDTH_OPS_GLSL
#include "prelude.glsl"

// The smallest cosine the reparametrisations divide by (about 89.4 degrees).
SVO_CONST float SVO_BW_MIN_COS = 0.01f;
// A bandwidth no image can show (non-band-limited signals until Eq. 6 clamps them).
SVO_CONST float SVO_BW_INFINITE = 1.0e20f;

SVO_FN vec2 svo_bw_transport(vec2 nu, float d) {
  // nu_s = 0 (distant light) stays 0 over any distance, an infinite one included.
  if (!(nu.x > 0.0f)) return nu;
  return vec2(nu.x, min(abs(d) * nu.x + nu.y, SVO_BW_INFINITE));
}

SVO_FN vec2 svo_bw_curvature(vec2 nu, float c) { return vec2(min(nu.x + abs(c) * nu.y, SVO_BW_INFINITE), nu.y); }

SVO_FN vec2 svo_bw_incident(vec2 nu, float cos_i) { return vec2(nu.x * clamp(abs(cos_i), 0.0f, 1.0f), nu.y); }

SVO_FN vec2 svo_bw_outgoing(vec2 nu, float cos_x) {
  return vec2(min(nu.x / max(abs(cos_x), SVO_BW_MIN_COS), SVO_BW_INFINITE), nu.y);
}

SVO_FN vec2 svo_bw_mirror(vec2 nu) { return nu; }

SVO_FN vec2 svo_bw_band_limit(vec2 nu, float t, float rho) { return vec2(nu.x + t, min(rho, nu.y)); }

// Eq. 3: R = P_x C_{-c} S B_{t,rho} C_c P_i, on the spectrum's support:
// B's angular cut is a window |nu_a| <= rho, and C_c shears along nu_s
// without moving nu_a, so the window cuts the sheared support exactly where
// it cuts the unsheared one. Cutting first gives the bounding rectangle of
// the true support (nu_s cos_i + |c| min(nu_a, rho)); boxing the sheared
// rectangle first would keep |c| nu_a, unbounded for a light of unbounded
// angular bandwidth (a directional light on a curved surface).
SVO_FN vec2 svo_bw_reflect(vec2 nu, float c, float cos_i, float cos_x, float t, float rho) {
  vec2 r = svo_bw_incident(nu, cos_i);
  r.y = min(r.y, rho);
  r = svo_bw_curvature(r, c);
  r = svo_bw_band_limit(r, t, rho);
  r = svo_bw_mirror(r);
  r = svo_bw_curvature(r, -c);
  return svo_bw_outgoing(r, cos_x);
}

// Eq. 4: nu^i = T_{d'} R T_d nu_l, the bandwidth at the eye of the path
// from a light of bandwidth nu_l at distance d (any, for distant light)
// through the surface point at distance d_eye from the eye.
SVO_FN vec2 svo_bw_one_bounce(vec2 nu_l, float d, float d_eye, float c, float cos_i, float cos_x, float t, float rho) {
  return svo_bw_transport(svo_bw_reflect(svo_bw_transport(nu_l, d), c, cos_i, cos_x, t, rho), d_eye);
}

// Eq. 6: the image-space bandwidth b_p in cycles per pixel of an angular
// bandwidth nu_a at the eye, for pixels `pixel_angle` radians wide
// (f_x / W of the paper, the larger of the two axes).
SVO_FN float svo_bw_image(float nu_a, float pixel_angle) { return nu_a * pixel_angle; }

// Eq. 11: the pyramid level at which a pixel of bandwidth b_p may be
// shaded, floor(log2(1 / b_p)), within [0, max_level] (0: the finest; a
// pixel of level r may be shaded on the grid of every 2^r-th pixel).
SVO_FN uint svo_bw_level(float b_p, uint max_level) {
  if (!(b_p > 0.0f)) return max_level;
  float l = floor(log2(1.0f / b_p));
  if (!(l > 0.0f)) return 0u;
  return min(uint(l), max_level);
}

// The band-limit (cycles per radian) of a function convolved with a
// normalised SG of sharpness kappa, near its axis a Gaussian of deviation
// 1 / sqrt(kappa), whose power spectrum holds 95% of its energy below
// 1.96 sqrt(kappa) / (2 sqrt(2) pi) = 0.2206 sqrt(kappa). None
// (SVO_BW_INFINITE) for kappa 0 (no kernel).
SVO_FN float svo_bw_sg_limit(float kappa) {
  if (!(kappa > 0.0f)) return SVO_BW_INFINITE;
  return min(0.2206f * sqrt(kappa), SVO_BW_INFINITE);
}

// Our addition: the band-limit (cycles per radian) of the reflected light
// of a surface whose slopes spread with variance sigma2 (the voxel's
// smaller principal slope variance): the reflected directions spread with
// deviation 2 sigma, the kernel of sharpness 1 / (4 sigma2), whose band is
// 0.1103 / sigma (svo_bw_sg_limit). None (SVO_BW_INFINITE) for a smooth
// surface.
SVO_FN float svo_bw_slope_limit(float sigma2) {
  if (!(sigma2 > 0.0f)) return SVO_BW_INFINITE;
  return svo_bw_sg_limit(0.25f / sigma2);
}

// Eq. 9's term of one light direction: (nu_a^i + nu_rho^i) chi_i^2, with
// nu_a the incident light's angular bandwidth at the point, nu_rho the
// BRDF's and chi = L_i rho (luminance).
SVO_FN float svo_bw_variance_term(float nu_a, float nu_rho, float chi) {
  return (min(nu_a, SVO_BW_INFINITE) + min(nu_rho, SVO_BW_INFINITE)) * chi * chi;
}

// Flags of the bandwidth-adaptive pass (SvoAdaptiveParams::config.z).
SVO_CONST uint SVO_ADAPTIVE_SLOPE_LIMIT = 1u;  // the voxels' slope variance band-limits too (svo_bw_slope_limit)
SVO_CONST uint SVO_ADAPTIVE_FINEST = 2u;       // every pixel at level 0 with shade.sampling.x samples: forward shading
SVO_CONST uint SVO_ADAPTIVE_MEASURED = 4u;     // N_p from the n_b directions' sample variance instead of Eq. 9's bound
// The pyramid levels of the pass's images (render::AdaptivePass): level 7
// shades every 128th pixel of each axis.
SVO_CONST uint SVO_ADAPTIVE_LEVELS = 8u;
// Threads that share one texel's samples on the Vulkan host (a divisor of
// the kernel's 64-thread workgroup).
SVO_CONST uint SVO_ADAPTIVE_SLOTS = 8u;
// States of a texel of the shading pyramid (its alpha).
SVO_CONST float SVO_ADAPTIVE_PENDING = 0.0f;    // left to finer levels
SVO_CONST float SVO_ADAPTIVE_SHADED = 1.0f;     // shaded at this level
SVO_CONST float SVO_ADAPTIVE_UPSAMPLED = 2.0f;  // from the coarser level's
SVO_CONST float SVO_ADAPTIVE_EMPTY = 3.0f;      // no surface at its centre pixel

// The bandwidth-adaptive pass's parameters, laid out identically in C++ and
// in the shaders' std430 block.
struct SvoAdaptiveParams {
  uvec4 config;  // x: n_b (directions per pixel), y: most samples per pixel, z: flags (SVO_ADAPTIVE_*),
                 // w: the coarsest level (< SVO_ADAPTIVE_LEVELS)
  vec4 quality;  // x: tau, the variance each pixel aims at relative to (L + 0.01)^2; y: the upsampling
                 // depth weight's deviation, in parent spacings times the pixel's footprint; z: fewest samples
  uvec4 tables;  // x: table offset of the environment's bandwidth map, y: its width, z: its height (0: none),
                 // w: table offset of the BRDF bandwidth tables (16^3 floats per material, in the scene's order)
  uvec4 frame;   // x: the level a dispatch works on, y: the BRDF tables' count, z: the side of the blocks the
                 // bandwidth buffer's estimates are made for (1: every pixel; 2: one per 2x2 pixels)
  uvec4 area;    // the area light's spatial bandwidth grid (render::area_light_bandwidth): x its table offset,
                 // y its width, z its height (0: none)
};

#endif
