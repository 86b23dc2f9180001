// The body of the lobe-aware filter's kernels (common/lobe_filter.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl; the
// upsampling step shades pixels again through forward.glsl):
// filter_single.comp, filter_address.comp, filter_switch.comp. The step
// is a specialisation constant (render::LobeFilterPass::run).
layout(local_size_x = 64) in;
layout(constant_id = 2) const uint SVO_FILTER_STEP = 0u;

layout(std430, set = 0, binding = 0) readonly buffer GBufferIn { vec4 gbuffer_in[]; };
layout(std430, set = 0, binding = 1) readonly buffer BackgroundIn { vec4 background_in[]; };
layout(std430, set = 0, binding = 2) readonly buffer DiffuseIn { vec4 diffuse_in[]; };
layout(std430, set = 0, binding = 3) readonly buffer SpecularIn { vec4 specular_in[]; };
layout(std430, set = 0, binding = 4) buffer Lobes { vec4 lobes[]; };
layout(std430, set = 0, binding = 5) buffer OutA { vec4 out_a[]; };
layout(std430, set = 0, binding = 6) buffer OutB { vec4 out_b[]; };
#define SVO_OCTREE_BINDING 10
#include "octree_bindings.glsl"
#include "common/shade_params.glsl"
layout(std430, set = 0, binding = 7) readonly restrict buffer ShadeBlock { SvoShadeParams shade; };
layout(std430, set = 0, binding = 8) readonly restrict buffer Tables { float tables[]; };
float svo_table(uint i) { return tables[i]; }
#include "common/gbuffer.glsl"
#include "common/lobe_filter_types.glsl"
layout(std430, set = 0, binding = 9) readonly restrict buffer FilterBlock { SvoFilterParams filter_params; };
SvoGBuffer svo_filter_gbuffer(uint t) { return SVO_GBUFFER_LOAD(gbuffer_in, t); }
SvoPixelLobe svo_filter_lobe(uint t) { return SVO_LOBE_LOAD(lobes, t); }
vec4 svo_filter_background(uint t) { return background_in[t]; }
vec4 svo_filter_diffuse(uint t) { return diffuse_in[t]; }
vec4 svo_filter_specular(uint t) { return specular_in[t]; }
#include "common/lobe_filter.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.image.x * params.image.y) return;
  if (SVO_FILTER_STEP == SVO_FILTER_STEP_LOBES) {
    SvoPixelLobe l = svo_pixel_lobe(SVO_GBUFFER_LOAD(gbuffer_in, i));
    for (uint k = 0u; k < SVO_LOBE_VEC4S; ++k) lobes[SVO_LOBE_VEC4S * i + k] = svo_lobe_pack(l, k);
    return;
  }
  SvoFilterOut o;
  if (SVO_FILTER_STEP == SVO_FILTER_STEP_ROWS) {
    o = svo_filter_rows_texel(i);
  } else if (SVO_FILTER_STEP == SVO_FILTER_STEP_COLUMNS) {
    o = svo_filter_columns_texel(i);
  } else {
    o = svo_filter_upsample_texel(i);
  }
  out_a[i] = o.diffuse;
  out_b[i] = o.specular;
}
