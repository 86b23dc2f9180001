// Sample sequences of the Monte Carlo passes: a Halton sequence (radical
// inverses in the first prime bases) per pixel, decorrelated between pixels
// by a Cranley-Patterson rotation per pixel and dimension from a hash, so
// that neighbouring pixels do not share their error pattern.
#ifndef SVO_SEQUENCE_GLSL
#define SVO_SEQUENCE_GLSL
#include "prelude.glsl"

// A 32-bit integer hash (Jarzynski & Olano 2020, PCG).
SVO_FN uint svo_pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// A uniform float in [0, 1) from the top 24 bits of x.
SVO_FN float svo_unit_float(uint x) { return float(x >> 8u) * (1.0f / 16777216.0f); }

// The radical inverse of i in the prime base of dimension `dim` (0: 2,
// 1: 3, 2: 5, ... up to 11: 37), in [0, 1).
SVO_FN float svo_radical_inverse(uint dim, uint i) {
  if (dim == 0u) return float(bitfieldReverse(i) >> 8u) * (1.0f / 16777216.0f);
  uint base = 3u;
  if (dim == 2u) base = 5u;
  if (dim == 3u) base = 7u;
  if (dim == 4u) base = 11u;
  if (dim == 5u) base = 13u;
  if (dim == 6u) base = 17u;
  if (dim == 7u) base = 19u;
  if (dim == 8u) base = 23u;
  if (dim == 9u) base = 29u;
  if (dim == 10u) base = 31u;
  if (dim >= 11u) base = 37u;
  float inv = 1.0f / float(base);
  float f = inv;
  float r = 0.0f;
  uint n = i;
  while (n > 0u) {
    // n / base without an integer division (lavapipe's division by these
    // constants went wrong past about 870 samples): a float quotient,
    // corrected by one either way.
    uint q = uint(float(n) * inv);
    if (q * base > n) {
      q -= 1u;
    } else if ((q + 1u) * base <= n) {
      q += 1u;
    }
    r += float(n - q * base) * f;
    n = q;
    f *= inv;
  }
  return min(r, 0.99999994f);
}

// Dimension `dim` of sample `i` of pixel `pixel` under seed `seed`.
SVO_FN float svo_sample_1d(uint pixel, uint seed, uint i, uint dim) {
  float shift = svo_unit_float(svo_pcg_hash(svo_pcg_hash(pixel ^ (seed * 0x9E3779B9u)) + dim * 0x85EBCA6Bu));
  float u = svo_radical_inverse(dim, i) + shift;
  return u >= 1.0f ? u - 1.0f : u;
}

SVO_FN vec2 svo_sample_2d(uint pixel, uint seed, uint i, uint dim) {
  return vec2(svo_sample_1d(pixel, seed, i, dim), svo_sample_1d(pixel, seed, i, dim + 1u));
}

#endif
