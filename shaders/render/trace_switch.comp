#version 460
#extension GL_GOOGLE_include_directive : require
// The cone tracer over bricks in several storage buffers, chosen by a switch
// (devices without buffer device addresses).
#include "trace_main.glsl"
