// A textured planar area light (Bagher et al. 2013, section 4.3, Fig. 17;
// render::AreaLight): a parallelogram of centre c and edge vectors e_u,
// e_v that emits from its front side (towards e_u x e_v) the radiance of
// its texture, piecewise constant over the texels, row 0 along the +e_v
// edge. Sampled directly: a point drawn from the texels' luminance
// (distribution.glsl), its density turned into solid angle at the shaded
// point. Host contract: svo_table (the texels and their distribution at
// the offsets of SvoShadeParams::area).
#ifndef SVO_AREA_LIGHT_GLSL
#define SVO_AREA_LIGHT_GLSL
#include "distribution.glsl"
#include "shade_params.glsl"

// One point of the light seen from a shaded point.
struct SvoAreaSample {
  vec3 l;         // unit, from the shaded point towards the light's point
  float dist;     // the distance between them
  vec3 radiance;  // the light's radiance along -l
  float pdf;      // the solid-angle density of l; 0: no sample (behind the light, no light)
  vec2 uv;        // where on the light: x along e_u, y down the rows, in [0, 1)
  float cos_l;    // the light's cosine towards the shaded point
};

// The texel of the light at uv (nearest: the texels are its radiance).
SVO_FN vec3 svo_area_texel(SvoShadeParams sp, vec2 uv) {
  uint at = floatBitsToUint(sp.area_centre.w) + 3u * svo_grid_cell(uv, sp.area.x, sp.area.y);
  return vec3(svo_table(at), svo_table(at + 1u), svo_table(at + 2u));
}

// A point of the light drawn with uniform u, seen from x.
SVO_FN SvoAreaSample svo_area_sample(SvoShadeParams sp, vec3 x, vec2 u) {
  SvoAreaSample s;
  s.l = vec3(0.0f, 0.0f, 1.0f);
  s.dist = 0.0f;
  s.radiance = vec3(0.0f);
  s.pdf = 0.0f;
  s.uv = vec2(0.0f);
  s.cos_l = 0.0f;
  if (sp.area.y == 0u) return s;
  vec3 d = svo_dist2d_sample(sp.area.w, sp.area.x, sp.area.y, u);
  vec3 eu = vec3(sp.area_u);
  vec3 ev = vec3(sp.area_v);
  vec3 c = cross(eu, ev);
  float area = length(c);
  if (!(d.z > 0.0f) || !(area > 0.0f)) return s;
  vec3 to = vec3(sp.area_centre) + (d.x - 0.5f) * eu + (0.5f - d.y) * ev - x;
  float d2 = dot(to, to);
  if (!(d2 > 0.0f)) return s;
  s.dist = sqrt(d2);
  s.l = to / s.dist;
  s.uv = vec2(d);
  s.cos_l = -dot(s.l, c) / area;
  if (!(s.cos_l > 0.0f)) return s;
  s.pdf = d.z * d2 / (area * s.cos_l);
  s.radiance = svo_area_texel(sp, s.uv);
  return s;
}

#endif
