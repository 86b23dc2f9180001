// Compact encodings of the octree's voxel channels (octree/octree.h,
// Encoding), decoded by the renderer and encoded by the voxelizer. Packed
// values are passed as uint (low bits first); bytes are little-endian.
#ifndef SVO_VOXEL_CODEC_GLSL
#define SVO_VOXEL_CODEC_GLSL
#include "prelude.glsl"

// Octahedral map of a unit vector to [-1, 1]^2 (Meyer et al. 2010).
SVO_FN vec2 svo_oct_wrap(vec2 v) {
  return (vec2(1.0f) - abs(vec2(v.y, v.x))) * vec2(v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f);
}

// Oct24: two 12-bit coordinates. The encoder tries the 4 codes around the
// projected point and keeps the one that decodes closest to n (Cigolle et
// al. 2014): worst angular error 0.04 degrees (plain rounding: 0.06).
// The point of the octahedron |x| + |y| + |z| = 1 that a code stands for.
SVO_FN vec3 svo_oct24_unfold(uint bits) {
  vec2 p = vec2(float(bits & 4095u), float((bits >> 12u) & 4095u)) * (2.0f / 4095.0f) - vec2(1.0f);
  vec3 n = vec3(p.x, p.y, 1.0f - abs(p.x) - abs(p.y));
  if (n.z < 0.0f) {
    vec2 w = svo_oct_wrap(vec2(n.x, n.y));
    n.x = w.x;
    n.y = w.y;
  }
  return n;
}

SVO_FN vec3 svo_decode_oct24(uint bits) {
  return normalize(svo_oct24_unfold(bits));
}

SVO_FN uint svo_encode_oct24(vec3 n) {
  vec3 a = abs(n);
  float l1 = a.x + a.y + a.z;
  if (!(l1 > 0.0f)) return 2047u | (2047u << 12u);  // no direction: +z
  vec2 p = vec2(n.x, n.y) / l1;
  if (n.z < 0.0f) p = svo_oct_wrap(p);
  vec2 q = clamp(p * 0.5f + vec2(0.5f), vec2(0.0f), vec2(1.0f)) * 4095.0f;
  // Compare sin^2 of the angle to n, |d x n|^2 / |d|^2 (times 1/|n|^2): precise
  // for small angles (a dot product near 1 would lose them), compared by
  // cross-multiplying, without sqrt or division.
  uint best = 0u;
  float best_c2 = 1.0f, best_d2 = 0.0f;
  uint x0 = uint(q.x), y0 = uint(q.y);  // q >= 0: truncation is floor
  for (int k = 0; k < 4; ++k) {
    uint x = min(x0 + uint(k & 1), 4095u);
    uint y = min(y0 + uint(k >> 1), 4095u);
    uint code = x | (y << 12u);
    vec3 d = svo_oct24_unfold(code);
    vec3 c = cross(d, n);
    float c2 = dot(c, c), d2 = dot(d, d);
    if (dot(d, n) > 0.0f && (best_d2 == 0.0f || c2 * best_d2 < best_c2 * d2)) {
      best_c2 = c2;
      best_d2 = d2;
      best = code;
    }
  }
  return best;
}

// U8LogRelative: x / scale on a log2 scale, 16 steps per octave over
// [2^-15.9, 1] (relative error within +-2.2%), 0 stored as 0.
SVO_FN uint svo_encode_u8_log_relative(float x, float scale) {
  float r = x / scale;
  if (!(r > 0.0f)) return 0u;
  float b = 255.0f + 16.0f * log2(min(r, 1.0f));
  return uint(clamp(floor(b + 0.5f), 1.0f, 255.0f));
}
SVO_FN float svo_decode_u8_log_relative(uint b, float scale) {
  b = b & 255u;
  return b == 0u ? 0.0f : scale * exp2((float(b) - 255.0f) / 16.0f);
}

// U8LogSlope: a slope deviation s on a log2 scale, 16 steps per octave over
// [2^-11.9, 16] (relative error within +-2.2%), 0 stored as 0.
SVO_FN uint svo_encode_u8_log_slope(float s) {
  return svo_encode_u8_log_relative(s, 16.0f);
}
SVO_FN float svo_decode_u8_log_slope(uint b) {
  return svo_decode_u8_log_relative(b, 16.0f);
}

// Signed8: x in [-1, 1] as a two's-complement byte of round(127 x).
SVO_FN uint svo_encode_s8(float x) {
  int i = int(floor(clamp(x, -1.0f, 1.0f) * 127.0f + 0.5f));
  return uint(i) & 255u;
}
SVO_FN float svo_decode_s8(uint b) {
  int i = int(b & 255u);
  if (i > 127) i -= 256;
  return max(float(i) / 127.0f, -1.0f);
}

// Srgb8: linear [0, 1] through the sRGB transfer function.
SVO_FN float svo_linear_to_srgb(float c) {
  c = clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * pow(c, 1.0f / 2.4f) - 0.055f;
}
SVO_FN float svo_srgb_to_linear(float s) {
  return s <= 0.04045f ? s / 12.92f : pow((s + 0.055f) / 1.055f, 2.4f);
}
SVO_FN uint svo_encode_srgb8(float c) {
  return uint(svo_linear_to_srgb(c) * 255.0f + 0.5f);
}
SVO_FN float svo_decode_srgb8(uint b) {
  return svo_srgb_to_linear(float(b & 255u) / 255.0f);
}

#endif
