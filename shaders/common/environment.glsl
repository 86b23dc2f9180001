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

// Radiance seen along d, interpolated bilinearly (the background).
SVO_FN vec3 svo_env_background(SvoShadeParams sp, vec3 d) {
  if (sp.env.y == 0u) return vec3(0.0f);
  vec2 uv = svo_env_uv(sp, d);
  float fx = uv.x * float(sp.env.x) - 0.5f;
  float fy = clamp(uv.y * float(sp.env.y) - 0.5f, 0.0f, float(sp.env.y - 1u));
  float x0f = floor(fx);
  float tx = fx - x0f;
  uint y0 = uint(fy);
  uint y1 = min(y0 + 1u, sp.env.y - 1u);
  float ty = fy - float(y0);
  uint x0 = uint(int(x0f) + int(sp.env.x)) % sp.env.x;
  uint x1 = (x0 + 1u) % sp.env.x;
  vec3 top = mix(svo_env_texel(sp, x0, y0), svo_env_texel(sp, x1, y0), tx);
  vec3 bottom = mix(svo_env_texel(sp, x0, y1), svo_env_texel(sp, x1, y1), tx);
  return sp.env_xform.y * mix(top, bottom, ty);
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
