// The body of the trace kernels: one cone per pixel (common/tracer.glsl),
// compiled once per way of reading the pools (octree_bindings.glsl):
// trace_single.comp, trace_address.comp, trace_switch.comp.
layout(local_size_x = 8, local_size_y = 8) in;

layout(std430, set = 0, binding = 0) writeonly restrict buffer ColourOut { vec4 colour_out[]; };
layout(std430, set = 0, binding = 1) writeonly restrict buffer GBufferOut { vec4 gbuffer_out[]; };
layout(std430, set = 0, binding = 2) writeonly restrict buffer StepsOut { uint steps_out[]; };
layout(std430, set = 0, binding = 3) writeonly restrict buffer BackgroundOut { vec4 background_out[]; };
#define SVO_OCTREE_BINDING 4
#include "octree_bindings.glsl"
#include "common/tracer.glsl"

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= params.image.x || pixel.y >= params.image.y) return;
  SvoPixel px = svo_trace_pixel(pixel);
  uint i = pixel.y * params.image.x + pixel.x;
  colour_out[i] = px.colour;
  background_out[i] = px.background;
  steps_out[i] = px.steps;
  if ((params.image.w & SVO_SPEC_FLAGS & SVO_FLAG_GBUFFER) != 0u) {
    for (uint k = 0u; k < SVO_GBUFFER_VEC4S; ++k) gbuffer_out[SVO_GBUFFER_VEC4S * i + k] = svo_gbuffer_pack(px.g, k);
  }
}
