// Sub-pixel occlusion masks (tracer part 2 of 5): the table lookup over
// (theta, v), bit counts, and the part of the footprint a set of bits stands
// for (its centre and spread).
//
// The buffer svo_mask reads (render::tracer_buffer builds it), in entries
// of four words:
//   [0, SVO_MASK_BINS^2)         the masks, theta-major;
//   SVO_MASK_POINTS + [0, 64)    the 128 footprint points, two to an entry;
//   SVO_MASK_POINTS + 64, 65     their sums (x, y, x^2, y^2; x y);
//   SVO_TABLE_SRGB8 + [0, 64)    256 floats: Srgb8 byte to linear;
//   SVO_TABLE_U8_LOG + [0, 64)   256 floats: U8LogRelative byte, scale 1;
//   SVO_TABLE_S8 + [0, 64)       256 floats: Signed8 byte.
#ifndef SVO_MASKS_GLSL
#define SVO_MASKS_GLSL
#include "cone_mask.glsl"
#include "tracer_params.glsl"

SVO_CONST uint SVO_MASK_POINTS = SVO_MASK_BINS * SVO_MASK_BINS;
SVO_CONST uint SVO_TABLE_SRGB8 = SVO_MASK_POINTS + 66u;
SVO_CONST uint SVO_TABLE_U8_LOG = SVO_TABLE_SRGB8 + 64u;
SVO_CONST uint SVO_TABLE_S8 = SVO_TABLE_U8_LOG + 64u;

// Entry `b` (a byte) of the decode table that starts at entry `table`.
SVO_FN float svo_decode_table(uint table, uint b) {
  uvec4 e = svo_mask(table + (b >> 2u));
  return uintBitsToFloat(e[b & 3u]);
}

// The table's mask for (theta, v), nearest cell; all or nothing outside (-1, 1).
// Same binning as render::lookup_mask.
SVO_FN uvec4 svo_mask_lookup(SvoMaskParams mp) {
  if (!(mp.v > -1.0f)) return uvec4(0u);
  if (mp.v >= 1.0f) return uvec4(0xFFFFFFFFu);
  int t = int(floor((mp.theta + SVO_PI) / (2.0f * SVO_PI) * float(SVO_MASK_BINS)));
  if (t >= int(SVO_MASK_BINS)) t -= int(SVO_MASK_BINS);
  if (t < 0) t += int(SVO_MASK_BINS);
  int vi = min(int((mp.v + 1.0f) * 0.5f * float(SVO_MASK_BINS)), int(SVO_MASK_BINS) - 1);
  return svo_mask(uint(t) * SVO_MASK_BINS + uint(vi));
}

SVO_FN int svo_popcount(uvec4 m) {
  return svo_bit_count(m.x) + svo_bit_count(m.y) + svo_bit_count(m.z) + svo_bit_count(m.w);
}

// Footprint point i of the mask bits (unit disk; render::tracer_mask_buffer
// stores the points after the table, two to an entry, then their sums).
SVO_FN vec2 svo_mask_point(uint i) {
  uvec4 w = svo_mask(SVO_MASK_POINTS + (i >> 1u));
  return (i & 1u) != 0u ? vec2(uintBitsToFloat(w.z), uintBitsToFloat(w.w))
                        : vec2(uintBitsToFloat(w.x), uintBitsToFloat(w.y));
}

// The part of the footprint some mask bits stand for, in the unit disk.
struct SvoFootprintPart {
  vec2 centre;  // mean of the bits' points
  vec3 spread;  // their covariance (xx, yy, xy)
};

// The mean and covariance of the points of the set bits of `bits`: a loop
// over at most 64 bits, the complement's when more than half are set. All
// bits or none stand for the whole disk, exactly: centre 0, variance 1/4
// per axis.
SVO_FN SvoFootprintPart svo_footprint_part(uvec4 bits) {
  SvoFootprintPart part;
  int n = svo_popcount(bits);
  if (n == 0 || n == 128) {
    part.centre = vec2(0.0f);
    part.spread = vec3(0.25f, 0.25f, 0.0f);
    return part;
  }
  bool complement = n > 64;
  uvec4 b = complement ? ~bits : bits;
  vec2 s1 = vec2(0.0f);
  vec3 s2 = vec3(0.0f);
  for (int k = 0; k < 4; ++k) {
    uint w = b[k];
    while (w != 0u) {
      vec2 q = svo_mask_point(uint(k) * 32u + uint(svo_find_lsb(w)));
      w &= w - 1u;
      s1 += q;
      s2 += vec3(q.x * q.x, q.y * q.y, q.x * q.y);
    }
  }
  if (complement) {
    uvec4 a = svo_mask(SVO_MASK_POINTS + 64u);
    uvec4 c = svo_mask(SVO_MASK_POINTS + 65u);
    s1 = vec2(uintBitsToFloat(a.x), uintBitsToFloat(a.y)) - s1;
    s2 = vec3(uintBitsToFloat(a.z), uintBitsToFloat(a.w), uintBitsToFloat(c.x)) - s2;
  }
  part.centre = s1 / float(n);
  part.spread = s2 / float(n) - vec3(part.centre.x * part.centre.x, part.centre.y * part.centre.y,
                                     part.centre.x * part.centre.y);
  return part;
}

#endif
