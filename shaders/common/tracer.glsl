// The cone tracer, Heitz & Neyret Algorithm 1 (DESIGN section 8), in the
// shared dialect: the trace kernels (shaders/render/trace_main.glsl) and the
// native host (render/src/native_renderer.cpp) include this same file. Its
// parts, each usable alone by a pass: fetch.glsl (reading the octree),
// masks.glsl, march.glsl (one cone element), visibility.glsl (shadow cones),
// shading.glsl (Eq. 13); the pixel is here.
//
// Before including it, the host declares:
//   SvoTraceParams params;                      the settings of this trace (tracer_params.glsl)
//   uvec2 svo_node(uint index);                 (children, brick) of a node, SVO_ABSENT for none
//   uint svo_brick_bytes(uint brick, uint offset);  the word holding byte `offset` of a brick, shifted
//                                               right so that this byte is the lowest (never straddles)
//   uvec4 svo_mask(uint cell);                  the mask table, theta-major, SVO_MASK_BINS^2 cells
//   uint SVO_SPEC_MODE, SVO_SPEC_FLAGS;         constants: what this kernel traces (tracer_params.glsl)
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
#include "gbuffer.glsl"
#include "shading.glsl"

struct SvoPixel {
  vec4 colour;      // linear RGB, the background's share included; alpha: coverage
  vec4 background;  // the background's share of colour: rgb, and 1 - coverage
  SvoGBuffer g;     // filled when params.image.w has SVO_FLAG_GBUFFER (gbuffer.glsl)
  uint steps;
};

// The unit direction of the camera ray through `at` (pixel coordinates).
SVO_FN vec3 svo_pixel_direction(vec2 at) {
  vec2 ndc = at / vec2(float(params.image.x), float(params.image.y)) * 2.0f - 1.0f;
  return normalize(vec3(params.cam_w) + ndc.x * vec3(params.cam_u) - ndc.y * vec3(params.cam_v));
}

// A pixel no element covers: the background alone.
SVO_FN SvoPixel svo_background_pixel() {
  SvoPixel px;
  px.background = vec4(vec3(params.background), 1.0f);
  px.colour = vec4(vec3(params.background), 0.0f);
  px.g = svo_gbuffer_empty();
  px.steps = 0u;
  return px;
}

// One cone through `at` (pixel coordinates) with `k` radius per unit
// distance. With a lens, the cone of the part of the lens centred at `lens`
// (in lens radii, in the unit disk) whose radius is `part` lens radii: the
// whole lens is lens 0, part 1.
SVO_FN SvoPixel svo_trace_cone(vec2 at, float k, uint mode, vec2 lens, float part) {
  vec3 d = svo_pixel_direction(at);
  vec3 eye = vec3(params.eye);
  // The focus plane is perpendicular to the view axis at the focus distance
  // (a thin lens, as Camera::focus and the reference take it): along this
  // pixel's ray it lies 1 / cos(angle to the axis) farther.
  float focus = params.lens.x / max(dot(d, vec3(params.cam_w)), 1.0e-6f);
  vec3 o = eye;
  vec3 axis = d;
  if (lens.x != 0.0f || lens.y != 0.0f) {
    // From that point of the lens to where the pixel's ray is in focus.
    o = eye + params.cam_w.w * (lens.x * normalize(vec3(params.cam_u)) + lens.y * normalize(vec3(params.cam_v)));
    vec3 to_focus = eye + focus * d - o;
    focus = length(to_focus);
    axis = to_focus / focus;
  }
  SvoCone cone = svo_make_cone(o, axis, 0.0f, k, part * params.cam_w.w, focus);
  // The domain grown by the widest the cone gets inside it: a defocused
  // cone whose axis misses the domain may still cover some of it.
  float reach = length(o - (vec3(params.domain) + 0.5f * params.domain.w)) + params.domain.w;
  float grow = params.cam_w.w > 0.0f ? svo_cone_radius(cone, reach) : 0.0f;
  vec3 lo = vec3(params.domain) - grow;
  float t0 = max(svo_box_entry(cone.o, cone.inv_d, lo, params.domain.w + 2.0f * grow), 0.0f);
  float t1 = svo_box_exit(cone.o, cone.inv_d, lo, params.domain.w + 2.0f * grow);
  SvoMarch m = svo_march_start(t0);
  vec3 radiance = vec3(0.0f);
  bool gbuffer = (params.image.w & SVO_SPEC_FLAGS & SVO_FLAG_GBUFFER) != 0u;
  SvoGBuffer g = svo_gbuffer_empty();
  uvec4 alpha = uvec4(0u);
  float coverage = 0.0f;
  uint steps = 0u;
  // The march stops at each element that covers part of the footprint, to
  // shade it outside the march's own loop: a SIMD group (lavapipe) then
  // marches until each of its lanes has found its next element and shades
  // them together, where shading inside the loop ran it in every step that
  // any lane needed it.
  bool open = true;
  while (open) {
    float weight = 0.0f;
    uvec4 fresh = uvec4(0u);
    while (m.t < t1 && steps < params.tree.z) {
      steps += 1u;
      svo_step(m, cone, mode);
      if (!m.hit) continue;
      // Weight of this element: the bits it sets first, or its opacity in alpha mode.
      fresh = m.mask & ~alpha;
      if (mode == SVO_MODE_ALPHA) {
        weight = (1.0f - coverage) * float(svo_popcount(m.mask)) / 128.0f;
      } else {
        weight = float(svo_popcount(fresh)) / 128.0f;
      }
      if (weight > 0.0f) break;
    }
    if (!(weight > 0.0f)) break;
    // The element shades the part of the footprint it covers first: the
    // centre and spread of its fresh bits.
    bool parts = mode == SVO_MODE_PREFILTERED && (params.image.w & SVO_FLAG_COVERED_PART) != 0u;
    SvoShade s = svo_shade(m, -axis, mode, svo_footprint_part(parts ? fresh : uvec4(0xFFFFFFFFu)));
    steps += s.steps;
    radiance += weight * s.radiance;
    if (gbuffer) {
      SvoGBuffer e;
      e.depth = dot(s.p - eye, d);
      e.position = s.p;
      e.normal = s.n;
      e.coverage = 1.0f;
      e.tangent = s.t;
      e.sigma_rho2 = params.material.x;
      e.slope_cov = s.slope_cov;
      e.abar = s.abar;
      e.a_s = s.a_s;
      g = svo_gbuffer_madd(g, e, weight);
    }
    coverage += weight;
    alpha = alpha | m.mask;
    open = mode == SVO_MODE_ALPHA ? coverage < 0.999f : svo_popcount(alpha) != 128;
  }
  SvoPixel px;
  coverage = min(coverage, 1.0f);
  px.background = vec4((1.0f - coverage) * vec3(params.background), 1.0f - coverage);
  px.colour = vec4(radiance + vec3(px.background), coverage);
  px.g = svo_gbuffer_finish(g, coverage);
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

// How many parts a side (n x n in all) the lens is split into, the same for
// every pixel of the frame: params.lens.y, set by the host
// (render::lens_parts, render/src/trace_setup.cpp), 1 without a lens.
// - One cone wider than the coarsest voxel / sqrt(2) (the widest element
//   svo_step reads without reaching past the 1.5 voxels that a lattice
//   point without surface guarantees) read that floor as surface: a
//   strongly defocused object was drawn as the outline of the coarse
//   bricks, boxes with hard edges (the bunny at --dof 0.3,4.8: relMSE 0.160
//   with one cone, 0.0138 with 4 x 4).
// - Narrower, one cone's mean planes still drew thin parts (a trunk, the
//   dragon's whiskers) as wide as the blur and patched with the coarse
//   voxels' planes: at the issue's strong blur (a lens of 0.041 eye
//   distances, 256^3) 2 x 2 parts gave relMSE 3-14x lower than one cone
//   for 2.9-3.9x the time, and no pixel off by 0.25 left on three of four
//   meshes (docs/RESULTS.md, "Lenses in parts").
SVO_FN uint svo_lens_parts() {
  return params.cam_w.w > 0.0f ? uint(max(params.lens.y, 1.0f)) : 1u;
}

// The pixel: one cone with the pixel's footprint, or, in raymarch mode (the
// supersampling baseline), n x n stratified rays over the same footprint
// disk that march the finest level and are averaged. With a lens, n x n
// cones, each from its part of the lens (svo_lens_parts; mostly one).
SVO_FN SvoPixel svo_trace_pixel(uvec2 pixel) {
  uint mode = SVO_SPEC_MODE != SVO_SPEC_ANY ? SVO_SPEC_MODE : params.image.z;
  bool march = mode == SVO_MODE_RAYMARCH;
  uint lens_parts = march ? 1u : svo_lens_parts();
  uint n = march ? uint(floor(sqrt(max(params.lens.y, 1.0f)) + 0.5f)) : lens_parts;
  // Rows [first, first + rows) of the n x n grid of rays or lens parts
  // (lens.z, lens.w): hosts split many over several dispatches (lavapipe
  // ends every loop of an invocation after 65,535 iterations in all).
  bool split = march || lens_parts > 1u;
  uint first = split ? uint(params.lens.z) : 0u;
  uint rows = split ? min(uint(params.lens.w), n - min(first, n)) : 1u;
  // One loop for both, so that the shader holds one copy of the tracer.
  float k = march ? 0.0f : params.eye.w;
  uint cone_mode = march ? SVO_MODE_PREFILTERED : mode;
  // Rays sample a footprint disk of the pixel's area, as the cone's.
  float radius = march ? 1.0f / SVO_SQRT_PI : 0.0f;
  // A pinhole cone whose axis misses the domain meets nothing
  // (svo_trace_cone tests the same box): the background, without the
  // cone's set-up, which lavapipe would pay for in every SIMD group.
  if (!march && !(params.cam_w.w > 0.0f)) {
    vec3 d = svo_pixel_direction(vec2(pixel) + 0.5f);
    vec3 inv_d = svo_safe_inverse(d);
    float t0 = max(svo_box_entry(vec3(params.eye), inv_d, vec3(params.domain), params.domain.w), 0.0f);
    if (!(t0 < svo_box_exit(vec3(params.eye), inv_d, vec3(params.domain), params.domain.w))) {
      return svo_background_pixel();
    }
  }
  SvoPixel sum;
  sum.colour = vec4(0.0f);
  sum.background = vec4(0.0f);
  sum.g = svo_gbuffer_empty();
  sum.steps = 0u;
  float covered = 0.0f;
  for (uint j = first; j < first + rows; ++j) {
    for (uint i = 0u; i < n; ++i) {
      vec2 u = (vec2(float(i), float(j)) + 0.5f) / float(n);
      vec2 disk = svo_concentric_disk(u);
      SvoPixel s = lens_parts > 1u
                       ? svo_trace_cone(vec2(pixel) + 0.5f, k, cone_mode, disk, 1.0f / float(n))
                       : svo_trace_cone(vec2(pixel) + 0.5f + radius * disk, k, cone_mode, vec2(0.0f), 1.0f);
      sum.colour += s.colour;
      sum.background += s.background;
      // G-buffer fields are coverage-weighted averages: weight by coverage again.
      sum.g = svo_gbuffer_madd(sum.g, s.g, s.g.coverage);
      covered += s.g.coverage;
      sum.steps += s.steps;
    }
  }
  float count = float(rows * n);
  sum.colour *= 1.0f / count;
  sum.background *= 1.0f / count;
  sum.g.coverage = covered;
  sum.g = svo_gbuffer_finish(sum.g, covered / count);
  if ((params.image.w & SVO_SPEC_FLAGS & SVO_FLAG_GBUFFER) != 0u && sum.g.coverage > 0.0f) {
    SvoMaterialMix mm = svo_material_mix(sum.g.position, params.eye.w * sum.g.depth);
    sum.g.material = mm.a;
    sum.g.material2 = mm.b;
    sum.g.material_mix = mm.mix;
  }
  return sum;
}

#endif
