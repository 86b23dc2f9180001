#version 460
#extension GL_GOOGLE_include_directive : require
// The lobe-aware filter over bricks in separate storage buffers and a switch.
#include "filter_main.glsl"
