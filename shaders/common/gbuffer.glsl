// The G-buffer, the one layout every pass reads (DESIGN section 10.1): the
// trace pass writes it, shading passes read it, and the hosts' files
// (render::GBufferTexel, image_io's channels) unpack it through these
// functions. A texel is SVO_GBUFFER_VEC4S vec4s, one after the other:
//   0: depth (distance along the view ray, scene units), position xyz
//   1: normal xyz (filtered: the mean of unit normals, not renormalised), coverage
//   2: tangent xyz (unit, perpendicular to the normal), sigma_rho^2 (the micro-BRDF's)
//   3: slope covariance (xx, yy, xy) in the frame (tangent, normal x tangent): the
//      voxels' sigma_n^2 with the footprint's normal spread, without sigma_rho^2;
//      w: the material the pixel shows most (an index into the scene's materials)
//   4: abar rgb (mean colour seen from the camera, linear), w: the second material
//   5: a_s rgb (colour-height correlation), w: the first material's share of the
//      two, in [0, 1] (1 where the scene has one material)
// Fields are coverage-weighted averages over the cone elements that set the
// pixel's bits, except the materials, which the trace pass looks up once per
// pixel at the average position (fetch.glsl, svo_material_mix); coverage 0:
// no surface, every other field 0. The radiance of
// the background is not here: the trace pass writes it as its own image, so
// that a pass adding light to the surface never adds it to the background.
#ifndef SVO_GBUFFER_GLSL
#define SVO_GBUFFER_GLSL
#include "frame.glsl"

SVO_CONST uint SVO_GBUFFER_VEC4S = 6u;

struct SvoGBuffer {
  float depth;
  vec3 position;
  vec3 normal;
  float coverage;
  vec3 tangent;
  float sigma_rho2;
  vec3 slope_cov;
  vec3 abar;
  vec3 a_s;
  uint material;        // the material the pixel shows most
  uint material2;       // the second
  float material_mix;   // the first's share of the two
};

SVO_FN SvoGBuffer svo_gbuffer_empty() {
  SvoGBuffer g;
  g.depth = 0.0f;
  g.position = vec3(0.0f);
  g.normal = vec3(0.0f);
  g.coverage = 0.0f;
  g.tangent = vec3(0.0f);
  g.sigma_rho2 = 0.0f;
  g.slope_cov = vec3(0.0f);
  g.abar = vec3(0.0f);
  g.a_s = vec3(0.0f);
  g.material = 0u;
  g.material2 = 0u;
  g.material_mix = 0.0f;
  return g;
}

// The k-th vec4 of the texel (k < SVO_GBUFFER_VEC4S).
SVO_FN vec4 svo_gbuffer_pack(SvoGBuffer g, uint k) {
  if (k == 0u) return vec4(g.depth, g.position);
  if (k == 1u) return vec4(g.normal, g.coverage);
  if (k == 2u) return vec4(g.tangent, g.sigma_rho2);
  if (k == 3u) return vec4(g.slope_cov, float(g.material));
  if (k == 4u) return vec4(g.abar, float(g.material2));
  return vec4(g.a_s, g.material_mix);
}

SVO_FN SvoGBuffer svo_gbuffer_unpack(vec4 v0, vec4 v1, vec4 v2, vec4 v3, vec4 v4, vec4 v5) {
  SvoGBuffer g;
  g.depth = v0.x;
  g.position = vec3(v0.y, v0.z, v0.w);
  g.normal = vec3(v1);
  g.coverage = v1.w;
  g.tangent = vec3(v2);
  g.sigma_rho2 = v2.w;
  g.slope_cov = vec3(v3);
  g.abar = vec3(v4);
  g.a_s = vec3(v5);
  g.material = uint(max(v3.w, 0.0f) + 0.5f);
  g.material2 = uint(max(v4.w, 0.0f) + 0.5f);
  g.material_mix = v5.w;
  return g;
}

// Texel `texel` of a G-buffer held as a vec4 array `buffer` (a kernel's
// storage buffer): SVO_GBUFFER_VEC4S vec4s from texel * SVO_GBUFFER_VEC4S on.
#define SVO_GBUFFER_LOAD(buffer, texel)                                                                     \
  svo_gbuffer_unpack(buffer[SVO_GBUFFER_VEC4S * (texel)], buffer[SVO_GBUFFER_VEC4S * (texel) + 1u],     \
                     buffer[SVO_GBUFFER_VEC4S * (texel) + 2u], buffer[SVO_GBUFFER_VEC4S * (texel) + 3u], \
                     buffer[SVO_GBUFFER_VEC4S * (texel) + 4u], buffer[SVO_GBUFFER_VEC4S * (texel) + 5u])

// a + w b, field by field (coverage-weighted sums over elements and rays);
// the materials are a's (they are looked up after the sum, not summed).
SVO_FN SvoGBuffer svo_gbuffer_madd(SvoGBuffer a, SvoGBuffer b, float w) {
  SvoGBuffer r;
  r.depth = a.depth + w * b.depth;
  r.position = a.position + w * b.position;
  r.normal = a.normal + w * b.normal;
  r.coverage = a.coverage + w * b.coverage;
  r.tangent = a.tangent + w * b.tangent;
  r.sigma_rho2 = a.sigma_rho2 + w * b.sigma_rho2;
  r.slope_cov = a.slope_cov + w * b.slope_cov;
  r.abar = a.abar + w * b.abar;
  r.a_s = a.a_s + w * b.a_s;
  r.material = a.material;
  r.material2 = a.material2;
  r.material_mix = a.material_mix;
  return r;
}

// A sum of `svo_gbuffer_madd(..., weight)` turned into the averages, with
// `coverage` the pixel's: the sum's own coverage field holds the sum of the
// weights. The tangent is made unit and perpendicular to the normal again
// (the normal's own tangent frame where the elements' tangents cancel).
SVO_FN SvoGBuffer svo_gbuffer_finish(SvoGBuffer sum, float coverage) {
  float inv = sum.coverage > 0.0f ? 1.0f / sum.coverage : 0.0f;
  SvoGBuffer g = svo_gbuffer_madd(svo_gbuffer_empty(), sum, inv);
  g.coverage = coverage;
  float nl = length(g.normal);
  vec3 n = nl > 0.0f ? g.normal / nl : vec3(0.0f);
  vec3 t = g.tangent - dot(g.tangent, n) * n;
  float tl = length(t);
  g.tangent = tl > 1.0e-3f ? t / tl : (nl > 0.0f ? svo_tangent_frame(n).t : vec3(0.0f));
  return g;
}

#endif
