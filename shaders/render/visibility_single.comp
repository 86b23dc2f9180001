#version 460
#extension GL_GOOGLE_include_directive : require
// The visibility pass over bricks in one storage buffer (any device).
#define SVO_POOL_SINGLE
#include "visibility_main.glsl"
