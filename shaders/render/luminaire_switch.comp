#version 460
#extension GL_GOOGLE_include_directive : require
// The luminaire pass over bricks in separate storage buffers and a switch.
#include "luminaire_main.glsl"
