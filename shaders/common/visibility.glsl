// Visibility cones (tracer part 4 of 5): the occlusion of a light seen from
// a point, marched and combined as the primary cone's. Any pass that can
// read the octree (the host contract in tracer.glsl) can trace them.
#ifndef SVO_VISIBILITY_GLSL
#define SVO_VISIBILITY_GLSL
#include "march.glsl"

// Light i (params.light_*) seen from p: the unit direction towards it, the
// irradiance it brings at normal incidence, its distance (3e38 for a
// directional light) and the widening of a cone that covers it (per unit
// distance).
struct SvoLightSample {
  vec3 l;
  vec3 e;
  float dist;
  float spread;
};

SVO_FN SvoLightSample svo_light_at(uint i, vec3 p) {
  vec4 lv = params.light_vector[i];
  vec4 lr = params.light_radiance[i];
  SvoLightSample s;
  s.l = vec3(lv);
  s.e = vec3(lr);
  s.dist = 3.0e38f;
  if (lv.w > 0.5f) {
    vec3 to = vec3(lv) - p;
    s.dist = length(to);
    s.l = to / max(s.dist, 1.0e-30f);
    s.e = vec3(lr) / max(s.dist * s.dist, 1.0e-30f);
  }
  s.spread = lv.w > 0.5f ? lr.w / max(s.dist, 1.0e-30f) : tan(lr.w);
  return s;
}

struct SvoVisibility {
  float visible;  // unoccluded fraction of the shadow cone's footprint
  uint steps;
};

// Visibility of a light from the element at p (radius r0) along unit l, up
// to `dist`: a cone that starts with the element's radius and widens with
// the light's size (`spread` per unit distance), occlusion combined as on
// the primary cone.
SVO_FN SvoVisibility svo_visibility(vec3 p, vec3 l, float dist, float r0, float spread, float n_dot_l, uint mode) {
  SvoVisibility vis;
  vis.visible = 1.0f;
  vis.steps = 0u;
  SvoCone cone = svo_make_cone(p, l, r0, spread, 0.0f, 0.0f);
  float t1 = min(dist, svo_box_exit(p, cone.inv_d, vec3(params.domain), params.domain.w));
  // Start where the element's own plane no longer reaches into the cone.
  SvoMarch m = svo_march_start(min(2.0f * r0 / max(n_dot_l, 0.25f), 8.0f * r0));
  uvec4 alpha = uvec4(0u);
  float opacity = 0.0f;
  while (m.t < t1 && vis.steps < SVO_SHADOW_STEPS) {
    vis.steps += 1u;
    svo_step(m, cone, mode);
    if (!m.hit) continue;
    if (mode == SVO_MODE_ALPHA) {
      opacity += (1.0f - opacity) * float(svo_popcount(m.mask)) / 128.0f;
      if (opacity >= 0.999f) break;
    } else {
      alpha = alpha | m.mask;
      if (svo_popcount(alpha) == 128) break;
    }
  }
  vis.visible = mode == SVO_MODE_ALPHA ? 1.0f - opacity : 1.0f - float(svo_popcount(alpha)) / 128.0f;
  return vis;
}

#endif
