#version 460
#extension GL_GOOGLE_include_directive : require
// The bandwidth-adaptive pass over bricks in one storage buffer (any device).
#define SVO_POOL_SINGLE
#include "adaptive_main.glsl"
