#version 460
#extension GL_GOOGLE_include_directive : require
// The bandwidth-adaptive pass over bricks in separate storage buffers and a switch.
#include "adaptive_main.glsl"
