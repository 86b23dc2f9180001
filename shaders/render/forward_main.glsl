// The body of the forward-shading pass's kernels (common/forward.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// forward_single.comp, forward_address.comp, forward_switch.comp.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer GBufferIn { vec4 gbuffer_in[]; };
layout(std430, set = 0, binding = 1) readonly buffer BackgroundIn { vec4 background_in[]; };
// The colour, or with diffuse and specular apart the diffuse image.
layout(std430, set = 0, binding = 2) buffer ColourOut { vec4 colour_out[]; };
layout(std430, set = 0, binding = 5) buffer SpecularOut { vec4 specular_out[]; };
// Samples [first, first + count) of this dispatch; split: diffuse and
// specular apart (svo_forward_split_texel), at 1/scale of the frame's size
// (ForwardPass::run).
layout(push_constant) uniform Push { uint first; uint count; uint split; uint scale; } push;
#define SVO_OCTREE_BINDING 6
#include "octree_bindings.glsl"
#include "common/shade_params.glsl"
layout(std430, set = 0, binding = 3) readonly restrict buffer ShadeBlock { SvoShadeParams shade; };
layout(std430, set = 0, binding = 4) readonly restrict buffer Tables { float tables[]; };
float svo_table(uint i) { return tables[i]; }
#include "common/forward.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (push.split == 0u) {
    if (i >= params.image.x * params.image.y) return;
    SvoGBuffer g = SVO_GBUFFER_LOAD(gbuffer_in, i);
    colour_out[i] = svo_forward_texel(g, background_in[i], i, push.first, push.count, colour_out[i]);
    return;
  }
  uint lw = (params.image.x + push.scale - 1u) / push.scale;
  uint lh = (params.image.y + push.scale - 1u) / push.scale;
  if (i >= lw * lh) return;
  uint at = svo_scaled_texel(i, push.scale);
  SvoGBuffer g = SVO_GBUFFER_LOAD(gbuffer_in, at);
  SvoForwardSplit previous;
  previous.diffuse = colour_out[i];
  previous.specular = specular_out[i];
  SvoForwardSplit f = svo_forward_split_texel(g, at, push.first, push.count, previous);
  colour_out[i] = f.diffuse;
  specular_out[i] = f.specular;
}
