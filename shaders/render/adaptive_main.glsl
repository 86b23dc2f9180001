// The body of the bandwidth-adaptive pass's kernels (common/bandwidth.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// adaptive_single.comp, adaptive_address.comp, adaptive_switch.comp. One
// kernel, five stages (push.stage; render::AdaptivePass::run dispatches them
// in order): 0 the bandwidth buffer's level 0, 1 its level push.level from
// the finer one, 2 level push.level of the shading pyramid (upsampled
// texels, and marks where to shade), 4 the marked texels' samples,
// SVO_ADAPTIVE_SLOTS threads per texel, after each stage 2; 3 the frame's
// colour and the shaded-pixel mask.
layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer GBufferIn { vec4 gbuffer_in[]; };
layout(std430, set = 0, binding = 1) readonly buffer BackgroundIn { vec4 background_in[]; };
layout(std430, set = 0, binding = 2) writeonly buffer ColourOut { vec4 colour_out[]; };
layout(std430, set = 0, binding = 5) buffer BandwidthPyramid { vec4 bw_pyramid[]; };
layout(std430, set = 0, binding = 6) buffer ShadingPyramid { vec4 shading_pyramid[]; };
layout(std430, set = 0, binding = 7) writeonly buffer MaskOut { vec4 mask_out[]; };
layout(push_constant) uniform Push {
  uint stage;
  uint level;
}
push;
#define SVO_OCTREE_BINDING 10
#include "common/bandwidth_ops.glsl"
#include "common/shade_params.glsl"
#include "octree_bindings.glsl"
layout(std430, set = 0, binding = 3) readonly restrict buffer ShadeBlock { SvoShadeParams shade; };
layout(std430, set = 0, binding = 4) readonly restrict buffer Tables { float tables[]; };
layout(std430, set = 0, binding = 8) readonly restrict buffer AdaptBlock { SvoAdaptiveParams adapt; };
layout(std430, set = 0, binding = 9) readonly restrict buffer BandwidthTables { float bw_tables[]; };
float svo_table(uint i) { return tables[i]; }
float svo_bw_table(uint i) { return bw_tables[i]; }
#include "common/gbuffer.glsl"

// Where level `level` of a pyramid over the frame starts (ImageDesc: each
// level after the finer ones, sides halved and rounded up).
uint svo_adaptive_offset(uint level) {
  uint at = 0u;
  for (uint l = 0u; l < level; ++l) {
    uint s = 1u << l;
    at += ((params.image.x + s - 1u) / s) * ((params.image.y + s - 1u) / s);
  }
  return at;
}
uint svo_adaptive_index(uint level, uvec2 q) {
  uint s = 1u << level;
  return svo_adaptive_offset(level) + q.y * ((params.image.x + s - 1u) / s) + q.x;
}
SvoGBuffer svo_adaptive_gbuffer(uint pixel) { return SVO_GBUFFER_LOAD(gbuffer_in, pixel); }
vec4 svo_adaptive_bandwidth(uint level, uvec2 q) { return bw_pyramid[svo_adaptive_index(level, q)]; }
vec4 svo_adaptive_pyramid(uint level, uvec2 q) { return shading_pyramid[svo_adaptive_index(level, q)]; }
#include "common/bandwidth.glsl"

SvoGBuffer neighbour(ivec2 at) {
  if (at.x < 0 || at.y < 0 || at.x >= int(params.image.x) || at.y >= int(params.image.y)) return svo_gbuffer_empty();
  return svo_adaptive_gbuffer(uint(at.y) * params.image.x + uint(at.x));
}

shared vec3 svo_slot_sums[64];

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (push.stage == 4u) {
    // Every thread reaches the barrier; slot 0 adds its texel's slots in order.
    uvec2 size = svo_adaptive_size(push.level);
    uint texel = i / SVO_ADAPTIVE_SLOTS;
    uint slot = gl_LocalInvocationID.x % SVO_ADAPTIVE_SLOTS;
    bool marked = false;
    uvec2 q = uvec2(0u);
    vec3 part = vec3(0.0f);
    if (texel < size.x * size.y) {
      q = uvec2(texel % size.x, texel / size.x);
      marked = push.level <= adapt.config.w && svo_adaptive_pyramid(push.level, q).w == SVO_ADAPTIVE_SHADED;
      if (marked) part = svo_adaptive_samples_of(q, push.level, slot);
    }
    svo_slot_sums[gl_LocalInvocationID.x] = part;
    barrier();
    if (marked && slot == 0u) {
      vec3 sum = vec3(0.0f);
      for (uint k = 0u; k < SVO_ADAPTIVE_SLOTS; ++k) sum += svo_slot_sums[gl_LocalInvocationID.x + k];
      shading_pyramid[svo_adaptive_index(push.level, q)] = vec4(sum, SVO_ADAPTIVE_SHADED);
    }
    return;
  }
  if (push.stage == 0u) {
    // One estimate per block of adapt.frame.z pixels a side, written to its pixels.
    uint side = adapt.frame.z;
    uvec2 blocks = (uvec2(params.image.x, params.image.y) + side - 1u) / side;
    if (i >= blocks.x * blocks.y) return;
    uvec2 block = uvec2(i % blocks.x, i / blocks.x);
    uvec2 rep = svo_bandwidth_representative(block, side);
    ivec2 p = ivec2(rep);
    vec4 estimate =
        svo_bandwidth_texel(neighbour(p), neighbour(p - ivec2(1, 0)), neighbour(p + ivec2(1, 0)),
                            neighbour(p - ivec2(0, 1)), neighbour(p + ivec2(0, 1)), rep.y * params.image.x + rep.x);
    for (uint k = 0u; k < side * side; ++k) {
      uvec2 at = block * side + uvec2(k % side, k / side);
      if (at.x >= params.image.x || at.y >= params.image.y) continue;
      uint pixel = at.y * params.image.x + at.x;
      bw_pyramid[pixel] = svo_bandwidth_pixel(estimate, svo_adaptive_gbuffer(pixel).coverage);
    }
    return;
  }
  uint level = push.stage == 3u ? 0u : push.level;
  uvec2 size = svo_adaptive_size(level);
  if (i >= size.x * size.y) return;
  uvec2 q = uvec2(i % size.x, i / size.x);
  if (push.stage == 1u) {
    uvec2 fine = svo_adaptive_size(level - 1u);
    uvec2 c0 = min(2u * q, fine - 1u);
    uvec2 c1 = min(2u * q + 1u, fine - 1u);
    bw_pyramid[svo_adaptive_index(level, q)] = svo_bandwidth_reduce(
        svo_adaptive_bandwidth(level - 1u, c0), svo_adaptive_bandwidth(level - 1u, uvec2(c1.x, c0.y)),
        svo_adaptive_bandwidth(level - 1u, uvec2(c0.x, c1.y)), svo_adaptive_bandwidth(level - 1u, c1));
  } else if (push.stage == 2u) {
    shading_pyramid[svo_adaptive_index(level, q)] =
        level > adapt.config.w ? vec4(0.0f) : svo_adaptive_level_texel(q, level, false);
  } else {
    colour_out[i] = svo_adaptive_compose(svo_adaptive_gbuffer(i), background_in[i], i, vec3(shading_pyramid[i]));
    mask_out[i] = svo_adaptive_mask(q);
  }
}
