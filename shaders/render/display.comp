#version 460
#extension GL_GOOGLE_include_directive : require
// Display pass: one texel of "colour" to "display" (common/display.glsl).
#include "common/display.glsl"

layout(local_size_x = 64) in;

layout(std430, set = 0, binding = 0) readonly restrict buffer ColourIn { vec4 colour[]; };
layout(std430, set = 0, binding = 1) writeonly restrict buffer DisplayOut { uint display[]; };
layout(push_constant) uniform Push { uint count; } push;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.count) return;
  display[i] = svo_display_texel(colour[i]);
}
