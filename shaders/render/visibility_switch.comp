#version 460
#extension GL_GOOGLE_include_directive : require
// The visibility pass over bricks in separate storage buffers and a switch.
#include "visibility_main.glsl"
