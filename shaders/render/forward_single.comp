#version 460
#extension GL_GOOGLE_include_directive : require
// The forward-shading pass over bricks in one storage buffer (any device).
#define SVO_POOL_SINGLE
#include "forward_main.glsl"
