// The body of the trace kernels: one cone per pixel (common/tracer.glsl).
// Bricks lie in one or more buffers of whole bricks each, read three ways:
//   trace_single.comp   one storage buffer (fits maxStorageBufferRange; any device)
//   trace_address.comp  up to SVO_POOL_SLOTS buffers through device addresses
//   trace_switch.comp   up to SVO_POOL_SLOTS storage buffers, a switch per read
//                       (devices without buffer device addresses; lavapipe
//                       runs it 2.7x slower than the others)
#include "common/tracer_params.glsl"

#define SVO_POOL_SLOTS 8

// What this pipeline traces (tracer_params.glsl, "Specialisation").
layout(constant_id = 0) const uint SVO_SPEC_MODE = SVO_SPEC_ANY;
layout(constant_id = 1) const uint SVO_SPEC_FLAGS = SVO_SPEC_ANY;

layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer ParamsBlock { SvoTraceParams params; };
layout(std430, set = 0, binding = 1) readonly restrict buffer Nodes { uvec2 nodes[]; };
layout(std430, set = 0, binding = 2) readonly restrict buffer Masks { uvec4 masks[]; };
layout(std430, set = 0, binding = 3) writeonly restrict buffer ColourOut { vec4 colour_out[]; };
layout(std430, set = 0, binding = 4) writeonly restrict buffer GBufferOut { vec4 gbuffer_out[]; };
layout(std430, set = 0, binding = 5) writeonly restrict buffer StepsOut { uint steps_out[]; };
layout(std430, set = 0, binding = 6) writeonly restrict buffer BackgroundOut { vec4 background_out[]; };
#if defined(SVO_POOL_SINGLE)
layout(std430, set = 0, binding = 7) readonly restrict buffer Pool { uint words[]; } pool;
#elif defined(SVO_POOL_ADDRESS)
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer SvoWords { uint w[]; };
layout(std430, set = 0, binding = 7) readonly restrict buffer PoolAddresses { uvec2 pool_address[]; };
#else
layout(std430, set = 0, binding = 7) readonly restrict buffer Pool0 { uint pool0[]; };
layout(std430, set = 0, binding = 8) readonly restrict buffer Pool1 { uint pool1[]; };
layout(std430, set = 0, binding = 9) readonly restrict buffer Pool2 { uint pool2[]; };
layout(std430, set = 0, binding = 10) readonly restrict buffer Pool3 { uint pool3[]; };
layout(std430, set = 0, binding = 11) readonly restrict buffer Pool4 { uint pool4[]; };
layout(std430, set = 0, binding = 12) readonly restrict buffer Pool5 { uint pool5[]; };
layout(std430, set = 0, binding = 13) readonly restrict buffer Pool6 { uint pool6[]; };
layout(std430, set = 0, binding = 14) readonly restrict buffer Pool7 { uint pool7[]; };
#endif

uvec2 svo_node(uint index) { return nodes[index]; }

uvec4 svo_mask(uint cell) { return masks[cell]; }

uint svo_pool_word(uint slot, uint i) {
#if defined(SVO_POOL_SINGLE)
  return pool.words[i];
#elif defined(SVO_POOL_ADDRESS)
  return SvoWords(pool_address[slot]).w[i];
#else
  switch (slot) {
    case 0u: return pool0[i];
    case 1u: return pool1[i];
    case 2u: return pool2[i];
    case 3u: return pool3[i];
    case 4u: return pool4[i];
    case 5u: return pool5[i];
    case 6u: return pool6[i];
    default: return pool7[i];
  }
#endif
}

uint svo_brick_bytes(uint brick, uint offset) {
  uint slot = brick / params.pool.y;
  uint at = (brick - slot * params.pool.y) * params.pool.x + offset;
  return svo_pool_word(slot, at >> 2u) >> ((at & 3u) * 8u);
}

#include "common/tracer.glsl"

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= params.image.x || pixel.y >= params.image.y) return;
  SvoPixel px = svo_trace_pixel(pixel);
  uint i = pixel.y * params.image.x + pixel.x;
  colour_out[i] = px.colour;
  background_out[i] = px.background;
  steps_out[i] = px.steps;
  if ((params.image.w & SVO_FLAG_GBUFFER) != 0u) {
    for (uint k = 0u; k < SVO_GBUFFER_VEC4S; ++k) gbuffer_out[SVO_GBUFFER_VEC4S * i + k] = svo_gbuffer_pack(px.g, k);
  }
}
