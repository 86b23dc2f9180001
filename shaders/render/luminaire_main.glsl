// The body of the luminaire pass's kernels (common/luminaire.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// luminaire_single.comp, luminaire_address.comp, luminaire_switch.comp.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer GBufferIn { vec4 gbuffer_in[]; };
// The background's share (first dispatch, not over the colour); unread otherwise.
layout(std430, set = 0, binding = 1) readonly buffer BaseIn { vec4 base_in[]; };
layout(std430, set = 0, binding = 2) buffer ColourOut { vec4 colour_out[]; };
// Pixels [band, band_end); state: entry y of pixel band + x of their state
// (svo_luminaire_state, `stride` entries each); otherwise samples [first,
// first + count) of each pixel; over: add to the colour the frame holds
// (render::LuminairePass).
layout(push_constant) uniform Push {
  uint first;
  uint count;
  uint over;
  uint state;
  uint band;
  uint band_end;
  uint stride;
  uint pad;
} push;
#define SVO_OCTREE_BINDING 7
#include "octree_bindings.glsl"
#include "common/shade_params.glsl"
layout(std430, set = 0, binding = 3) readonly restrict buffer ShadeBlock { SvoShadeParams shade; };
layout(std430, set = 0, binding = 4) readonly restrict buffer Tables { float tables[]; };
layout(std430, set = 0, binding = 5) readonly restrict buffer LumTables { float lum_tables[]; };
// The band's pixels' state, pixel by pixel.
layout(std430, set = 0, binding = 6) restrict buffer LumState { float lum_state[]; };
float svo_table(uint i) { return tables[i]; }
float svo_lum_table(uint i) { return lum_tables[i]; }
#include "common/forward.glsl"
float svo_lum_state(uint pixel, uint k, in SvoShadingPoint p) { return lum_state[(pixel - push.band) * push.stride + k]; }
#include "common/luminaire.glsl"

void main() {
  uint i = push.band + gl_GlobalInvocationID.x;
  if (i >= push.band_end) return;
  SvoGBuffer g = SVO_GBUFFER_LOAD(gbuffer_in, i);
  if (push.state != 0u) {
    lum_state[gl_GlobalInvocationID.x * push.stride + gl_GlobalInvocationID.y] =
        svo_luminaire_state(g, gl_GlobalInvocationID.y);
    return;
  }
  bool first_call = push.first == 0u && push.over == 0u;
  vec4 base = first_call ? base_in[i] : colour_out[i];
  colour_out[i] = svo_luminaire_texel(g, base, i, push.over != 0u, push.first, push.count);
}
