#version 460
#extension GL_GOOGLE_include_directive : require
// The cone tracer over bricks in one storage buffer (any device).
#define SVO_POOL_SINGLE
#include "trace_main.glsl"
