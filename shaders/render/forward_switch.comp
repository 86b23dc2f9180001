#version 460
#extension GL_GOOGLE_include_directive : require
// The forward-shading pass over bricks in separate storage buffers and a switch.
#include "forward_main.glsl"
