#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_buffer_reference_uvec2 : require
// The bandwidth-adaptive pass over bricks in several buffers read through their
// device addresses (VK_KHR_buffer_device_address).
#define SVO_POOL_ADDRESS
#include "adaptive_main.glsl"
