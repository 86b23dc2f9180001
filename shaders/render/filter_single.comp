#version 460
#extension GL_GOOGLE_include_directive : require
// The lobe-aware filter over bricks in one storage buffer (any device).
#define SVO_POOL_SINGLE
#include "filter_main.glsl"
