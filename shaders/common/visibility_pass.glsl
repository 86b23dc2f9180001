// The visibility pass's kernel (render::VisibilityPass), per texel: the
// unoccluded fraction of each light (x: light 1 ... w: light 4; 1 for a
// light that is not there and for a texel without surface), seen from the
// G-buffer's point by a visibility cone through the octree (visibility.glsl)
// that starts with the pixel's footprint there. Host contract: tracer.glsl's.
#ifndef SVO_VISIBILITY_PASS_GLSL
#define SVO_VISIBILITY_PASS_GLSL
#include "gbuffer.glsl"
#include "visibility.glsl"

SVO_FN vec4 svo_visibility_texel(SvoGBuffer g) {
  vec4 visible = vec4(1.0f);
  if (!(g.coverage > 0.0f)) return visible;
  float r = params.eye.w * g.depth;
  float nl = length(g.normal);
  vec3 n = nl > 0.0f ? g.normal / nl : vec3(0.0f);
  for (uint i = 0u; i < params.tree.w; ++i) {
    SvoLightSample light = svo_light_at(i, g.position);
    visible[i] = svo_visibility(g.position, light.l, light.dist, r, light.spread, dot(n, light.l),
                                SVO_MODE_PREFILTERED).visible;
  }
  return visible;
}

#endif
