// The body of the forward-shading pass's kernels (common/forward.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// forward_single.comp, forward_address.comp, forward_switch.comp.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer GBufferIn { vec4 gbuffer_in[]; };
layout(std430, set = 0, binding = 1) readonly restrict buffer BackgroundIn { vec4 background_in[]; };
layout(std430, set = 0, binding = 2) restrict buffer ColourOut { vec4 colour_out[]; };
// Samples [first, first + count) of this dispatch (ForwardPass::run).
layout(push_constant) uniform Push { uint first; uint count; } push;
#define SVO_OCTREE_BINDING 5
#include "octree_bindings.glsl"
#include "common/shade_params.glsl"
layout(std430, set = 0, binding = 3) readonly restrict buffer ShadeBlock { SvoShadeParams shade; };
layout(std430, set = 0, binding = 4) readonly restrict buffer Tables { float tables[]; };
float svo_table(uint i) { return tables[i]; }
#include "common/forward.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.image.x * params.image.y) return;
  SvoGBuffer g = SVO_GBUFFER_LOAD(gbuffer_in, i);
  colour_out[i] = svo_forward_texel(g, background_in[i], i, push.first, push.count, colour_out[i]);
}
