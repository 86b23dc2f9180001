// The environment map (DESIGN section 10.2): latitude-longitude RGB, +Y up,
// rotated about +Y and scaled (SvoShadeParams::env, env_xform), its texels
// and sampling distribution in the shading tables (distribution.glsl). A
// direction d maps to u = 1/2 + atan2(d.x, -d.z) / (2 pi) (the map's centre
// column looks along -Z) minus the rotation, v = acos(d.y) / pi (row 0 at
// +Y). Lighting reads the nearest texel, exactly the piecewise-constant
// function the sampler draws from (pdf proportional to its luminance times
// sin(theta)); the background reads it bilinearly.
#ifndef SVO_ENVIRONMENT_GLSL
#define SVO_ENVIRONMENT_GLSL
#include "distribution.glsl"
#include "shade_params.glsl"

SVO_FN vec2 svo_env_uv(SvoShadeParams sp, vec3 d) {
  float u = 0.5f + atan(d.x, -d.z) * (0.5f / SVO_PI) - sp.env_xform.x * (0.5f / SVO_PI);
  u = u - floor(u);
  float v = acos(clamp(d.y, -1.0f, 1.0f)) * (1.0f / SVO_PI);
  return vec2(u, v);
}

SVO_FN vec3 svo_env_direction(SvoShadeParams sp, vec2 uv) {
  float phi = (uv.x - 0.5f) * 2.0f * SVO_PI + sp.env_xform.x;
  float theta = uv.y * SVO_PI;
  float s = sin(theta);
  return vec3(s * sin(phi), cos(theta), -s * cos(phi));
}

SVO_FN vec3 svo_env_texel(SvoShadeParams sp, uint x, uint y) {
  uint at = sp.env.z + 3u * (y * sp.env.x + x);
  return vec3(svo_table(at), svo_table(at + 1u), svo_table(at + 2u));
}

// Radiance arriving from direction d (nearest texel): what lighting sees.
SVO_FN vec3 svo_env_radiance(SvoShadeParams sp, vec3 d) {
  if (sp.env.y == 0u) return vec3(0.0f);
  vec2 uv = svo_env_uv(sp, d);
  uint x = min(uint(uv.x * float(sp.env.x)), sp.env.x - 1u);
  uint y = min(uint(uv.y * float(sp.env.y)), sp.env.y - 1u);
  return sp.env_xform.y * svo_env_texel(sp, x, y);
}

// A latitude-longitude map of width x height RGB texels at table offset
// `at`, interpolated bilinearly at uv (wrapping in u).
SVO_FN vec3 svo_latlong_bilinear(uint at, uint width, uint height, vec2 uv) {
  float fx = uv.x * float(width) - 0.5f;
  float fy = clamp(uv.y * float(height) - 0.5f, 0.0f, float(height - 1u));
  float x0f = floor(fx);
  float tx = fx - x0f;
  uint y0 = uint(fy);
  uint y1 = min(y0 + 1u, height - 1u);
  float ty = fy - float(y0);
  uint x0 = uint(int(x0f) + int(width)) % width;
  uint x1 = (x0 + 1u) % width;
  uint r0 = at + 3u * y0 * width;
  uint r1 = at + 3u * y1 * width;
  vec3 a = vec3(svo_table(r0 + 3u * x0), svo_table(r0 + 3u * x0 + 1u), svo_table(r0 + 3u * x0 + 2u));
  vec3 b = vec3(svo_table(r0 + 3u * x1), svo_table(r0 + 3u * x1 + 1u), svo_table(r0 + 3u * x1 + 2u));
  vec3 c = vec3(svo_table(r1 + 3u * x0), svo_table(r1 + 3u * x0 + 1u), svo_table(r1 + 3u * x0 + 2u));
  vec3 e = vec3(svo_table(r1 + 3u * x1), svo_table(r1 + 3u * x1 + 1u), svo_table(r1 + 3u * x1 + 2u));
  return mix(mix(a, b, tx), mix(c, e, tx), ty);
}

// Radiance seen along d, interpolated bilinearly (the background).
SVO_FN vec3 svo_env_background(SvoShadeParams sp, vec3 d) {
  if (sp.env.y == 0u) return vec3(0.0f);
  return sp.env_xform.y * svo_latlong_bilinear(sp.env.z, sp.env.x, sp.env.y, svo_env_uv(sp, d));
}

// One pre-convolved map (render::PreconvolvedEnvironment; level `k` of the
// directory at sp.env_xform.z, the irradiance after the last) along d.
SVO_FN vec3 svo_env_preconvolved_level(SvoShadeParams sp, uint k, vec3 d) {
  uint dir = floatBitsToUint(sp.env_xform.z) + 2u + 3u * k;
  return svo_latlong_bilinear(floatBitsToUint(svo_table(dir + 2u)), uint(svo_table(dir)), uint(svo_table(dir + 1u)),
                              svo_env_uv(sp, d));
}

// The radiance about d weighted by the normalised SG of the given sharpness
// (its integral over the sphere is 1): the pre-convolved maps' levels
// either side of it interpolated in log2(sharpness), clamped to the first
// and the last. Needs SVO_SHADE_PRECONVOLVED (env_xform.z set).
SVO_FN vec3 svo_env_preconvolved(SvoShadeParams sp, vec3 d, float sharpness) {
  if (sp.env.y == 0u) return vec3(0.0f);
  uint at = floatBitsToUint(sp.env_xform.z);
  uint n = uint(svo_table(at));
  float f = clamp(log2(max(sharpness, 1.0e-30f) / svo_table(at + 1u)), 0.0f, float(n - 1u));
  uint k = min(uint(f), n - 1u);
  vec3 a = svo_env_preconvolved_level(sp, k, d);
  vec3 b = k + 1u < n ? svo_env_preconvolved_level(sp, k + 1u, d) : a;
  return sp.env_xform.y * mix(a, b, f - float(k));
}

// The irradiance at a surface of unit normal n over pi (what a white
// Lambert surface reflects), from the pre-convolved maps.
SVO_FN vec3 svo_env_irradiance(SvoShadeParams sp, vec3 n) {
  if (sp.env.y == 0u) return vec3(0.0f);
  return sp.env_xform.y * svo_env_preconvolved_level(sp, uint(svo_table(floatBitsToUint(sp.env_xform.z))), n);
}

// The solid-angle density of svo_env_sample at d.
SVO_FN float svo_env_pdf(SvoShadeParams sp, vec3 d) {
  if (sp.env.y == 0u) return 0.0f;
  vec2 uv = svo_env_uv(sp, d);
  float s = sqrt(max(1.0f - d.y * d.y, 0.0f));
  if (!(s > 0.0f)) return 0.0f;
  return svo_dist2d_pdf(sp.env.w, sp.env.x, sp.env.y, uv) / (2.0f * SVO_PI * SVO_PI * s);
}

// A direction drawn from the environment's distribution with uniform u:
// xyz, and its solid-angle density w (0: none, at a pole).
SVO_FN vec4 svo_env_sample(SvoShadeParams sp, vec2 u) {
  if (sp.env.y == 0u) return vec4(0.0f);
  vec3 p = svo_dist2d_sample(sp.env.w, sp.env.x, sp.env.y, u);
  float s = sin(p.y * SVO_PI);
  if (!(s > 0.0f) || !(p.z > 0.0f)) return vec4(0.0f);
  return vec4(svo_env_direction(sp, vec2(p)), p.z / (2.0f * SVO_PI * SVO_PI * s));
}

#endif
