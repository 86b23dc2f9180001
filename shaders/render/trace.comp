#version 460
#extension GL_GOOGLE_include_directive : require
// One cone per pixel (common/tracer.glsl). Brick records are spread over up
// to SVO_POOL_SLOTS storage buffers of whole bricks each, so that a pool
// larger than the device's maxStorageBufferRange still fits.
#include "common/tracer_params.glsl"

#define SVO_POOL_SLOTS 8
// How many pool buffers hold bricks (specialised at pipeline creation, so
// that the usual single buffer costs no branch).
layout(constant_id = 0) const uint SVO_POOL_BUFFERS = SVO_POOL_SLOTS;

layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer ParamsBlock { SvoTraceParams params; };
layout(std430, set = 0, binding = 1) readonly restrict buffer Nodes { uvec2 nodes[]; };
layout(std430, set = 0, binding = 2) readonly restrict buffer Masks { uvec4 masks[]; };
layout(std430, set = 0, binding = 3) writeonly restrict buffer ColourOut { vec4 colour_out[]; };
layout(std430, set = 0, binding = 4) writeonly restrict buffer GBufferOut { vec4 gbuffer_out[]; };
layout(std430, set = 0, binding = 5) writeonly restrict buffer StepsOut { uint steps_out[]; };
layout(std430, set = 0, binding = 6) readonly restrict buffer Pool0 { uint pool0[]; };
layout(std430, set = 0, binding = 7) readonly restrict buffer Pool1 { uint pool1[]; };
layout(std430, set = 0, binding = 8) readonly restrict buffer Pool2 { uint pool2[]; };
layout(std430, set = 0, binding = 9) readonly restrict buffer Pool3 { uint pool3[]; };
layout(std430, set = 0, binding = 10) readonly restrict buffer Pool4 { uint pool4[]; };
layout(std430, set = 0, binding = 11) readonly restrict buffer Pool5 { uint pool5[]; };
layout(std430, set = 0, binding = 12) readonly restrict buffer Pool6 { uint pool6[]; };
layout(std430, set = 0, binding = 13) readonly restrict buffer Pool7 { uint pool7[]; };

uvec2 svo_node(uint index) { return nodes[index]; }

uvec4 svo_mask(uint cell) { return masks[cell]; }

uint svo_pool_word(uint slot, uint i) {
  if (SVO_POOL_BUFFERS == 1u) return pool0[i];
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
  steps_out[i] = px.steps;
  if ((params.image.w & SVO_FLAG_GBUFFER) != 0u) {
    gbuffer_out[3u * i] = px.g0;
    gbuffer_out[3u * i + 1u] = px.g1;
    gbuffer_out[3u * i + 2u] = px.g2;
  }
}
