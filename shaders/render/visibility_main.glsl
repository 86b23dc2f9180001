// The body of the visibility pass's kernels (common/visibility_pass.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// visibility_single.comp, visibility_address.comp, visibility_switch.comp.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer GBufferIn { vec4 gbuffer_in[]; };
layout(std430, set = 0, binding = 1) writeonly restrict buffer VisibilityOut { vec4 visibility_out[]; };
#define SVO_OCTREE_BINDING 2
#include "octree_bindings.glsl"
#include "common/visibility_pass.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.image.x * params.image.y) return;
  SvoGBuffer g = SVO_GBUFFER_LOAD(gbuffer_in, i);
  visibility_out[i] = svo_visibility_texel(g);
}
