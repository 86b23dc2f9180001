// The cone tracer, Heitz & Neyret Algorithm 1 (DESIGN section 8), in the
// shared dialect: the compute shader (shaders/render/trace.comp) and the CPU
// renderer (render/src/cpu_renderer.cpp) include this same file.
//
// Before including it, the host declares:
//   SvoTraceParams params;                      the settings of this trace (tracer_params.glsl)
//   uvec2 svo_node(uint index);                 (children, brick) of a node, SVO_ABSENT for none
//   uint svo_brick_bytes(uint brick, uint offset);  the word holding byte `offset` of a brick, shifted
//                                               right so that this byte is the lowest (never straddles)
//   uvec4 svo_mask(uint cell);                  the mask table, theta-major, SVO_MASK_BINS^2 cells
// A brick holds every channel of its (B+1)^3 lattice samples, channel after
// channel (offsets in params), samples x-fastest; a sample of 3 bytes takes 4.
//
// Per pixel: one cone through the pixel centre with the pixel's footprint
// (a disk of the pixel's area) or the thin lens's. Cone elements are as long
// as they are wide; each samples the octree at the level whose voxel matches
// its diameter, interpolating in space and between two levels, and turns the
// voxel's mean plane into a 128-bit sub-pixel mask (cone_mask.glsl); masks
// combine A-buffer style and the background fills the bits never set.
#ifndef SVO_TRACER_GLSL
#define SVO_TRACER_GLSL
#include "beckmann.glsl"
#include "cone_mask.glsl"
#include "detail.glsl"
#include "frame.glsl"
#include "smith.glsl"
#include "tracer_params.glsl"
#include "trig.glsl"
#include "voxel_codec.glsl"

// A voxel as the renderer uses it.
struct SvoVoxel {
  float hbar;  // signed distance to the mean plane, scene units (> 0 outside)
  float sh2;   // height variance sigma_h^2 (read only to draw detail octaves)
  vec3 n;      // mean normal (interpolated, not renormalised)
  vec3 cov;    // slope covariance (xx, yy, xy) in the tangent frame of n
  vec3 abar;   // mean colour, linear
  vec3 a_s;    // colour-height correlation
};

// A cell of the octree at some depth: the brick that covers it, or an empty
// region (brick SVO_ABSENT) known to hold no surface at that depth.
struct SvoCell {
  uint brick;
  uint depth;  // the depth asked for (SVO_ABSENT: no cell yet)
  vec3 lo;     // lower corner of the node's box (of the empty region for an empty cell)
  float size;
};

// A cone: radius(t) = max(r0 + k t, aperture |t - focus| / focus).
struct SvoCone {
  vec3 o;
  vec3 d;      // unit axis
  vec3 inv_d;  // 1 / d, finite
  float r0;
  float k;
  float aperture;
  float focus;
  SvoFrame frame;  // footprint axes (the mask table's x and y)
};

// The state of a march along a cone, advanced element by element.
struct SvoMarch {
  SvoCell lo_cell;  // cached lookups of the coarser and the finer level
  SvoCell hi_cell;
  float t;          // where the next element starts
  bool hit;         // the last element sampled a brick (v, p, mask valid)
  SvoVoxel v;
  vec3 p;           // centre of the last element
  float depth;      // its distance along the cone
  float radius;
  float blend;      // weight of the finer level (hi_cell) in v; 0: the coarser alone
  uvec4 mask;       // its sub-pixel coverage
};

SVO_FN float svo_voxel_size(uint depth) {
  return params.domain.w / float(params.tree.x << depth);
}

// The fractional level whose voxel is `voxel` (scene units), clamped to the
// stored levels: its floor is the level, its fraction the blend with the
// next finer one.
SVO_FN float svo_level_of_voxel(float voxel) {
  return clamp(log2(params.domain.w / (float(params.tree.x) * voxel)), 0.0f, float(params.tree.y - 1u));
}

SVO_FN uint svo_byte(uint brick, uint offset) {
  return svo_brick_bytes(brick, offset) & 255u;
}

// What svo_fetch decodes: most cone elements need the distance only, the
// mask needs the normal too, and only elements that reach the pixel need the
// shading attributes.
// (SVO_PART_* in tracer_params.glsl.)
// Sample s of a brick; fields outside `parts` are zero.
SVO_FN SvoVoxel svo_fetch(uint brick, uint s, uint parts) {
  SvoVoxel v;
  v.hbar = 0.0f;
  v.sh2 = 0.0f;
  v.n = vec3(0.0f);
  v.cov = vec3(0.0f);
  v.abar = vec3(0.0f);
  v.a_s = vec3(0.0f);
  if ((parts & SVO_PART_DISTANCE) != 0u) v.hbar = uintBitsToFloat(svo_brick_bytes(brick, params.offsets_a.x + s * 4u));
  if ((parts & SVO_PART_HEIGHT) != 0u && params.offsets_a.z != SVO_ABSENT) {
    // Relative to the voxel size unless stored as f32 (svo_sample_trilinear scales it).
    float sh = params.encodings.x == SVO_ENC_F32
                   ? uintBitsToFloat(svo_brick_bytes(brick, params.offsets_a.z + s * 4u))
                   : svo_decode_u8_log_relative(svo_byte(brick, params.offsets_a.z + s), 1.0f);
    v.sh2 = sh * sh;
  }
  if ((parts & SVO_PART_NORMAL) == 0u) return v;
  v.n = vec3(0.0f, 0.0f, 1.0f);
  if (params.offsets_a.y != SVO_ABSENT) {
    v.n = svo_decode_oct24(svo_brick_bytes(brick, params.offsets_a.y + s * 4u) & 0xFFFFFFu);
  }
  if ((parts & SVO_PART_SHADING) == 0u) return v;
  if (params.offsets_b.x != SVO_ABSENT) {
    uint b = svo_brick_bytes(brick, params.offsets_b.x + s * 4u);
    float sx = svo_decode_u8_log_slope(b & 255u);
    float sy = svo_decode_u8_log_slope((b >> 8u) & 255u);
    float rho = svo_decode_s8((b >> 16u) & 255u);
    v.cov = vec3(sx * sx, sy * sy, rho * sx * sy);
  } else if (params.offsets_a.w != SVO_ABSENT) {
    float sd = params.encodings.y == SVO_ENC_F32
                   ? uintBitsToFloat(svo_brick_bytes(brick, params.offsets_a.w + s * 4u))
                   : svo_decode_u8_log_slope(svo_byte(brick, params.offsets_a.w + s));
    v.cov = vec3(sd * sd, sd * sd, 0.0f);
  }
  v.abar = vec3(params.constant_colour);
  if (params.offsets_b.y != SVO_ABSENT) {
    uint b = svo_brick_bytes(brick, params.offsets_b.y + s * 4u);
    v.abar = vec3(svo_decode_srgb8(b & 255u), svo_decode_srgb8((b >> 8u) & 255u), svo_decode_srgb8((b >> 16u) & 255u));
  }
  if (params.offsets_b.z != SVO_ABSENT) {
    uint b = svo_brick_bytes(brick, params.offsets_b.z + s * 4u);
    v.a_s = vec3(svo_decode_s8(b & 255u), svo_decode_s8((b >> 8u) & 255u), svo_decode_s8((b >> 16u) & 255u));
  }
  return v;
}

// a + w b, field by field.
SVO_FN SvoVoxel svo_voxel_madd(SvoVoxel a, SvoVoxel b, float w) {
  SvoVoxel r;
  r.hbar = a.hbar + w * b.hbar;
  r.sh2 = a.sh2 + w * b.sh2;
  r.n = a.n + w * b.n;
  r.cov = a.cov + w * b.cov;
  r.abar = a.abar + w * b.abar;
  r.a_s = a.a_s + w * b.a_s;
  return r;
}

SVO_FN SvoVoxel svo_voxel_scaled(SvoVoxel a, float w) {
  SvoVoxel r;
  r.hbar = w * a.hbar;
  r.sh2 = w * a.sh2;
  r.n = w * a.n;
  r.cov = w * a.cov;
  r.abar = w * a.abar;
  r.a_s = w * a.a_s;
  return r;
}

// Lattice coordinates of p in the brick of `cell`, in [0, B].
SVO_FN vec3 svo_local(SvoCell cell, vec3 p) {
  float B = float(params.tree.x);
  return clamp((p - cell.lo) / cell.size * B, vec3(0.0f), vec3(B));
}

SVO_FN uint svo_sample_index(uvec3 i) {
  uint S = params.tree.x + 1u;
  return (i.z * S + i.y) * S + i.x;
}

// Trilinear interpolation of the brick's lattice at p.
SVO_FN SvoVoxel svo_sample_trilinear(SvoCell cell, vec3 p, uint parts) {
  vec3 c = svo_local(cell, p);
  vec3 i0f = min(floor(c), vec3(float(params.tree.x - 1u)));
  vec3 f = c - i0f;
  uvec3 i0 = uvec3(i0f);
  SvoVoxel r = svo_voxel_scaled(svo_fetch(cell.brick, svo_sample_index(i0), parts), (1.0f - f.x) * (1.0f - f.y) * (1.0f - f.z));
  for (uint k = 1u; k < 8u; ++k) {
    uvec3 o = uvec3(k & 1u, (k >> 1u) & 1u, k >> 2u);
    vec3 w = mix(vec3(1.0f) - f, f, vec3(o));
    r = svo_voxel_madd(r, svo_fetch(cell.brick, svo_sample_index(i0 + o), parts), w.x * w.y * w.z);
  }
  if (params.encodings.x != SVO_ENC_F32) {
    float voxel = cell.size / float(params.tree.x);
    r.sh2 *= voxel * voxel;
  }
  return r;
}

// How the trilinearly interpolated normal of a level changes along world
// directions q1 and q2 at p: the derivatives of the interpolation weights
// applied to the cell's 8 unit normals.
struct SvoNormalChange {
  vec3 d1;
  vec3 d2;
};
SVO_FN SvoNormalChange svo_normal_change(SvoCell cell, vec3 p, vec3 q1, vec3 q2) {
  vec3 c = svo_local(cell, p);
  vec3 i0f = min(floor(c), vec3(float(params.tree.x - 1u)));
  vec3 f = c - i0f;
  uvec3 i0 = uvec3(i0f);
  float inv_voxel = float(params.tree.x) / cell.size;
  SvoNormalChange r;
  r.d1 = vec3(0.0f);
  r.d2 = vec3(0.0f);
  for (uint k = 0u; k < 8u; ++k) {
    uvec3 o = uvec3(k & 1u, (k >> 1u) & 1u, k >> 2u);
    vec3 w = mix(vec3(1.0f) - f, f, vec3(o));
    vec3 dw = mix(vec3(-1.0f), vec3(1.0f), vec3(o));
    vec3 grad = inv_voxel * vec3(dw.x * w.y * w.z, w.x * dw.y * w.z, w.x * w.y * dw.z);
    vec3 n = svo_fetch(cell.brick, svo_sample_index(i0 + o), SVO_PART_NORMAL).n;
    r.d1 += dot(grad, q1) * n;
    r.d2 += dot(grad, q2) * n;
  }
  return r;
}

// Slope variance a level's voxel already holds along the surface: the
// spread over its box footprint (s^2 / 12 per axis); none at the finest
// level, whose voxels store zero variances.
SVO_FN float svo_voxel_spread(SvoCell cell) {
  float s = cell.size / float(params.tree.x);
  return cell.depth + 1u >= params.tree.y ? 0.0f : s * s / 12.0f;
}

// The lattice point nearest to p (binary-voxel baseline).
SVO_FN SvoVoxel svo_sample_nearest(SvoCell cell, vec3 p) {
  return svo_fetch(cell.brick, svo_sample_index(uvec3(floor(svo_local(cell, p) + 0.5f))),
                   SVO_PART_DISTANCE | SVO_PART_NORMAL | SVO_PART_SHADING);
}

// Descends from the root to the node of `depth` holding p; stops at the
// first missing node or brick and returns that node's box as empty.
SVO_FN SvoCell svo_lookup(vec3 p, uint depth) {
  vec3 q = clamp((p - vec3(params.domain)) / params.domain.w, vec3(0.0f), vec3(0.99999994f));
  SvoCell c;
  c.depth = depth;
  c.lo = vec3(params.domain);
  c.size = params.domain.w;
  uvec2 node = svo_node(0u);
  c.brick = node.y;
  for (uint k = 1u; k <= depth && c.brick != SVO_ABSENT; ++k) {
    uvec3 cell = uvec3(q * float(1u << k));
    c.size = params.domain.w / float(1u << k);
    c.lo = vec3(params.domain) + vec3(cell) * c.size;
    if (node.x == SVO_ABSENT) {
      c.brick = SVO_ABSENT;
    } else {
      uvec3 bit = cell & uvec3(1u);
      node = svo_node(node.x + bit.x + 2u * bit.y + 4u * bit.z);
      c.brick = node.y;
    }
  }
  return c;
}

SVO_FN bool svo_cell_holds(SvoCell c, vec3 p, uint depth) {
  return c.depth == depth && all(greaterThanEqual(p, c.lo)) && all(lessThan(p, c.lo + c.size));
}

// Distance along the ray (o, inv_d) to where it leaves the box [lo, lo + size].
SVO_FN float svo_box_exit(vec3 o, vec3 inv_d, vec3 lo, float size) {
  vec3 t0 = (lo - o) * inv_d;
  vec3 t1 = (lo + size - o) * inv_d;
  vec3 tmax = max(t0, t1);
  return min(min(tmax.x, tmax.y), tmax.z);
}

SVO_FN float svo_box_entry(vec3 o, vec3 inv_d, vec3 lo, float size) {
  vec3 t0 = (lo - o) * inv_d;
  vec3 t1 = (lo + size - o) * inv_d;
  vec3 tmin = min(t0, t1);
  return max(max(tmin.x, tmin.y), tmin.z);
}

SVO_FN vec3 svo_safe_inverse(vec3 d) {
  vec3 s = vec3(d.x < 0.0f ? -1.0f : 1.0f, d.y < 0.0f ? -1.0f : 1.0f, d.z < 0.0f ? -1.0f : 1.0f);
  return s / max(abs(d), vec3(1.0e-20f));
}

SVO_FN SvoCone svo_make_cone(vec3 o, vec3 d, float r0, float k, float aperture, float focus) {
  SvoCone c;
  c.o = o;
  c.d = d;
  c.inv_d = svo_safe_inverse(d);
  c.r0 = r0;
  c.k = k;
  c.aperture = aperture;
  c.focus = focus;
  c.frame = svo_tangent_frame(d);
  return c;
}

SVO_FN float svo_cone_radius(SvoCone c, float t) {
  float r = c.r0 + c.k * t;
  if (c.aperture > 0.0f) r = max(r, c.aperture * abs(t - c.focus) / c.focus);
  return max(r, 1.0e-7f * params.domain.w);
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
  ivec4 c = bitCount(m);
  return c.x + c.y + c.z + c.w;
}

// Footprint point i of the mask bits (unit disk; render::tracer_mask_buffer
// stores the points after the table, two to an entry, then their sums).
SVO_FN vec2 svo_mask_point(uint i) {
  uvec4 w = svo_mask(SVO_MASK_BINS * SVO_MASK_BINS + (i >> 1u));
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
      vec2 q = svo_mask_point(uint(k) * 32u + uint(findLSB(w)));
      w &= w - 1u;
      s1 += q;
      s2 += vec3(q.x * q.x, q.y * q.y, q.x * q.y);
    }
  }
  if (complement) {
    uvec4 a = svo_mask(SVO_MASK_BINS * SVO_MASK_BINS + 64u);
    uvec4 c = svo_mask(SVO_MASK_BINS * SVO_MASK_BINS + 65u);
    s1 = vec2(uintBitsToFloat(a.x), uintBitsToFloat(a.y)) - s1;
    s2 = vec3(uintBitsToFloat(a.z), uintBitsToFloat(a.w), uintBitsToFloat(c.x)) - s2;
  }
  part.centre = s1 / float(n);
  part.spread = s2 / float(n) - vec3(part.centre.x * part.centre.x, part.centre.y * part.centre.y,
                                     part.centre.x * part.centre.y);
  return part;
}

// The file's detail octaves (params.detail*).
SVO_FN SvoDetail svo_trace_detail() {
  SvoDetail d;
  d.octaves = params.detail_u.x;
  d.seed = params.detail_u.y;
  d.amplitude = params.detail.x;
  d.wavelength = params.detail.y;
  d.gain = params.detail.z;
  return d;
}

// Whether an element of radius r draws detail octaves that the finest level
// holds only as statistics (its footprint is finer than the finest level's).
SVO_FN bool svo_draws_detail(float r) { return params.detail_u.x > 0u && r < params.detail_colour.w; }

// The mean normal n tilted by the gradient g of an added displacement along
// it (the gradient of distance - displacement), its length kept.
SVO_FN vec3 svo_detail_tilt(vec3 n, vec3 g) {
  float nl = length(n);
  if (!(nl > 0.0f)) return n;
  return normalize(n / nl - g) * nl;
}

SVO_FN SvoMarch svo_march_start(float t) {
  SvoMarch m;
  m.lo_cell.brick = SVO_ABSENT;
  m.lo_cell.depth = SVO_ABSENT;
  m.lo_cell.lo = vec3(0.0f);
  m.lo_cell.size = 0.0f;
  m.hi_cell = m.lo_cell;
  m.t = t;
  m.hit = false;
  m.v.hbar = 0.0f;
  m.v.sh2 = 0.0f;
  m.v.n = vec3(0.0f, 0.0f, 1.0f);
  m.v.cov = vec3(0.0f);
  m.v.abar = vec3(0.0f);
  m.v.a_s = vec3(0.0f);
  m.p = vec3(0.0f);
  m.depth = 0.0f;
  m.radius = 0.0f;
  m.blend = 0.0f;
  m.mask = uvec4(0u);
  return m;
}

// One cone element from m.t: skips a region the octree knows to be empty,
// or samples the voxel under the element and computes its coverage mask.
SVO_FN SvoMarch svo_step(SvoMarch m, SvoCone cone, uint mode) {
  float r = svo_cone_radius(cone, m.t);
  // Elements shorter than a quarter of the finest voxel see nothing new,
  // unless detail octaves are drawn: then a quarter of the finest drawn
  // wavelength (between r and 2r).
  float shortest = params.material.z;
  if (svo_draws_detail(r)) {
    SvoDetail d = svo_trace_detail();
    float drawn = svo_detail_drawn(d, r);
    if (drawn > 0.0f) shortest = min(shortest, svo_detail_wavelength(d, uint(drawn) - 1u));
  }
  float half_length = max(r, 0.25f * shortest);
  vec3 p = cone.o + cone.d * (m.t + half_length);
  uint last = params.tree.y - 1u;
  // The level whose trilinear filter matches the footprint: interpolation
  // spreads a level's values over a tent of half-width one voxel, whose
  // variance (s^2 / 6) equals that of the footprint's width 2r (a box,
  // (2r)^2 / 12) when the voxel size is s = sqrt(2) r, half an octave finer
  // than "voxel = diameter". Measured on the bumpy sphere's far view (256^3,
  // 256x256): relMSE 0.00181 at voxel = 2r, 0.00093 at sqrt(2) r, 0.00102 at r.
  float df = svo_level_of_voxel(SVO_SQRT2 * r);
  // Outside the domain (a defocused cone's elements may start there): empty.
  vec3 inside = (p - vec3(params.domain)) / params.domain.w;
  if (any(lessThan(inside, vec3(0.0f))) || any(greaterThanEqual(inside, vec3(1.0f)))) {
    m.hit = false;
    m.mask = uvec4(0u);
    m.t += 2.0f * half_length;
    return m;
  }
  uint lo = mode == SVO_MODE_NEAREST ? uint(floor(df + 0.5f)) : uint(floor(df));
  float w = mode == SVO_MODE_NEAREST ? 0.0f : df - float(lo);
  if (!svo_cell_holds(m.lo_cell, p, lo)) m.lo_cell = svo_lookup(p, lo);
  m.hit = false;
  m.mask = uvec4(0u);
  if (m.lo_cell.brick == SVO_ABSENT) {
    // Empty at this level: jump to where the ray leaves the empty box.
    float exit = svo_box_exit(cone.o, cone.inv_d, m.lo_cell.lo, m.lo_cell.size);
    m.t = max(m.t + 2.0f * half_length, exit + 1.0e-5f * m.lo_cell.size);
    return m;
  }
  SvoVoxel v;
  m.blend = 0.0f;
  float jump = -1.0f;  // how far the distance allows to skip past p (< 0: the distance less the radius)
  if (mode == SVO_MODE_NEAREST) {
    v = svo_sample_nearest(m.lo_cell, p);
    m.mask = v.hbar <= 0.0f ? uvec4(0xFFFFFFFFu) : uvec4(0u);
  } else {
    // The distance first: an element farther than its radius and half length
    // from the mean plane covers nothing, whatever the normal.
    v = svo_sample_trilinear(m.lo_cell, p, SVO_PART_DISTANCE);
    if (w > 0.0f && lo < last) {
      if (!svo_cell_holds(m.hi_cell, p, lo + 1u)) m.hi_cell = svo_lookup(p, lo + 1u);
      if (m.hi_cell.brick != SVO_ABSENT) {
        m.blend = w;
        v.hbar = mix(v.hbar, svo_sample_trilinear(m.hi_cell, p, SVO_PART_DISTANCE).hbar, w);
      }
    }
    // Detail octaves finer than the finest level, coarser than the element:
    // the surface moves by their displacement and tilts with their gradient.
    // Outside the shell they can reach, the stored distance less the reach
    // is a safe distance and nothing needs evaluating.
    vec4 detail = vec4(0.0f);
    if (svo_draws_detail(r)) {
      SvoDetail d = svo_trace_detail();
      vec2 bounds = svo_detail_bounds(d, r, params.detail_colour.w);
      if (v.hbar - bounds.x < half_length + r) {
        // Eight jumps to try, 1/2 to 1/256 of the longest the gap could
        // allow: the octaves seldom come near the shell's bound.
        float longest = 0.8f * max(v.hbar + bounds.x - r, 0.0f);
        vec4 s = longest * vec4(0.5f, 0.25f, 0.125f, 0.0625f);
        vec4 s2 = longest * vec4(0.03125f, 0.015625f, 0.0078125f, 0.00390625f);
        SvoDetailSample ds = svo_detail_displacement_along(d, p, r, params.detail_colour.w, cone.d, s, s2);
        detail = ds.displacement;
        v.hbar -= detail.w;
        // The stored distance changes by at most the jump, the drawn
        // octaves by `change`: the longest jump that keeps both within the
        // gap, else the Lipschitz bound of stored distance and octaves.
        float gap = 0.8f * (v.hbar - r);
        jump = gap / (1.0f + bounds.y);
        for (int i = 3; i >= 0; --i) {
          if (s[i] + ds.change[i] <= gap) jump = max(jump, s[i]);
          if (s2[i] + ds.change2[i] <= gap) jump = max(jump, s2[i]);
        }
      } else {
        v.hbar -= bounds.x;
      }
    }
    if (v.hbar < half_length + r) {
      v.n = svo_sample_trilinear(m.lo_cell, p, SVO_PART_NORMAL).n;
      if (m.blend > 0.0f) v.n = mix(v.n, svo_sample_trilinear(m.hi_cell, p, SVO_PART_NORMAL).n, m.blend);
      v.n = svo_detail_tilt(v.n, vec3(detail));
      float nl = length(v.n);
      vec3 n = nl > 0.0f ? v.n / nl : -cone.d;
      vec3 nc = vec3(dot(n, cone.frame.t), dot(n, cone.frame.b), dot(n, cone.d));
      // The surface's curvature along the axis, d . dn/dd, for masks that
      // follow a convex silhouette (cone_mask.glsl); rays have no footprint.
      // Convex only: where interpolation meets a voxel that knows no
      // surface (a stand-in normal), the normal turns fast and either way,
      // and a concave reading would add coverage beside the silhouette
      // (3 specks instead of 1 in Specks.*); the plane stays the bound.
      // Only for footprints of at least about a finest voxel (full weight
      // from r = 0.75 voxel, none below 0.25): finer, the interpolated
      // distance of a convex surface already lies outside it, and a mesh's
      // per-triangle normals turn at triangle edges, not with the surface
      // (the bunny's close view lost 6% with the correction there).
      float kappa = 0.0f;
      bool curved = (params.image.w & SVO_FLAG_CURVED_MASKS) != 0u;
      if (curved && (mode == SVO_MODE_PREFILTERED || mode == SVO_MODE_ALPHA) && nl > 0.0f &&
          r > 1.0e-6f * params.domain.w) {
        vec3 dn = svo_normal_change(m.lo_cell, p, cone.d, cone.d).d1;
        if (m.blend > 0.0f) dn = mix(dn, svo_normal_change(m.hi_cell, p, cone.d, cone.d).d1, m.blend);
        kappa = max(dot(cone.d, dn) / max(nl, 0.5f), 0.0f) * clamp(2.0f * r / params.material.z - 0.5f, 0.0f, 1.0f);
      }
      m.mask = svo_mask_lookup(svo_cone_mask_params_curved(nc, v.hbar, r, half_length, kappa));
    }
  }
  m.hit = true;
  m.v = v;
  m.p = p;
  m.depth = m.t + half_length;
  m.radius = r;
  // The element cannot reach a surface farther than hbar: skip most of the
  // gap (where detail is evaluated, as far as its bounds allow).
  float advance = 2.0f * half_length;
  if (mode != SVO_MODE_NEAREST && v.hbar > half_length + r) {
    advance = max(advance, half_length + (jump >= 0.0f ? jump : 0.8f * (v.hbar - r)));
  }
  m.t += advance;
  return m;
}

struct SvoVisibility {
  float visible;  // unoccluded fraction of the shadow cone's footprint
  uint steps;
};

// Visibility of a light from the element at p (radius r0) along unit l, up
// to `dist`: a cone that starts with the element's radius and widens with
// the light's size (`spread` per unit distance), occlusion combined as on
// the primary cone.
SVO_FN SvoVisibility svo_visibility(vec3 p, vec3 l, float dist, float r0, float spread, float n_dot_l, uint mode) {
  SvoVisibility vis;
  vis.visible = 1.0f;
  vis.steps = 0u;
  SvoCone cone = svo_make_cone(p, l, r0, spread, 0.0f, 0.0f);
  float t1 = min(dist, svo_box_exit(p, cone.inv_d, vec3(params.domain), params.domain.w));
  // Start where the element's own plane no longer reaches into the cone.
  SvoMarch m = svo_march_start(min(2.0f * r0 / max(n_dot_l, 0.25f), 8.0f * r0));
  uvec4 alpha = uvec4(0u);
  float opacity = 0.0f;
  while (m.t < t1 && vis.steps < SVO_SHADOW_STEPS) {
    vis.steps += 1u;
    m = svo_step(m, cone, mode);
    if (!m.hit) continue;
    if (mode == SVO_MODE_ALPHA) {
      opacity += (1.0f - opacity) * float(svo_popcount(m.mask)) / 128.0f;
      if (opacity >= 0.999f) break;
    } else {
      alpha = alpha | m.mask;
      if (svo_popcount(alpha) == 128) break;
    }
  }
  vis.visible = mode == SVO_MODE_ALPHA ? 1.0f - opacity : 1.0f - float(svo_popcount(alpha)) / 128.0f;
  return vis;
}

// The normals' spread over the part of the surface the cone's footprint
// covers, as slope covariance (xx, yy, xy) in the tangent frame of the unit
// mean normal nh (n_length: the interpolated normal's length). A cone
// element shades one point, with the statistics of voxels that stop at
// their own box (or hold none, at the finest level): where the normal field
// turns across the footprint, a narrow lobe would light all of a pixel or
// none of it, and a grazing light all of it or none. `spread` is the
// covariance of the part of the footprint the element shades, in units of
// the radius (the whole disk: r^2 / 4 per axis); on the mean plane each axis
// stretches along the ray by 1 / |d.n| (at most 1 / min_cosine), and the
// interpolated normal changes along it at the rate the lattice gives.
// Scaled by params.material.w (`svo render --footprint-spread`, default 1:
// the second-order theory).
SVO_FN vec3 svo_footprint_slope_covariance(SvoMarch m, vec3 dir, vec3 nh, float n_length, vec3 spread) {
  const float min_cosine = 0.2f;
  SvoFrame across = svo_tangent_frame(dir);
  float dn = dot(dir, nh);
  dn = dn >= 0.0f ? max(dn, min_cosine) : min(dn, -min_cosine);
  vec3 q1 = across.t - (dot(across.t, nh) / dn) * dir;
  vec3 q2 = across.b - (dot(across.b, nh) / dn) * dir;
  SvoNormalChange g = svo_normal_change(m.lo_cell, m.p, q1, q2);
  float own = svo_voxel_spread(m.lo_cell);
  if (m.blend > 0.0f) {
    SvoNormalChange gh = svo_normal_change(m.hi_cell, m.p, q1, q2);
    g.d1 = mix(g.d1, gh.d1, m.blend);
    g.d2 = mix(g.d2, gh.d2, m.blend);
    own = mix(own, svo_voxel_spread(m.hi_cell), m.blend);
  }
  // Positional variance along each stretched axis beyond the voxels' own,
  // per unit of |q|^2 (the derivatives are per unit of q); the covariance
  // of the two shrinks with them.
  vec3 c = m.radius * m.radius * spread;
  float e1 = max(c.x * dot(q1, q1) - own, 0.0f) / max(dot(q1, q1), 1.0e-30f);
  float e2 = max(c.y * dot(q2, q2) - own, 0.0f) / max(dot(q2, q2), 1.0e-30f);
  float e12 = c.x > 0.0f && c.y > 0.0f ? c.z * sqrt(e1 * e2 / (c.x * c.y)) : 0.0f;
  SvoFrame f = svo_tangent_frame(nh);
  float inv = 1.0f / max(n_length, 0.5f);
  vec2 s1 = inv * vec2(dot(g.d1, f.t), dot(g.d1, f.b));
  vec2 s2 = inv * vec2(dot(g.d2, f.t), dot(g.d2, f.b));
  return params.material.w * (e1 * vec3(s1.x * s1.x, s1.y * s1.y, s1.x * s1.y) +
                              e2 * vec3(s2.x * s2.x, s2.y * s2.y, s2.x * s2.y) +
                              e12 * vec3(2.0f * s1.x * s2.x, 2.0f * s1.y * s2.y, s1.x * s2.y + s1.y * s2.x));
}

// A slope covariance (xx, yy, xy) along the axes turned by the angle of
// cosine ca and sine sa: the variances there, floored at 0.
SVO_FN vec2 svo_principal_variances(vec3 cov, float ca, float sa) {
  return max(vec2(ca * ca * cov.x + 2.0f * ca * sa * cov.z + sa * sa * cov.y,
                  sa * sa * cov.x - 2.0f * ca * sa * cov.z + ca * ca * cov.y),
             vec2(0.0f));
}

struct SvoShade {
  vec3 radiance;
  vec3 p;                // where the element was shaded (on its mean plane)
  vec3 abar;             // colour seen from the camera (Eq. 17 with the view alone in prefiltered mode)
  vec3 n;                // unit mean normal
  float slope_variance;  // mean of the total per-axis variances
  uint steps;            // shadow cone elements
};

// Paper Eq. 13 for the element: sum over lights of E_l abar(v, l) rho(v, l)
// (l . nbar) V(l), rho Lambertian plus a Beckmann lobe whose variance is
// sigma_n^2 + sigma_rho^2; mip and nearest use abar and sigma_rho^2 only.
// The Lambertian part's l . nbar becomes the mean cosine over the voxel's
// slopes (svo_rough_lambert): l . nbar alone is 2-3% bright on surfaces of
// slope variance 0.02 (tests/reference/detail_test.cpp).
SVO_FN SvoShade svo_shade(SvoMarch m, vec3 view, uint mode, SvoFootprintPart part) {
  vec3 dir = -view;
  vec3 footprint = vec3(0.0f);  // the footprint's half share not in m.v.cov (the specular lobe's)
  bool filtered = mode == SVO_MODE_PREFILTERED || mode == SVO_MODE_ALPHA;
  // A cone with a footprint (rays of raymarch mode have none).
  bool footprinted = filtered && m.radius > 1.0e-6f * params.domain.w;
  SvoShade s;
  s.steps = 0u;
  if (mode != SVO_MODE_NEAREST) {
    // The shading attributes where the ray through the centre of `part`
    // meets the element's mean plane. For the whole footprint that is the
    // axis, so that the elements of one cone that see the same plane shade
    // the same point: sampled at each element's centre, a narrow specular
    // lobe would change from element to element and show their boundaries
    // as bands along the surface's contours. For the part an element
    // covers first (prefiltered mode), the elements of a grazing cone,
    // each of which covers a band of the footprint, shade their own bands:
    // together they integrate the footprint where a tilted surface spans
    // several elements.
    vec3 n_centre = m.v.n;
    float nl0 = length(m.v.n);
    float reach = 2.0f * max(m.radius, 0.25f * params.material.z);
    vec3 nu = nl0 > 0.0f ? m.v.n / nl0 : vec3(0.0f);
    float nd = dot(nu, dir);
    SvoFrame across = svo_tangent_frame(dir);
    vec3 offset = m.radius * (part.centre.x * across.t + part.centre.y * across.b);
    float h0 = m.v.hbar + dot(nu, offset);
    float along = abs(nd) * reach > abs(h0) ? -h0 / nd : (h0 * nd > 0.0f ? -reach : reach);
    vec3 ps = m.p + offset + dir * along;
    // Prefiltered mode shades from a finer level than occlusion reads: the
    // one whose voxel is params.shading.x cone radii (default 1, where
    // occlusion reads sqrt(2)). A level's value spreads over its voxel's
    // box (variance s^2 / 12 per axis) and the trilinear tent (s^2 / 6), in
    // all s^2 / 4, the footprint disk's r^2 / 4 at s = r; at sqrt(2) r shading
    // was blurred twice over (docs/RESULTS.md, "Shading the part of the
    // footprint each element covers"). Finer still, a point sample of the
    // normal field aliases bumps smaller than the footprint into sparkle
    // (Fig. 12). Occlusion keeps the coarser level: finer, a footprint
    // whose centre lies in an empty node loses the surface beside it.
    SvoCell lo = m.lo_cell;
    SvoCell hi = m.hi_cell;
    uint depth = lo.depth;
    float blend = m.blend;
    if (mode == SVO_MODE_PREFILTERED) {
      float df = svo_level_of_voxel(params.shading.x * m.radius);
      depth = uint(floor(df));
      blend = df - float(depth);
    }
    if (!svo_cell_holds(lo, ps, depth)) lo = svo_lookup(ps, depth);
    if (blend > 0.0f && !svo_cell_holds(hi, ps, depth + 1u)) hi = svo_lookup(ps, depth + 1u);
    if (lo.brick != SVO_ABSENT && (blend == 0.0f || hi.brick != SVO_ABSENT)) {
      m.p = ps;
      m.lo_cell = lo;
      m.hi_cell = hi;
      m.blend = blend;
    }
    bool detail = svo_draws_detail(m.radius);
    uint parts = SVO_PART_SHADING | SVO_PART_NORMAL | (detail ? SVO_PART_HEIGHT : 0u);
    SvoVoxel a = svo_sample_trilinear(m.lo_cell, m.p, parts);
    if (m.blend > 0.0f) {
      a = svo_voxel_madd(svo_voxel_scaled(a, 1.0f - m.blend), svo_sample_trilinear(m.hi_cell, m.p, parts), m.blend);
    }
    // A cone's elements see different parts of a wide footprint: along a
    // grazing cone each element's bits are where the surface meets it, near
    // its own centre, not at the point the elements share. Cones of at least
    // about a finest voxel (full weight from r = 0.75 voxel) take half their
    // normal from the element's centre, where svo_step found it: relMSE of
    // the far views 0.000289 to 0.000272 (bumpy sphere) and 0.000166 to
    // 0.000134 (bunny), before G1 below; all of it, the sphere's went up to
    // 0.000362. Finer cones keep the shared point (their elements' normals
    // would band).
    if ((params.image.w & SVO_FLAG_ELEMENT_NORMALS) != 0u && filtered) {
      a.n = mix(a.n, n_centre, 0.5f * clamp(2.0f * m.radius / params.material.z - 0.5f, 0.0f, 1.0f));
    }
    // Only cones have a footprint to spread over. The specular
    // lobe takes all of the spread, the rest (Lambert, masking) half: a
    // Gaussian's tails reach farther than the bounded spread of normals
    // over a pixel, past the terminator (with one weight for every term,
    // the bumpy sphere's far view was at 0.000345 with 0.5 and 0.000442
    // with 1; docs/RESULTS.md, "The far view after four additions").
    float na = length(a.n);
    if (footprinted && params.material.w > 0.0f && na > 0.0f) {
      footprint = 0.5f * svo_footprint_slope_covariance(m, dir, a.n / na, na, part.spread);
      a.cov += footprint;
    }
    if (detail) {
      // The octaves drawn here leave the statistics: their slope and height
      // variances and their share of the colour-height covariance; the
      // colour follows the drawn height instead (detail.glsl).
      SvoDetail d = svo_trace_detail();
      vec4 g = svo_detail_displacement(d, m.p, m.radius, params.detail_colour.w);
      vec2 moved = svo_detail_moved_variance(d, m.radius, params.detail_colour.w);
      vec3 slope = vec3(params.detail_colour);
      a.n = svo_detail_tilt(a.n, vec3(g));
      a.cov -= vec3(moved.y, moved.y, 0.0f);
      a.a_s = svo_detail_fold_a_s(a.a_s, a.sh2, -moved.x, slope);
      a.abar += slope * g.w;
    }
    m.v.n = a.n;
    m.v.cov = a.cov;
    m.v.abar = a.abar;
    m.v.a_s = a.a_s;
  }
  float nl = length(m.v.n);
  vec3 n = nl > 0.0f ? m.v.n / nl : view;
  // A surface the eye sees faces it: a mean normal turned away (a thin
  // part's two faces averaged, the distance field's continuation past a
  // silhouette) is laid into the silhouette plane, where the visible
  // normals of a limb are.
  if ((params.image.w & SVO_FLAG_FRONT_FACING) != 0u && footprinted && dot(n, view) < 0.0f) {
    vec3 side = n - dot(n, view) * view;
    float sl = length(side);
    n = sl > 1.0e-6f ? side / sl : view;
  }
  SvoFrame f = svo_tangent_frame(n);
  vec3 cov = filtered ? max(m.v.cov, vec3(0.0f, 0.0f, -1.0e30f)) : vec3(0.0f);
  // Principal axes of the slope covariance.
  float angle = 0.5f * svo_atan2(2.0f * cov.z, cov.x - cov.y);
  float ca = cos(angle);
  float sa = sin(angle);
  vec3 tx = ca * f.t + sa * f.b;
  vec3 ty = ca * f.b - sa * f.t;
  vec2 sn2 = svo_principal_variances(cov, ca, sa);
  vec2 lobe = svo_principal_variances(footprint, ca, sa);
  vec2 total = svo_total_slope_variance(sn2 + lobe, vec2(params.material.x));
  vec3 vl = vec3(dot(view, tx), dot(view, ty), dot(view, n));
  float lambda_v = mode == SVO_MODE_PREFILTERED ? svo_smith_lambda_dir(vl, sn2) : 0.0f;
  vec3 a_view = mode == SVO_MODE_PREFILTERED ? svo_attribute_vl3(m.v.abar, m.v.a_s, lambda_v) : m.v.abar;
  s.radiance = vec3(params.ambient) * a_view;
  for (uint i = 0u; i < params.tree.w; ++i) {
    vec4 lv = params.light_vector[i];
    vec4 lr = params.light_radiance[i];
    vec3 l = vec3(lv);
    vec3 e = vec3(lr);
    float dist = 3.0e38f;
    if (lv.w > 0.5f) {
      vec3 to = vec3(lv) - m.p;
      dist = length(to);
      l = to / max(dist, 1.0e-30f);
      e = vec3(lr) / max(dist * dist, 1.0e-30f);
    }
    float ndl = dot(n, l);
    vec3 ll = vec3(dot(l, tx), dot(l, ty), ndl);
    // Lambert over the voxel's micro-slopes (beckmann.glsl; l.n with none):
    // past the mean plane's terminator, the facets still facing the light.
    float lambert = svo_rough_lambert(vl, ll, sn2);
    if (!(ndl > 0.0f) && !(lambert > 0.0f)) continue;
    float visible = 1.0f;
    if ((params.image.w & SVO_FLAG_SHADOWS) != 0u) {
      float spread = lv.w > 0.5f ? lr.w / max(dist, 1.0e-30f) : tan(lr.w);
      SvoVisibility vis = svo_visibility(m.p, l, dist, m.radius, spread, ndl, mode);
      visible = vis.visible;
      s.steps += vis.steps;
    }
    float lambda_l = mode == SVO_MODE_PREFILTERED ? svo_smith_lambda_dir(ll, sn2) : 0.0f;
    vec3 a = mode == SVO_MODE_PREFILTERED ? svo_attribute_vl3(m.v.abar, m.v.a_s, lambda_v + lambda_l) : m.v.abar;
    // The facets that face a grazing light shade one another: Smith's G1(l)
    // over the voxel's own slopes (not the footprint's spread: a smooth
    // convex patch shades nothing of itself). Without it the Lambert term
    // past the terminator lit the fine bumpy sphere's grazing-light region
    // 18% bright (Fig. 11, side light: relMSE 0.118 against 0.033 with it).
    float lambda_own = lambda_l;
    if (mode == SVO_MODE_PREFILTERED && lobe.x + lobe.y > 0.0f) {
      lambda_own = svo_smith_lambda_dir(ll, max(sn2 - lobe, vec2(0.0f)));
    }
    vec3 diffuse = a * (lambert / SVO_PI) / (1.0f + lambda_own);
    vec3 specular = vec3(params.material.y * svo_specular_brdf(vl, ll, total) * ndl);
    s.radiance += e * (diffuse + specular) * visible;
  }
  s.abar = a_view;
  s.p = m.p;
  s.n = n;
  s.slope_variance = 0.5f * (total.x + total.y);
  return s;
}

struct SvoPixel {
  vec4 colour;  // linear RGB; alpha: coverage
  vec4 g0;      // depth, position
  vec4 g1;      // normal, total slope variance
  vec4 g2;      // abar, coverage
  uint steps;
};

// One cone through `at` (pixel coordinates) with `k` radius per unit distance.
SVO_FN SvoPixel svo_trace_cone(vec2 at, float k, uint mode) {
  vec2 ndc = at / vec2(float(params.image.x), float(params.image.y)) * 2.0f - 1.0f;
  vec3 d = normalize(vec3(params.cam_w) + ndc.x * vec3(params.cam_u) - ndc.y * vec3(params.cam_v));
  // The focus plane is perpendicular to the view axis at the focus distance
  // (a thin lens, as Camera::focus and the reference take it): along this
  // pixel's ray it lies 1 / cos(angle to the axis) farther.
  float focus = params.lens.x / max(dot(d, vec3(params.cam_w)), 1.0e-6f);
  SvoCone cone = svo_make_cone(vec3(params.eye), d, 0.0f, k, params.cam_w.w, focus);
  // The domain grown by the widest the cone gets inside it: a defocused
  // cone whose axis misses the domain may still cover some of it.
  float reach = length(vec3(params.eye) - (vec3(params.domain) + 0.5f * params.domain.w)) + params.domain.w;
  float grow = params.cam_w.w > 0.0f ? svo_cone_radius(cone, reach) : 0.0f;
  vec3 lo = vec3(params.domain) - grow;
  float t0 = max(svo_box_entry(cone.o, cone.inv_d, lo, params.domain.w + 2.0f * grow), 0.0f);
  float t1 = svo_box_exit(cone.o, cone.inv_d, lo, params.domain.w + 2.0f * grow);
  SvoMarch m = svo_march_start(t0);
  vec3 radiance = vec3(0.0f);
  vec4 g0 = vec4(0.0f);
  vec4 g1 = vec4(0.0f);
  vec4 g2 = vec4(0.0f);
  uvec4 alpha = uvec4(0u);
  float coverage = 0.0f;
  uint steps = 0u;
  while (m.t < t1 && steps < params.tree.z) {
    steps += 1u;
    m = svo_step(m, cone, mode);
    if (!m.hit) continue;
    // Weight of this element: the bits it sets first, or its opacity in alpha mode.
    float weight;
    uvec4 fresh = m.mask & ~alpha;
    if (mode == SVO_MODE_ALPHA) {
      weight = (1.0f - coverage) * float(svo_popcount(m.mask)) / 128.0f;
    } else {
      weight = float(svo_popcount(fresh)) / 128.0f;
    }
    if (!(weight > 0.0f)) continue;
    // The element shades the part of the footprint it covers first: the
    // centre and spread of its fresh bits.
    bool parts = mode == SVO_MODE_PREFILTERED && (params.image.w & SVO_FLAG_COVERED_PART) != 0u;
    SvoShade s = svo_shade(m, -d, mode, svo_footprint_part(parts ? fresh : uvec4(0xFFFFFFFFu)));
    steps += s.steps;
    radiance += weight * s.radiance;
    g0 += weight * vec4(dot(s.p - cone.o, d), s.p);
    g1 += weight * vec4(s.n, s.slope_variance);
    g2 += weight * vec4(s.abar, 1.0f);
    coverage += weight;
    alpha = alpha | m.mask;
    if (mode == SVO_MODE_ALPHA ? coverage >= 0.999f : svo_popcount(alpha) == 128) break;
  }
  SvoPixel px;
  coverage = min(coverage, 1.0f);
  px.colour = vec4(radiance + (1.0f - coverage) * vec3(params.background), coverage);
  float inv = coverage > 0.0f ? 1.0f / g2.w : 0.0f;
  px.g0 = g0 * inv;
  px.g1 = g1 * inv;
  px.g2 = vec4(vec3(g2) * inv, coverage);
  px.steps = steps;
  return px;
}

// Point u of the unit square to the unit disk, preserving stratification
// (Shirley and Chiu's concentric map).
SVO_FN vec2 svo_concentric_disk(vec2 u) {
  vec2 o = 2.0f * u - 1.0f;
  if (o.x == 0.0f && o.y == 0.0f) return vec2(0.0f);
  float r;
  float theta;
  if (abs(o.x) > abs(o.y)) {
    r = o.x;
    theta = 0.25f * SVO_PI * (o.y / o.x);
  } else {
    r = o.y;
    theta = 0.5f * SVO_PI - 0.25f * SVO_PI * (o.x / o.y);
  }
  return r * vec2(cos(theta), sin(theta));
}

// The pixel: one cone with the pixel's footprint, or, in raymarch mode (the
// supersampling baseline), n x n stratified rays over the same footprint
// disk that march the finest level and are averaged.
SVO_FN SvoPixel svo_trace_pixel(uvec2 pixel) {
  uint mode = params.image.z;
  bool march = mode == SVO_MODE_RAYMARCH;
  uint n = march ? uint(floor(sqrt(max(params.lens.y, 1.0f)) + 0.5f)) : 1u;
  // Rows [first, first + rows) of the n x n grid of rays (lens.z, lens.w):
  // hosts split many rays over several dispatches (lavapipe ends every
  // loop of an invocation after 65,535 iterations in all).
  uint first = march ? uint(params.lens.z) : 0u;
  uint rows = march ? min(uint(params.lens.w), n - min(first, n)) : 1u;
  // One loop for both, so that the shader holds one copy of the tracer.
  float k = march ? 0.0f : params.eye.w;
  uint cone_mode = march ? SVO_MODE_PREFILTERED : mode;
  // Rays sample a footprint disk of the pixel's area, as the cone's.
  float radius = march ? 1.0f / SVO_SQRT_PI : 0.0f;
  SvoPixel sum;
  sum.colour = vec4(0.0f);
  sum.g0 = vec4(0.0f);
  sum.g1 = vec4(0.0f);
  sum.g2 = vec4(0.0f);
  sum.steps = 0u;
  for (uint j = first; j < first + rows; ++j) {
    for (uint i = 0u; i < n; ++i) {
      vec2 u = (vec2(float(i), float(j)) + 0.5f) / float(n);
      SvoPixel s = svo_trace_cone(vec2(pixel) + 0.5f + radius * svo_concentric_disk(u), k, cone_mode);
      sum.colour += s.colour;
      // G-buffer fields are coverage-weighted averages: weight by coverage again.
      sum.g0 += s.g2.w * s.g0;
      sum.g1 += s.g2.w * s.g1;
      sum.g2 += vec4(s.g2.w * vec3(s.g2), s.g2.w);
      sum.steps += s.steps;
    }
  }
  float covered = sum.g2.w;
  float inv = covered > 0.0f ? 1.0f / covered : 0.0f;
  float count = float(rows * n);
  sum.colour *= 1.0f / count;
  sum.g0 *= inv;
  sum.g1 *= inv;
  sum.g2 = vec4(vec3(sum.g2) * inv, covered / count);
  return sum;
}

#endif
