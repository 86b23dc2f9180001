#version 460
#extension GL_GOOGLE_include_directive : require
// Display pass: linear RGB radiance to 8-bit sRGB, clamped, NaN as 0;
// coverage to alpha.
#include "common/voxel_codec.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer ColourIn { vec4 colour[]; };
layout(std430, set = 0, binding = 1) writeonly restrict buffer DisplayOut { uint display[]; };
layout(push_constant) uniform Push { uint count; } push;

uint to_byte(float linear) {
  float c = linear > 0.0f ? min(linear, 1.0f) : 0.0f;  // NaN fails the test: 0
  return uint(svo_encode_srgb8(c));
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.count) return;
  vec4 c = colour[i];
  float a = c.w > 0.0f ? min(c.w, 1.0f) : 0.0f;
  display[i] = to_byte(c.x) | (to_byte(c.y) << 8u) | (to_byte(c.z) << 16u) | (uint(floor(a * 255.0f + 0.5f)) << 24u);
}
