// Reading the octree (tracer part 1 of 5; the host contract is in
// tracer.glsl): the voxel and cell types, decoding a brick's samples,
// trilinear and nearest sampling, the normal field's change, and the
// descent from the root to the node holding a point.
#ifndef SVO_FETCH_GLSL
#define SVO_FETCH_GLSL
#include "masks.glsl"
#include "tracer_params.glsl"
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

SVO_FN float svo_voxel_size(uint depth) {
  return params.domain.w / float(params.tree.x << depth);
}

// The fractional level whose voxel is `voxel` (scene units), clamped to the
// stored levels: its floor is the level, its fraction the blend with the
// next finer one. At or below the finest level's voxel (every element of
// the native bunny 512^3 mid view, where log2f was 3-5% of the profile) the
// clamp's answer without the logarithm (log2 is exact at powers of two).
SVO_FN float svo_level_of_voxel(float voxel) {
  float x = params.domain.w / (float(params.tree.x) * voxel);
  if (x >= float(1u << (params.tree.y - 1u))) return float(params.tree.y - 1u);
  return clamp(log2(x), 0.0f, float(params.tree.y - 1u));
}

SVO_FN uint svo_byte(uint brick, uint offset) {
  return svo_brick_bytes(brick, offset) & 255u;
}

// The decodes of voxel_codec.glsl through the tables of the mask buffer
// (masks.glsl): the same values, built on the host by the same formulas.
SVO_FN float svo_table_srgb8(uint b) { return svo_decode_table(SVO_TABLE_SRGB8, b & 255u); }
SVO_FN float svo_table_u8_log_relative(uint b, float scale) {
  return scale * svo_decode_table(SVO_TABLE_U8_LOG, b & 255u);
}
SVO_FN float svo_table_u8_log_slope(uint b) { return svo_table_u8_log_relative(b, 16.0f); }
SVO_FN float svo_table_s8(uint b) { return svo_decode_table(SVO_TABLE_S8, b & 255u); }

// The channels of lattice sample s of a brick, one by one; a channel the
// file lacks reads as svo_fetch fills it.
// sigma_h^2, relative to the voxel size unless stored as f32 (svo_sample_shading scales it).
SVO_FN float svo_fetch_sh2(uint brick, uint s) {
  if (params.offsets_a.z == SVO_ABSENT) return 0.0f;
  float sh = params.encodings.x == SVO_ENC_F32 ? uintBitsToFloat(svo_brick_bytes(brick, params.offsets_a.z + s * 4u))
                                               : svo_table_u8_log_relative(svo_byte(brick, params.offsets_a.z + s), 1.0f);
  return sh * sh;
}

// The unit normal ((0, 0, 1) when the file has none).
SVO_FN vec3 svo_fetch_normal(uint brick, uint s) {
  if (params.offsets_a.y == SVO_ABSENT) return vec3(0.0f, 0.0f, 1.0f);
  return svo_decode_oct24(svo_brick_bytes(brick, params.offsets_a.y + s * 4u) & 0xFFFFFFu);
}

// The normal shading reads, where the file stores one apart from n (the
// face's normal on an open edge's cap, whose n is the distance's gradient
// that the masks read); n elsewhere.
SVO_FN vec3 svo_fetch_shading_normal(uint brick, uint s, vec3 n) {
  if ((SVO_SPEC_FLAGS & SVO_FLAG_SHADING_NORMAL) == 0u || params.offsets_c.x == SVO_ABSENT) return n;
  return svo_decode_oct24(svo_brick_bytes(brick, params.offsets_c.x + s * 4u) & 0xFFFFFFu);
}

// The slope covariance (xx, yy, xy).
SVO_FN vec3 svo_fetch_cov(uint brick, uint s) {
  if (params.offsets_b.x != SVO_ABSENT) {
    uint b = svo_brick_bytes(brick, params.offsets_b.x + s * 4u);
    float sx = svo_table_u8_log_slope(b & 255u);
    float sy = svo_table_u8_log_slope((b >> 8u) & 255u);
    float rho = svo_table_s8((b >> 16u) & 255u);
    return vec3(sx * sx, sy * sy, rho * sx * sy);
  }
  if (params.offsets_a.w != SVO_ABSENT) {
    float sd = params.encodings.y == SVO_ENC_F32
                   ? uintBitsToFloat(svo_brick_bytes(brick, params.offsets_a.w + s * 4u))
                   : svo_table_u8_log_slope(svo_byte(brick, params.offsets_a.w + s));
    return vec3(sd * sd, sd * sd, 0.0f);
  }
  return vec3(0.0f);
}

// The mean colour, linear (params.constant_colour when the file has none).
SVO_FN vec3 svo_fetch_abar(uint brick, uint s) {
  if (params.offsets_b.y == SVO_ABSENT) return vec3(params.constant_colour);
  uint b = svo_brick_bytes(brick, params.offsets_b.y + s * 4u);
  return vec3(svo_table_srgb8(b & 255u), svo_table_srgb8((b >> 8u) & 255u), svo_table_srgb8((b >> 16u) & 255u));
}

// The colour-height correlation.
SVO_FN vec3 svo_fetch_a_s(uint brick, uint s) {
  if (params.offsets_b.z == SVO_ABSENT) return vec3(0.0f);
  uint b = svo_brick_bytes(brick, params.offsets_b.z + s * 4u);
  return vec3(svo_table_s8(b & 255u), svo_table_s8((b >> 8u) & 255u), svo_table_s8((b >> 16u) & 255u));
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
  if ((parts & SVO_PART_HEIGHT) != 0u) v.sh2 = svo_fetch_sh2(brick, s);
  if ((parts & SVO_PART_NORMAL) == 0u) return v;
  v.n = svo_fetch_normal(brick, s);
  if ((parts & SVO_PART_SHADING) == 0u) return v;
  v.cov = svo_fetch_cov(brick, s);
  v.abar = svo_fetch_abar(brick, s);
  v.a_s = svo_fetch_a_s(brick, s);
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

// The eight lattice samples around p in the brick of `cell`: corner k
// (bit 0: +x, bit 1: +y, bit 2: +z) is sample `first` + svo_corner_offset(k),
// with trilinear weight svo_corner_weight(f, k).
struct SvoCorners {
  uint first;  // sample index of corner 0
  vec3 f;      // p's fractions from corner 0 towards corner 7, in [0, 1]
};
SVO_FN SvoCorners svo_corners(SvoCell cell, vec3 p) {
  vec3 c = svo_local(cell, p);
  uvec3 i0 = min(uvec3(c), uvec3(params.tree.x - 1u));  // c >= 0: truncation is floor
  SvoCorners k;
  k.f = c - vec3(i0);
  k.first = svo_sample_index(i0);
  return k;
}

SVO_FN uint svo_corner_offset(uint k) {
  uint S = params.tree.x + 1u;
  return (k & 1u) + ((k >> 1u) & 1u) * S + (k >> 2u) * S * S;
}

// The weight of corner k in the trilinear interpolation: the product of
// (1 - f) or f per axis.
SVO_FN float svo_corner_weight(vec3 f, uint k) {
  float wx = (k & 1u) != 0u ? f.x : 1.0f - f.x;
  float wy = (k & 2u) != 0u ? f.y : 1.0f - f.y;
  float wz = (k & 4u) != 0u ? f.z : 1.0f - f.z;
  return wx * wy * wz;
}

// The distance hbar alone, interpolated as svo_sample_shading interpolates
// it (same weights, same order of the sum: the same value).
SVO_FN float svo_sample_distance(SvoCell cell, vec3 p) {
  SvoCorners c = svo_corners(cell, p);
  uint at = params.offsets_a.x + c.first * 4u;
  float r = svo_corner_weight(c.f, 0u) * uintBitsToFloat(svo_brick_bytes(cell.brick, at));
  for (uint k = 1u; k < 8u; ++k) {
    r += svo_corner_weight(c.f, k) * uintBitsToFloat(svo_brick_bytes(cell.brick, at + 4u * svo_corner_offset(k)));
  }
  return r;
}

// The interpolated normal at p and, when `along` is set, its derivative
// along the world direction q, from one fetch of the eight corners: the
// normal of svo_sample_shading with `toward` zero (same terms, same order)
// above the finest level, and its dn * q up to rounding (here summed per
// corner). At the finest level the shading also weighs the corners by
// svo_plane_weight; this normal, which the masks' coverage reads, does not.
struct SvoNormalAlong {
  vec3 n;
  vec3 dn;  // zero unless `along`
};
SVO_FN SvoNormalAlong svo_sample_normal_along(SvoCell cell, vec3 p, vec3 q, bool along) {
  SvoCorners c = svo_corners(cell, p);
  float inv_voxel = float(params.tree.x) / cell.size;
  SvoNormalAlong r;
  r.n = vec3(0.0f);
  r.dn = vec3(0.0f);
  for (uint k = 0u; k < 8u; ++k) {
    vec3 o = vec3(float(k & 1u), float((k >> 1u) & 1u), float(k >> 2u));
    vec3 w = mix(vec3(1.0f) - c.f, c.f, o);
    vec3 n = svo_fetch_normal(cell.brick, c.first + svo_corner_offset(k));
    r.n = k == 0u ? w.x * w.y * w.z * n : r.n + w.x * w.y * w.z * n;
    if (along) {
      vec3 dw = mix(vec3(-1.0f), vec3(1.0f), o);
      vec3 grad = inv_voxel * vec3(dw.x * w.y * w.z, w.x * dw.y * w.z, w.x * w.y * dw.z);
      r.dn += dot(grad, q) * n;
    }
  }
  return r;
}

// The trilinear interpolation of the brick's lattice at p (the fields in
// `parts`) and, when `jacobian` is set, the derivatives of the interpolated
// normal: the derivatives of the interpolation weights applied to the
// eight corners' unit normals. One fetch of each corner serves both.
struct SvoShadingSample {
  SvoVoxel v;
  mat3 dn;  // column a: the normal's change along world axis a, per scene unit; zero unless `jacobian`
  float faces;  // the least cosine between two normals each held by two corners (flat faces'); 1 with fewer than two
};
// With `toward` (unit, towards the eye; zero: off), the shading fields
// (normal, slope covariance, colours) leave out the corners whose normal
// faces clearly away from the eye, by a weight from 1 at n . toward = -0.1
// to 0 at -0.5, and are renormalised; the distance and height are not.
// Those corners hold the far face of a wall about a voxel thick (both faces
// on the lattice, no point inside): summed with the near face's, the normal
// shrank to 0.35-0.42 of its length and tilted, a lattice of dots over the
// face (libcgal-demo's boeing, docs/RESULTS.md "Walls one voxel thick").
// Only corners opposed to the most eye-facing corner's normal (n . front
// below -0.3, fully from -0.7) are left out: those of a convex edge's far
// face (at 90 degrees to the near one) stay, as they were; left out, the
// rims of boxes' silhouettes came out bright (libcgal-demo's corner -1.6 dB).
SVO_FN float svo_facing_weight(vec3 n, vec3 toward, vec3 front) {
  float away = 1.0f - clamp((dot(n, toward) + 0.5f) * 2.5f, 0.0f, 1.0f);
  float opposed = clamp((-dot(n, front) - 0.3f) * 2.5f, 0.0f, 1.0f);
  return 1.0f - away * opposed;
}

// At the finest level, where each lattice sample's distance and normal are
// the plane of the surface nearest to it, a corner's weight in the shading
// fields is scaled by how well its plane passes through the surface at p:
// exp(-(e / 0.25 voxel)^2), e the gap between the corner's plane,
// hbar_k + n_k . (p - x_k), and the interpolated distance at p. Beside a
// crease the corners across it hold the other face's plane, which misses p
// by its distance from the crease: left in by their trilinear weight alone,
// they drew the crease as a sawtooth whose teeth follow the lattice
// (libcgal-demo's fandisk at 256^3, docs/RESULTS.md "Creases"). On a smooth
// surface of radius R voxels every corner's gap is under 1.5 / R voxels.
// At least 1e-3, so that where no corner's plane fits (p off the surface)
// the weights fall back to the trilinear ones rather than to none.
// `sharpen` in [0, 1] blends it in: a footprint as wide as the voxel
// averages its normals, which is what the trilinear weights give; a point
// sample would take the tip of a thin feature's normal alone (the
// armadillo's claws, over-bright at its far view).
SVO_CONST float SVO_PLANE_GAP = 0.25f;
SVO_FN float svo_plane_weight(float sharpen, float hk, vec3 n, vec3 fo, float hp, float inv_voxel) {
  if (sharpen <= 0.0f) return 1.0f;
  float e = ((hk - hp) * inv_voxel + dot(n, fo)) * (1.0f / SVO_PLANE_GAP);
  // exp(-7) < 1e-3, the floor.
  return mix(1.0f, max(exp(-min(e * e, 7.0f)), 1.0e-3f), sharpen);
}

// How much of svo_plane_weight a footprint of radius r takes at the level
// of `cell`: all of it up to a quarter of a finest voxel, none from three
// quarters; none above the finest level, whose voxels hold filtered
// statistics.
SVO_FN float svo_plane_sharpen(SvoCell cell, float r) {
  if (cell.depth + 1u < params.tree.y) return 0.0f;
  return 1.0f - clamp(2.0f * r / params.material.z - 0.5f, 0.0f, 1.0f);
}

SVO_FN SvoShadingSample svo_sample_shading(SvoCell cell, vec3 p, uint parts, bool jacobian, vec3 toward,
                                           float sharpen) {
  SvoCorners c = svo_corners(cell, p);
  float inv_voxel = float(params.tree.x) / cell.size;
  bool distance = (parts & SVO_PART_DISTANCE) != 0u;
  bool height = (parts & SVO_PART_HEIGHT) != 0u;
  bool normal = (parts & SVO_PART_NORMAL) != 0u;
  bool shading = normal && (parts & SVO_PART_SHADING) != 0u;
  SvoShadingSample r;
  r.v.hbar = 0.0f;
  r.v.sh2 = 0.0f;
  r.v.n = vec3(0.0f);
  r.v.cov = vec3(0.0f);
  r.v.abar = vec3(0.0f);
  r.v.a_s = vec3(0.0f);
  r.dn = mat3(0.0f);
  float kept = 0.0f;  // the shading fields' weight
  // The normal facing the eye most of the corners' (svo_facing_weight). The
  // loop below fetches the normals again: kept in an array (which the
  // dialect rules out), they made lavapipe's whole trace kernel 2.1x slower
  // (bumpy sphere 256^3, mid view, 512^2: 1842 against 871 ms), since it
  // holds a private array in memory; natively the two cost the same.
  // The same loop finds how far the corners' normals turn from corner 0's:
  // where they all agree within about 5 degrees the planes' weights
  // (svo_plane_weight) change little and are not computed (natively a few
  // per cent of the bunny's mid view at 512^3; docs/RESULTS.md "Creases").
  // With the planes' weights asked for, it also checks that the corners'
  // planes fit together: corners whose normals agree (within about 8
  // degrees) should hold one plane. Where they lie apart the weights pick
  // among planes the lattice placed, and are faded out from a quarter of a
  // voxel apart (`apart`, against corner 0's plane and one other) to a
  // half. Measured at libcgal-demo's turbine at 128^3: its ring steps by
  // 0.73 voxel between two faces that both face along its axis, and the
  // weights drew it as a row of teeth (1.5 dB lost); fandisk's far edges
  // too (tests/reference/crease_test.cpp, docs/RESULTS.md "Creases").
  vec3 front = vec3(0.0f);
  float agree = 1.0f;
  // Flat faces among the corners: a normal two corners hold (`face`, the
  // first such), and the least cosine between two of them (`faces`).
  vec3 face = vec3(0.0f);
  float faces = 1.0f;
  float apart = 0.0f;
  float hp = 0.0f;  // the interpolated distance at p (summed where sharpen > 0: the planes' weights read it)
  if (normal) {
    float best = -2.0f;
    vec3 n0 = vec3(0.0f);
    vec3 n1 = vec3(0.0f);
    vec3 previous = vec3(0.0f);
    vec3 other = vec3(0.0f);  // the first normal that is not corner 0's
    float d0 = 0.0f;
    float d1 = 0.0f;
    for (uint k = 0u; k < 8u; ++k) {
      uint s = c.first + svo_corner_offset(k);
      vec3 n = svo_fetch_normal(cell.brick, s);
      if (k == 0u) n0 = n;
      agree = min(agree, dot(n, n0));
      if (k > 0u) {
        float same = max(max(dot(n, previous), dot(n, n0)), dot(n, other));
        if (same > 0.99999f) {
          if (dot(face, face) == 0.0f) face = n;
          faces = min(faces, dot(n, face));
        }
        if (dot(other, other) == 0.0f && dot(n, n0) <= 0.99999f) other = n;
      }
      previous = n;
      float f = dot(n, toward);
      if (f > best) {
        best = f;
        front = n;
      }
      if (sharpen > 0.0f) {
        // The corner's plane at the cell's centre, in voxels.
        vec3 o = vec3(float(k & 1u), float((k >> 1u) & 1u), float(k >> 2u));
        float hk = uintBitsToFloat(svo_brick_bytes(cell.brick, params.offsets_a.x + s * 4u));
        // The interpolated distance at p as svo_sample_distance sums it
        // (same weights, same order): one fetch of the corners' distances
        // fewer, which lavapipe ran for every lane of a group where one
        // needed it.
        hp = k == 0u ? svo_corner_weight(c.f, k) * hk : hp + svo_corner_weight(c.f, k) * hk;
        float d = hk * inv_voxel + dot(n, vec3(0.5f) - o);
        if (k == 0u) {
          d0 = d;
        } else if (dot(n, n0) > 0.99f) {
          apart = max(apart, abs(d - d0));
        } else if (dot(n1, n1) == 0.0f) {
          n1 = n;
          d1 = d;
        } else if (dot(n, n1) > 0.99f) {
          apart = max(apart, abs(d - d1));
        }
      }
    }
  }
  sharpen *= 1.0f - clamp(apart / SVO_PLANE_GAP - 1.0f, 0.0f, 1.0f);
  r.faces = faces;
  bool finest = sharpen > 0.0f && normal && agree < 0.996f;
  // Each field is the sum of its corners' terms in the order of k (the
  // first term alone, not added to zero: the sign of a zero is kept).
  for (uint k = 0u; k < 8u; ++k) {
    uint s = c.first + svo_corner_offset(k);
    vec3 o = vec3(float(k & 1u), float((k >> 1u) & 1u), float(k >> 2u));
    vec3 w = mix(vec3(1.0f) - c.f, c.f, o);
    float wk = w.x * w.y * w.z;
    bool first = k == 0u;
    float hk = 0.0f;
    if (distance || finest) hk = uintBitsToFloat(svo_brick_bytes(cell.brick, params.offsets_a.x + s * 4u));
    if (distance) r.v.hbar = first ? wk * hk : r.v.hbar + wk * hk;
    if (height) {
      float x = svo_fetch_sh2(cell.brick, s);
      r.v.sh2 = first ? wk * x : r.v.sh2 + wk * x;
    }
    if (!normal) continue;
    vec3 n = svo_fetch_normal(cell.brick, s);
    vec3 ns = svo_fetch_shading_normal(cell.brick, s, n);
    float facing = svo_facing_weight(ns, toward, front) *
                   svo_plane_weight(finest ? sharpen : 0.0f, hk, n, c.f - o, hp, inv_voxel);
    wk *= facing;
    kept += wk;
    r.v.n = first ? wk * ns : r.v.n + wk * ns;
    if (shading) {
      vec3 cov = svo_fetch_cov(cell.brick, s);
      vec3 abar = svo_fetch_abar(cell.brick, s);
      vec3 a_s = svo_fetch_a_s(cell.brick, s);
      r.v.cov = first ? wk * cov : r.v.cov + wk * cov;
      r.v.abar = first ? wk * abar : r.v.abar + wk * abar;
      r.v.a_s = first ? wk * a_s : r.v.a_s + wk * a_s;
    }
    if (jacobian) {
      vec3 dw = mix(vec3(-1.0f), vec3(1.0f), o);
      vec3 grad = facing * inv_voxel * vec3(dw.x * w.y * w.z, w.x * dw.y * w.z, w.x * w.y * dw.z);
      r.dn[0] += grad.x * ns;
      r.dn[1] += grad.y * ns;
      r.dn[2] += grad.z * ns;
    }
  }
  // Renormalised over the corners kept; all of them facing away: as they are.
  if (normal && kept > 0.0f && kept < 0.999999f) {
    float inv = 1.0f / kept;
    r.v.n *= inv;
    r.v.cov *= inv;
    r.v.abar *= inv;
    r.v.a_s *= inv;
    r.dn[0] *= inv;
    r.dn[1] *= inv;
    r.dn[2] *= inv;
  }
  if (params.encodings.x != SVO_ENC_F32) {
    float voxel = cell.size / float(params.tree.x);
    r.v.sh2 *= voxel * voxel;
  }
  return r;
}

// Two levels' samples blended: (1 - w) a + w b.
SVO_FN SvoShadingSample svo_shading_sample_blend(SvoShadingSample a, SvoShadingSample b, float w) {
  SvoShadingSample r;
  r.v = svo_voxel_madd(svo_voxel_scaled(a.v, 1.0f - w), b.v, w);
  r.dn = mat3(mix(a.dn[0], b.dn[0], w), mix(a.dn[1], b.dn[1], w), mix(a.dn[2], b.dn[2], w));
  r.faces = min(a.faces, b.faces);
  return r;
}

// How the interpolated normal changes along world directions q1 and q2.
struct SvoNormalChange {
  vec3 d1;
  vec3 d2;
};

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

// The materials a surface point shows to a footprint of radius `radius`:
// at the level the prefiltered shading reads for that footprint (the
// finest stored brick holding p at or above it), the eight lattice corners
// around p vote with their trilinear weight times their dominant
// material's share; the two heaviest materials and the first's share of
// both. Material 0 alone where the file has no material channel.
struct SvoMaterialMix {
  uint a;
  uint b;
  float mix;  // a's share of a and b, in [0, 1]
};
SVO_FN SvoMaterialMix svo_material_mix(vec3 p, float radius) {
  SvoMaterialMix r;
  r.a = 0u;
  r.b = 0u;
  r.mix = 1.0f;
  if (params.offsets_b.w == SVO_ABSENT) return r;
  uint last = max(params.encodings.z, 1u) - 1u;
  uint depth = uint(svo_level_of_voxel(params.shading.x * radius) + 0.5f);
  SvoCell cell = svo_lookup(p, depth);
  while (cell.brick == SVO_ABSENT && depth > 0u) {
    depth -= 1u;
    cell = svo_lookup(p, depth);
  }
  if (cell.brick == SVO_ABSENT) return r;
  SvoCorners c = svo_corners(cell, p);
  // The corners' materials, a byte each (k < 4 in lo, the rest in hi), and
  // their votes (the dialect has no arrays: prelude.glsl).
  uint index_lo = 0u;
  uint index_hi = 0u;
  vec4 weight_lo = vec4(0.0f);
  vec4 weight_hi = vec4(0.0f);
  for (uint k = 0u; k < 8u; ++k) {
    uint bytes = svo_brick_bytes(cell.brick, params.offsets_b.w + (c.first + svo_corner_offset(k)) * 2u);
    uint index = min(bytes & 255u, last) << (8u * (k & 3u));
    float weight = svo_corner_weight(c.f, k) * float((bytes >> 8u) & 255u) / 255.0f;
    if (k < 4u) {
      index_lo |= index;
      weight_lo[k] = weight;
    } else {
      index_hi |= index;
      weight_hi[k - 4u] = weight;
    }
  }
  // Each corner's material with the votes of every corner showing it.
  float best = -1.0f;
  float second = 0.0f;
  for (uint k = 0u; k < 8u; ++k) {
    uint index_k = ((k < 4u ? index_lo : index_hi) >> (8u * (k & 3u))) & 255u;
    float total = 0.0f;
    for (uint j = 0u; j < 8u; ++j) {
      uint index_j = ((j < 4u ? index_lo : index_hi) >> (8u * (j & 3u))) & 255u;
      total += index_j == index_k ? (j < 4u ? weight_lo[j] : weight_hi[j - 4u]) : 0.0f;
    }
    if (index_k == r.a && best >= 0.0f) continue;
    if (total > best) {
      if (best >= 0.0f) {
        r.b = r.a;
        second = best;
      }
      r.a = index_k;
      best = total;
    } else if (total > second && (second <= 0.0f || index_k != r.b)) {
      r.b = index_k;
      second = total;
    }
  }
  r.mix = best + second > 0.0f ? best / (best + second) : 1.0f;
  if (second <= 0.0f) r.b = r.a;
  return r;
}

SVO_FN bool svo_cell_holds(SvoCell c, vec3 p, uint depth) {
  return c.depth == depth && all(greaterThanEqual(p, c.lo)) && all(lessThan(p, c.lo + c.size));
}

#endif
