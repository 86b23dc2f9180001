#version 460
#extension GL_GOOGLE_include_directive : require
// Evaluates the shared math (common/probe.glsl) for each input; the C++ side
// computes the same and compares (svo selftest, tests/gpu).
#include "common/probe.glsl"

layout(local_size_x = SVO_PROBE_WORKGROUP) in;

layout(std430, set = 0, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
layout(push_constant) uniform Push { uint count; } push;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= push.count) return;
  for (int k = 0; k < SVO_PROBE_OUTPUTS; ++k) {
    outputs[i * uint(SVO_PROBE_OUTPUTS) + uint(k)] = svo_probe_row(inputs[i], k);
  }
}
