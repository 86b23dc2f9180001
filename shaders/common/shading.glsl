// Shading a cone element (tracer part 5 of 5, paper Eq. 13 with the Eq. 17
// attribute): the footprint's normal spread, the principal slope variances,
// and the sum over lights with Smith masking and visibility cones.
#ifndef SVO_SHADING_GLSL
#define SVO_SHADING_GLSL
#include "beckmann.glsl"
#include "smith.glsl"
#include "trig.glsl"
#include "visibility.glsl"

// The footprint's axes (the cone frame's t and b, per unit of offset
// across the cone) carried along the ray onto the plane of unit normal nh,
// stretched by 1 / |d.n|, at most 1 / 0.2.
struct SvoFootprintAxes {
  vec3 q1;
  vec3 q2;
};
SVO_FN SvoFootprintAxes svo_footprint_axes(vec3 dir, vec3 nh) {
  const float min_cosine = 0.2f;
  SvoFrame across = svo_tangent_frame(dir);
  float dn = dot(dir, nh);
  dn = dn >= 0.0f ? max(dn, min_cosine) : min(dn, -min_cosine);
  SvoFootprintAxes a;
  a.q1 = across.t - (dot(across.t, nh) / dn) * dir;
  a.q2 = across.b - (dot(across.b, nh) / dn) * dir;
  return a;
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
// the second-order theory). `jacobian`: the derivatives of the normal
// field at m.p, its levels blended as m's (svo_sample_shading).
SVO_FN vec3 svo_footprint_slope_covariance(SVO_IN(SvoMarch) m, vec3 dir, vec3 nh, float n_length, vec3 spread,
                                           mat3 jacobian) {
  SvoFootprintAxes axes = svo_footprint_axes(dir, nh);
  vec3 q1 = axes.q1;
  vec3 q2 = axes.q2;
  SvoNormalChange g;
  g.d1 = jacobian * q1;
  g.d2 = jacobian * q2;
  float own = svo_voxel_spread(m.lo_cell);
  if (m.blend > 0.0f) own = mix(own, svo_voxel_spread(m.hi_cell), m.blend);
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
  vec3 t;                // the tangent of n's frame in which slope_cov is expressed
  vec3 slope_cov;        // the slope covariance the specular lobe sees, without sigma_rho^2
  vec3 a_s;              // colour-height correlation
  uint steps;            // shadow cone elements
};

// What svo_shade_attributes leaves besides the voxel: the footprint's
// spread it added (the specular lobe takes it again) and the normal's
// derivatives.
struct SvoShadeAttributes {
  vec3 footprint;
  mat3 dn;
  float faces;  // SvoShadingSample::faces
};

// An octree whose provenance says "two_sided" draws every open surface as
// a shell 1.25 voxels thick (svo voxelize), whose normal turns around
// inside it. A cone wider than a fraction of a voxel meets elements of
// the shell's far half behind its near face, and they cover the bits the
// near face left: with their turned normals, laid into the silhouette
// plane below, they drew bands across a box's faces at the far view
// wherever the cone's radius let them in (libcgal-demo's open_cube at
// 128^3: 27.6 dB, 35.4 with the turn), dots over the lion at 512^3 (35.0
// dB, 41.6). The reference turns every back face towards the eye; so does
// this, for a mean normal facing away where the element's centre lies
// inside the shell (hbar < 0), behind its near face: the normal, its
// slopes' covariance (svo_turned_slope_covariance, as the voxelizer's
// two_sided) and the colour-height correlation. Where the cone passes
// outside (hbar >= 0), as beside a box's bottom edge, the laying below
// stays: turned there, the bottom face's normals lit the edge. Only
// normals facing clearly away (below -0.3 of their length) were turned at
// first: the lion kept its dots (39.2 dB).
SVO_FN SvoVoxel svo_turn_to_eye(SvoVoxel a, vec3 view, float hbar) {
  float nl = length(a.n);
  if (!(params.shading.y > 0.0f) || !(hbar < 0.0f) || !(nl > 0.0f) || dot(a.n, view) >= 0.0f) return a;
  a.cov = svo_turned_slope_covariance(a.n / nl, a.cov);
  a.n = -a.n;
  a.a_s = -a.a_s;
  return a;
}

// The shading attributes at ps (on the element's mean plane) into m.v, for
// the footprint part of covariance `spread` (in cone radii); n_centre: the
// element's own normal.
SVO_FN SvoShadeAttributes svo_shade_attributes(SVO_INOUT(SvoMarch) m, vec3 ps, vec3 view, uint mode, vec3 spread_part,
                                               vec3 n_centre) {
  vec3 dir = -view;
  bool filtered = mode == SVO_MODE_PREFILTERED || mode == SVO_MODE_ALPHA;
  bool footprinted = filtered && m.radius > 1.0e-6f * params.domain.w;
  SvoShadeAttributes r;
  r.footprint = vec3(0.0f);
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
  // The attributes and, for the footprint's spread below, the normal's
  // derivatives, from one fetch of each level's corners.
  bool spread = footprinted && params.material.w > 0.0f;
  vec3 toward = filtered ? view : vec3(0.0f);
  // The two levels in one loop of one or two turns rather than the second
  // under an `if`: lavapipe runs a branch's body in every SIMD group, taken
  // or not, but leaves a loop once no lane is in it, so that groups none of
  // whose lanes blends sample one level (bunny 512^3, mid view: about 8%
  // faster there, 3% natively; images bit-identical on both hosts). In
  // svo_step the same loops were 3-4% slower on both hosts, on that view
  // whose steps never blend; there the Vulkan host leaves the second level
  // out where no cone of the frame can need it (SVO_FLAG_LEVEL_BLEND).
  SvoShadingSample sampled;
  uint levels = m.blend > 0.0f ? 2u : 1u;
  for (uint l = 0u; l < levels; ++l) {
    SvoCell cell = l == 0u ? m.lo_cell : m.hi_cell;
    SvoShadingSample s = svo_sample_shading(cell, m.p, parts, spread, toward, svo_plane_sharpen(cell, m.radius));
    sampled = l == 0u ? s : svo_shading_sample_blend(sampled, s, m.blend);
  }
  SvoVoxel a = sampled.v;
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
  a = svo_turn_to_eye(a, view, m.v.hbar);
  // Only cones have a footprint to spread over. The specular
  // lobe takes all of the spread, the rest (Lambert, masking) half: a
  // Gaussian's tails reach farther than the bounded spread of normals
  // over a pixel, past the terminator (with one weight for every term,
  // the bumpy sphere's far view was at 0.000345 with 0.5 and 0.000442
  // with 1; docs/RESULTS.md, "The far view after four additions").
  float na = length(a.n);
  if (footprinted && params.material.w > 0.0f && na > 0.0f) {
    r.footprint = 0.5f * svo_footprint_slope_covariance(m, dir, a.n / na, na, spread_part, sampled.dn);
    a.cov += r.footprint;
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
  r.dn = sampled.dn;
  r.faces = sampled.faces;
  return r;
}

// The lights on m's attributes (m.v, m.p), paper Eq. 13 for the element: sum over lights of E_l abar(v, l) rho(v, l)
// (l . nbar) V(l), rho Lambertian plus a Beckmann lobe whose variance is
// sigma_n^2 + sigma_rho^2; mip and nearest use abar and sigma_rho^2 only.
// The Lambertian part's l . nbar becomes the mean cosine over the voxel's
// slopes (svo_rough_lambert): l . nbar alone is 2-3% bright on surfaces of
// slope variance 0.02 (tests/reference/detail_test.cpp).
SVO_FN SvoShade svo_shade_lights(SVO_IN(SvoMarch) m, vec3 view, uint mode, vec3 footprint) {
  bool filtered = mode == SVO_MODE_PREFILTERED || mode == SVO_MODE_ALPHA;
  bool footprinted = filtered && m.radius > 1.0e-6f * params.domain.w;
  SvoShade s;
  s.steps = 0u;
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
  vec2 specular_s2 = svo_specular_variance(total);
  float specular_lambda_v = vl.z > 0.0f ? svo_smith_lambda_dir(vl, specular_s2) : 0.0f;
  for (uint i = 0u; i < params.tree.w; ++i) {
    SvoLightSample light = svo_light_at(i, m.p);
    vec3 l = light.l;
    vec3 e = light.e;
    float ndl = dot(n, l);
    vec3 ll = vec3(dot(l, tx), dot(l, ty), ndl);
    // Lambert over the voxel's micro-slopes (beckmann.glsl; l.n with none):
    // past the mean plane's terminator, the facets still facing the light.
    float lambert = svo_rough_lambert(vl, ll, sn2);
    if (!(ndl > 0.0f) && !(lambert > 0.0f)) continue;
    float visible = 1.0f;
    if ((params.image.w & SVO_SPEC_FLAGS & SVO_FLAG_SHADOWS) != 0u) {
      SvoVisibility vis = svo_visibility(m.p, l, light.dist, m.radius, light.spread, ndl, mode);
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
    vec3 specular = vec3(params.material.y * svo_specular_brdf_view(vl, ll, specular_s2, specular_lambda_v) * ndl);
    s.radiance += e * (diffuse + specular) * visible;
  }
  s.abar = a_view;
  s.p = m.p;
  s.n = n;
  s.t = f.t;
  s.slope_cov = cov + footprint;
  s.a_s = m.v.a_s;
  return s;
}

// Where svo_shade splits a part of the footprint at a crease: two flat
// faces meet there at more than acos(SVO_CREASE_APART), 37 degrees (two of
// the corners hold one face's normal, two another's: svo_sample_shading's
// `faces`), the normal turns by more than SVO_CREASE_TURN radians over
// twice the part's standard deviation along the turn, and the footprint's
// radius is at least SVO_CREASE_FOOTPRINT finest voxels (finer, the planes'
// weights of svo_sample_shading draw the crease sharp already: split
// there, the oblique box edge of tests/reference/crease_test.cpp, 7 pixels
// a voxel, went from 6 to 9 pixels off). Its halves are shaded at
// SVO_CREASE_OFFSET standard deviations either side of its centre, wider
// than the halves' centroids (0.85): the lattice rounds a crease over a
// voxel, and the wider points reach its faces' normals. Chosen on eight
// libcgal-demo meshes at 128^3 (docs/RESULTS.md, "Creases shaded as two
// halves", with the halves averaged): a turn of 0.3 radians drew about as
// well, 0.6 left up to 4x the pixels off; an offset of 1.0 or 2.0 left
// more pixels off on 7 of 8.
SVO_CONST float SVO_CREASE_APART = 0.8f;
SVO_CONST float SVO_CREASE_TURN = 0.15f;
SVO_CONST float SVO_CREASE_OFFSET = 1.5f;
SVO_CONST float SVO_CREASE_FOOTPRINT = 0.25f;

// One cone element shaded: the attributes where it meets its mean plane
// (svo_shade_attributes), then the lights on them (svo_shade_lights); a
// part across a crease as its two halves.
SVO_FN SvoShade svo_shade(SvoMarch m, vec3 view, uint mode, SvoFootprintPart part) {
  if (mode == SVO_MODE_NEAREST) return svo_shade_lights(m, view, mode, vec3(0.0f));
  vec3 dir = -view;
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
  // A crease across the part (SVO_CREASE_APART, SVO_CREASE_TURN). One Gaussian
  // lobe about the mean normal cannot hold two faces' normals: halfway
  // between them it drew a glint brighter than either face along every
  // crease (libcgal-demo's cube, octahedron, fandisk, pinion). The part is
  // shaded as its two halves across the turn instead, each at its own
  // point with its own attributes; the G-buffer keeps the whole part's.
  // Averaged, the halves darkened the lit face beside a crease off the
  // part's centre (hedra, pyramid: -0.4 to -0.6 dB); weighted by where the
  // part's own normal lies between theirs, they gained there too.
  // Smooth surfaces keep one sample: their spread is the lobe's. Split
  // wherever the corners lay 37 degrees apart, the bumpy sphere lost 16%
  // (relMSE, 128^3, the whole domain's far view of
  // tests/reference/far_view_test.cpp), its bumps setting corners'
  // normals up to about 70 degrees apart (with 53 and 66 degrees as the
  // bound it still lost 3% and 0.6%); split where one flat face's normal
  // showed twice, the armadillo's toes' highlights dimmed (one pixel off by
  // more than 0.25 in tests/reference/specks_test.cpp). One loop shades the
  // part (j = 0) and then its halves: a second copy of the shading made
  // lavapipe's kernel 30% slower where no part was split.
  SvoShade s;
  vec3 n_part = vec3(0.0f);   // the unit normals of the part and of its halves,
  vec3 n_minus = vec3(0.0f);  // and the halves' radiance
  vec3 n_plus = vec3(0.0f);
  vec3 l_minus = vec3(0.0f);
  vec3 l_plus = vec3(0.0f);
  uint count = 1u;
  vec3 q = vec3(0.0f);
  vec3 spread = part.spread;
  for (uint j = 0u; j < count; ++j) {
    vec3 pj = j == 0u ? ps : ps + (j == 1u ? -1.0f : 1.0f) * q;
    SvoShadeAttributes at = svo_shade_attributes(m, pj, view, mode, spread, n_centre);
    if (j == 0u) {
      float na = length(m.v.n);
      if ((params.image.w & SVO_FLAG_CREASE_SPLIT) != 0u && mode == SVO_MODE_PREFILTERED &&
          params.material.w > 0.0f && m.radius > SVO_CREASE_FOOTPRINT * params.material.z && na > 0.0f &&
          at.faces < SVO_CREASE_APART) {
        SvoFootprintAxes axes = svo_footprint_axes(dir, m.v.n / na);
        vec3 q1 = axes.q1 * sqrt(max(part.spread.x, 0.0f));
        vec3 q2 = axes.q2 * sqrt(max(part.spread.y, 0.0f));
        float c1 = length(at.dn * q1);
        float c2 = length(at.dn * q2);
        if (2.0f * m.radius * max(c1, c2) / max(na, 0.5f) > SVO_CREASE_TURN) {
          bool first = c1 >= c2;
          q = SVO_CREASE_OFFSET * m.radius * (first ? q1 : q2);
          spread = first ? vec3(0.25f, 1.0f, 0.5f) * part.spread : vec3(1.0f, 0.25f, 0.5f) * part.spread;
          count = 3u;
        }
      }
    }
    SvoShade sj = svo_shade_lights(m, view, mode, at.footprint);
    vec3 nj = vec3(0.0f);
    if (count > 1u) {
      float nl = length(m.v.n);
      if (nl > 0.0f) nj = m.v.n / nl;
    }
    if (j == 0u) {
      s = sj;
      n_part = nj;
    } else {
      if (j == 1u) {
        n_minus = nj;
        l_minus = sj.radiance;
      } else {
        n_plus = nj;
        l_plus = sj.radiance;
      }
      s.steps += sj.steps;
    }
  }
  if (count > 1u) {
    // Each half by how near the part's normal lies to its own: where the
    // crease is off the part's centre, the centre lies on one face.
    vec3 turn = n_minus - n_plus;
    float w = clamp(dot(n_part - n_plus, turn) / max(dot(turn, turn), 1.0e-6f), 0.0f, 1.0f);
    s.radiance = w * l_minus + (1.0f - w) * l_plus;
  }
  return s;
}

#endif
