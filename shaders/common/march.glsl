// Marching a cone through the octree (tracer part 3 of 5, paper Algorithm
// 1): cones, their radius, box entry and exit, the march state and one cone
// element (svo_step): empty-space skipping, the level blend, the detail
// octaves' shell, and the element's occlusion mask.
#ifndef SVO_MARCH_GLSL
#define SVO_MARCH_GLSL
#include "detail.glsl"
#include "fetch.glsl"
#include "frame.glsl"
#include "masks.glsl"

// Where a defocused cone's march lands after entering the domain or leaving
// an empty node: on a grid along the axis that depends on t alone. Elements
// are as long as the cone is wide, many voxels for a strong blur. Landing
// where the entry or the node's exit happens to be (axis-aligned planes),
// neighbouring rows of pixels sampled the surface at different points of
// their elements, and where the landing changed (a skip that lands on
// another node) the shade stepped between rows: the streaks of a strongly
// defocused silhouette (issue 20, item 4). Steps by the distance to the
// surface land where the surface says, the same in neighbouring rows, and
// stay as they are: marching the whole cone on the grid lost the landing
// just in front of the surface (Fig. 4's silhouettes lost 0.02 coverage).
//
// The grid: point n at T(n), spaced twice the half length
//   h(t) = min(sqrt(b^2 + (c s)^2), H),  s = |t - f|,
// with c = aperture / f before the focus f and aperture / f + k (the
// pixel's cone) after it, and b = max(k f, a quarter of the finest voxel):
// below H, h is between 0.7 and 1.5 times the cone's radius (a smooth
// maximum of b and c s). H is the coarsest level's voxel / sqrt(2), also
// the longest any defocused element gets: a cone wider than that level
// resolves is sampled as often as the level's trilinear filter needs (one
// sample per element there, two voxels apart, drew the domain's cube
// through a blur a third of the object wide). The index U(t) = integral of
// dt / (2 h) is closed-form on each side of f: asinh(c s / b) / (2 c) up to
// where h reaches H, linear beyond; negative before f.
struct SvoDefocusGrid {
  float f;
  float b;
  float big_h;
  vec2 c;      // before the focus, after it
  vec2 s_cap;  // the distance from f where h reaches H, each side
  vec2 u_cap;  // |U| there
};

// asinh(x) and sinh(x) for x >= 0, without cancellation near 0.
SVO_FN float svo_asinh(float x) {
  return x < 1.0e-3f ? x * (1.0f - x * x * (1.0f / 6.0f)) : log(x + sqrt(x * x + 1.0f));
}
SVO_FN float svo_sinh(float x) {
  return x < 1.0e-3f ? x * (1.0f + x * x * (1.0f / 6.0f)) : 0.5f * (exp(x) - exp(-x));
}

// The grid of a cone of radius max(r0 + k t, aperture |t - focus| / focus),
// aperture > 0: once a cone (svo_make_cone), not at every element.
SVO_FN SvoDefocusGrid svo_defocus_grid(float r0, float k, float aperture, float focus) {
  SvoDefocusGrid g;
  g.f = focus;
  g.b = max(r0 + k * focus, 0.25f * params.material.z);
  g.big_h = params.domain.w / (float(params.tree.x) * SVO_SQRT2);
  g.c = vec2(aperture / focus, aperture / focus + k);
  for (int i = 0; i < 2; ++i) {
    g.s_cap[i] = sqrt(max(g.big_h * g.big_h - g.b * g.b, 0.0f)) / g.c[i];
    g.u_cap[i] = svo_asinh(g.c[i] * g.s_cap[i] / g.b) / (2.0f * g.c[i]);
  }
  return g;
}

SVO_FN float svo_defocus_index(SvoDefocusGrid g, float t) {
  int i = t >= g.f ? 1 : 0;
  float s = abs(t - g.f);
  float u = s <= g.s_cap[i] ? svo_asinh(g.c[i] * s / g.b) / (2.0f * g.c[i])
                            : g.u_cap[i] + (s - g.s_cap[i]) / (2.0f * g.big_h);
  return i == 1 ? u : -u;
}

SVO_FN float svo_defocus_start(SvoDefocusGrid g, float u) {
  int i = u >= 0.0f ? 1 : 0;
  float a = abs(u);
  float s = a <= g.u_cap[i] ? g.b * svo_sinh(2.0f * g.c[i] * a) / g.c[i]
                            : g.s_cap[i] + (a - g.u_cap[i]) * 2.0f * g.big_h;
  return i == 1 ? g.f + s : g.f - s;
}

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
  SvoDefocusGrid grid;  // aperture > 0: where the march lands (svo_defocus_grid)
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
  float cell;       // a defocused cone: the grid index (svo_defocus_grid) of its last element's start
  bool land;        // a defocused cone: m.t was set by the domain's entry or an empty node's exit
};

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
  if (aperture > 0.0f) {
    c.grid = svo_defocus_grid(r0, k, aperture, focus);
  } else {  // unused; set so that copies of the cone copy defined values
    c.grid.f = c.grid.b = c.grid.big_h = 0.0f;
    c.grid.c = c.grid.s_cap = c.grid.u_cap = vec2(0.0f);
  }
  return c;
}

SVO_FN float svo_cone_radius(SvoCone c, float t) {
  float r = c.r0 + c.k * t;
  if (c.aperture > 0.0f) r = max(r, c.aperture * abs(t - c.focus) / c.focus);
  return max(r, 1.0e-7f * params.domain.w);
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
SVO_FN bool svo_draws_detail(float r) {
  return (SVO_SPEC_FLAGS & SVO_FLAG_DETAIL) != 0u && params.detail_u.x > 0u && r < params.detail_colour.w;
}

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
  m.cell = -3.0e38f;
  m.land = true;
  return m;
}

// One cone element from m.t: skips a region the octree knows to be empty,
// or samples the voxel under the element and computes its coverage mask.
// Advances m in place.
SVO_FN void svo_step(SVO_INOUT(SvoMarch) m, SVO_IN(SvoCone) cone, uint mode) {
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
  // A defocused cone (a lens, aperture > 0; not while detail octaves set the
  // shortest element): elements at most H long; after a landing, the grid
  // point at or before m.t, never before an element already marched.
  if (cone.aperture > 0.0f && shortest == params.material.z) {
    if (m.land) {
      m.cell = max(floor(svo_defocus_index(cone.grid, m.t)), m.cell + 1.0f);
      m.t = svo_defocus_start(cone.grid, m.cell);
      r = svo_cone_radius(cone, m.t);
    } else {
      m.cell = max(m.cell, floor(svo_defocus_index(cone.grid, m.t)));
    }
    half_length = min(max(r, 0.25f * shortest), cone.grid.big_h);
  }
  m.land = false;
  vec3 p = cone.o + cone.d * (m.t + half_length);
  uint last = params.tree.y - 1u;
  // The level whose trilinear filter matches the footprint: interpolation
  // spreads a level's values over a tent of half-width one voxel, whose
  // variance (s^2 / 6) equals that of the footprint's width 2r (a box,
  // (2r)^2 / 12) when the voxel size is s = sqrt(2) r, half an octave finer
  // than "voxel = diameter". Measured on the bumpy sphere's far view (256^3,
  // 256x256): relMSE 0.00181 at voxel = 2r, 0.00093 at sqrt(2) r, 0.00102 at r.
  //
  // An element longer than the cone is wide (a defocused cone's grid) takes
  // the level whose voxel is (r + half length) / sqrt(2), the same for
  // half length = r: what it can reach, r + half length, stays inside the
  // 1.5 voxels that a voxel without surface in its footprint guarantees,
  // or it would draw coverage from that floor (specks beside the bunny's
  // ears).
  float df = svo_level_of_voxel((r + half_length) / SVO_SQRT2);
  // Outside the domain (a defocused cone's elements may start there): empty.
  vec3 inside = (p - vec3(params.domain)) / params.domain.w;
  if (any(lessThan(inside, vec3(0.0f))) || any(greaterThanEqual(inside, vec3(1.0f)))) {
    m.hit = false;
    m.mask = uvec4(0u);
    m.t += 2.0f * half_length;
    return;
  }
  // df >= 0: truncation is floor.
  uint lo = mode == SVO_MODE_NEAREST ? uint(df + 0.5f) : uint(df);
  float w = mode == SVO_MODE_NEAREST ? 0.0f : df - float(lo);
  if (!svo_cell_holds(m.lo_cell, p, lo)) m.lo_cell = svo_lookup(p, lo);
  m.hit = false;
  m.mask = uvec4(0u);
  if (m.lo_cell.brick == SVO_ABSENT) {
    // Empty at this level: jump to where the ray leaves the empty box.
    float exit = svo_box_exit(cone.o, cone.inv_d, m.lo_cell.lo, m.lo_cell.size);
    m.t = max(m.t + 2.0f * half_length, exit + 1.0e-5f * m.lo_cell.size);
    m.land = true;
    return;
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
    v.hbar = svo_sample_distance(m.lo_cell, p);
    v.sh2 = 0.0f;
    v.n = vec3(0.0f);
    v.cov = vec3(0.0f);
    v.abar = vec3(0.0f);
    v.a_s = vec3(0.0f);
    // A host that knows every element of the frame reads the finest level
    // (SVO_FLAG_LEVEL_BLEND) leaves the second level's code out: lavapipe
    // would run it in every SIMD group (about 8% of the bunny's and the
    // bumpy sphere's far views at 256^3).
    bool blends = (SVO_SPEC_FLAGS & SVO_FLAG_LEVEL_BLEND) != 0u;
    if (blends && w > 0.0f && lo < last) {
      if (!svo_cell_holds(m.hi_cell, p, lo + 1u)) m.hi_cell = svo_lookup(p, lo + 1u);
      if (m.hi_cell.brick != SVO_ABSENT) {
        m.blend = w;
        v.hbar = mix(v.hbar, svo_sample_distance(m.hi_cell, p), w);
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
      // The normal, and its change along the axis where curved masks need
      // it (below), from one fetch of each level's corners.
      bool curved = (params.image.w & SVO_FLAG_CURVED_MASKS) != 0u;
      bool along = curved && (mode == SVO_MODE_PREFILTERED || mode == SVO_MODE_ALPHA) && r > 1.0e-6f * params.domain.w;
      SvoNormalAlong na = svo_sample_normal_along(m.lo_cell, p, cone.d, along);
      if (blends && m.blend > 0.0f) {
        SvoNormalAlong nh = svo_sample_normal_along(m.hi_cell, p, cone.d, along);
        na.n = mix(na.n, nh.n, m.blend);
        na.dn = mix(na.dn, nh.dn, m.blend);
      }
      v.n = svo_detail_tilt(na.n, vec3(detail));
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
      if (along && nl > 0.0f) {
        kappa = max(dot(cone.d, na.dn) / max(nl, 0.5f), 0.0f) * clamp(2.0f * r / params.material.z - 0.5f, 0.0f, 1.0f);
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
}

#endif
