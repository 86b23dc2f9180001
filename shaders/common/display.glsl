// The display pass's kernel (render::DisplayPass), per texel: linear RGB
// radiance to 8-bit sRGB, clamped, NaN as 0; coverage to alpha. One uint,
// R in the lowest byte.
#ifndef SVO_DISPLAY_GLSL
#define SVO_DISPLAY_GLSL
#include "voxel_codec.glsl"

SVO_FN uint svo_display_byte(float linear) {
  float c = linear > 0.0f ? min(linear, 1.0f) : 0.0f;  // NaN fails the test: 0
  return svo_encode_srgb8(c);
}

SVO_FN uint svo_display_texel(vec4 c) {
  float a = c.w > 0.0f ? min(c.w, 1.0f) : 0.0f;
  return svo_display_byte(c.x) | (svo_display_byte(c.y) << 8u) | (svo_display_byte(c.z) << 16u) |
         (uint(floor(a * 255.0f + 0.5f)) << 24u);
}

#endif
