// The types of the lobe-aware filter (lobe_filter.glsl): its parameters
// and a pixel's lobes, which a host declares its readers with before it
// includes lobe_filter.glsl, and the parameters' per-frame constants (also
// in shared_math.h, for the hosts that fill SvoFilterParams).
#ifndef SVO_LOBE_FILTER_TYPES_GLSL
#define SVO_LOBE_FILTER_TYPES_GLSL
#include "prelude.glsl"
#include "sg.glsl"

// Directional weights (SvoFilterParams::mode.x; render::FilterWeight).
SVO_CONST uint SVO_FILTER_NONE = 0u;     // depth and screen kernels alone
SVO_CONST uint SVO_FILTER_NORMAL = 1u;   // Eq. 4: G(n_i, n_j, 1 / sigma_n^2)
SVO_CONST uint SVO_FILTER_LOBE = 2u;     // Eq. 12: one SG per pixel, Iwasaki's product integral
SVO_CONST uint SVO_FILTER_MIXTURE = 3u;  // Eq. 11: up to 3 SGs per pixel, exact product integrals
SVO_CONST uint SVO_FILTER_ASG = 4u;      // Eq. 13: one anisotropic SG per pixel

// Steps (SvoFilterParams::mode.w).
SVO_CONST uint SVO_FILTER_STEP_LOBES = 0u;
SVO_CONST uint SVO_FILTER_STEP_ROWS = 1u;
SVO_CONST uint SVO_FILTER_STEP_COLUMNS = 2u;
SVO_CONST uint SVO_FILTER_STEP_UPSAMPLE = 3u;

// vec4 and uvec4 only: the same bytes in C++ and std430.
struct SvoFilterParams {
  uvec4 mode;     // x: weight (SVO_FILTER_*), y: radius R (pixels), z: input scale (1, 2, 4), w: step
  vec4 weights;   // x: beta, y: sigma_n^2, z: sigma_z (of the depth relative to the pixel's), w: kappa (> 3e38: none)
  vec4 adapt;     // x: total weight under which upsampling shades a pixel again (0: never),
                  // y: the screen kernel's sigma (pixels), z: 1 to leave the voxels' slopes out of the lobes,
                  // w: the diffuse lobes' weight as a normal-aware variance (svo_filter_diffuse_variance)
  vec4 screen;    // x: the screen kernel's weights over the 2R + 1 taps, summed (svo_filter_screen_sum); yzw: 0
};

// The screen kernel at d pixels: a Gaussian of deviation sigma.
SVO_FN float svo_filter_screen(float d, float sigma) {
  float s = max(sigma, 1.0e-3f);
  return exp(-0.5f * d * d / (s * s));
}

// Its weights over the 2R + 1 taps of radius R, summed.
SVO_FN float svo_filter_screen_sum(int radius, float sigma) {
  float norm = 0.0f;
  for (int k = -radius; k <= radius; ++k) norm += svo_filter_screen(float(k), sigma);
  return norm;
}

// The variance of the normal-aware weight equal to Eq. 12 for two diffuse
// lobes smoothed by kappa, at power beta (0: the weight is 1).
SVO_FN float svo_filter_diffuse_variance(float beta, float kappa) {
  float ld = svo_sg_smooth(svo_diffuse_lobe(vec3(0.0f, 0.0f, 1.0f)), kappa).sharpness;
  return beta > 0.0f && ld > 0.0f ? 2.0f / (beta * ld) : 0.0f;
}

// A pixel's lobes, the rows' input: the specular lobes share one axis (the
// reflection of the view about the mean normal); sharpness and amplitudes
// are after the smoothing kernel (Eq. 10, kappa).
struct SvoPixelLobe {
  vec3 axis;            // the reflection lobes' axis
  float sharpness;      // the single lobe of Eq. 12 (the mixture merged)
  vec3 normal;          // unit mean normal (the diffuse lobe's axis and Eq. 4's)
  float depth;          // distance along the view ray; 0: no surface
  vec3 mix_sharpness;   // Eq. 11's lobes (up to 3)
  float mix_count;
  vec3 mix_amplitude;
  float asg_ly;         // Eq. 13's ASG: bandwidths along x and z cross x
  vec3 asg_x;
  float asg_lx;
  float asg_norm;       // sqrt of the ASG's product integral with itself (Eq. 13's normalisation)
  float mix_norm;       // sqrt of the mixture's alpha_ii (Eq. 11's)
};

SVO_CONST uint SVO_LOBE_VEC4S = 6u;

SVO_FN vec4 svo_lobe_pack(SvoPixelLobe l, uint k) {
  if (k == 0u) return vec4(l.axis, l.sharpness);
  if (k == 1u) return vec4(l.normal, l.depth);
  if (k == 2u) return vec4(l.mix_sharpness, l.mix_count);
  if (k == 3u) return vec4(l.mix_amplitude, l.asg_ly);
  if (k == 4u) return vec4(l.asg_x, l.asg_lx);
  return vec4(l.asg_norm, l.mix_norm, 0.0f, 0.0f);
}

SVO_FN SvoPixelLobe svo_lobe_unpack(vec4 v0, vec4 v1, vec4 v2, vec4 v3, vec4 v4, vec4 v5) {
  SvoPixelLobe l;
  l.axis = vec3(v0);
  l.sharpness = v0.w;
  l.normal = vec3(v1);
  l.depth = v1.w;
  l.mix_sharpness = vec3(v2);
  l.mix_count = v2.w;
  l.mix_amplitude = vec3(v3);
  l.asg_ly = v3.w;
  l.asg_x = vec3(v4);
  l.asg_lx = v4.w;
  l.asg_norm = v5.x;
  l.mix_norm = v5.y;
  return l;
}

#define SVO_LOBE_LOAD(buffer, texel)                                                                   \
  svo_lobe_unpack(buffer[SVO_LOBE_VEC4S * (texel)], buffer[SVO_LOBE_VEC4S * (texel) + 1u],         \
                  buffer[SVO_LOBE_VEC4S * (texel) + 2u], buffer[SVO_LOBE_VEC4S * (texel) + 3u],   \
                  buffer[SVO_LOBE_VEC4S * (texel) + 4u], buffer[SVO_LOBE_VEC4S * (texel) + 5u])

#endif
