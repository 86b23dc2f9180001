// Light-field luminaires (Lu et al. 2015; DESIGN 10.4; render/include/svo/
// render/luminaire.h gives the model): the radiance a G-buffer point
// reflects towards the eye from the luminaires, by position-dependent
// importance sampling of each image C_m restricted to the projection of its
// basis function's support (Eq. 7-8), samples balanced over the images by
// A_m(p) from summed-area tables (Eq. 10, 12), and the estimator of Eq. 14
// with the point's BRDF (forward.glsl) and a visibility through the octree.
//
// Host contract: forward.glsl's, plus `float svo_lum_table(uint i)` reading
// the floats render::build_luminaire_tables makes. Counts and offsets are
// stored as the bits of a uint (svo_lum_uint). Layout:
//   0: the luminaire count; 1: sampler (SVO_LUM_SAMPLER_*); 2: search
//   (SVO_LUM_SEARCH_*) | depth << 8; 3: visibility | sequence << 8; 4: K, the
//   samples per pixel of each luminaire; 5: K_max (0: none); 6: seed; 7:
//   the entries of a pixel's state (below), the sum over luminaires of 2 +
//   (with cell visibility) its cells.
//   8 + 32 l: luminaire l (svo_lum_info): plane S's centre, delta, its x
//   axis, the basis spacing h, its y axis, the basis kind, its z axis (the
//   direction light leaves in), the texel area, S's extent, the image size
//   w x h, the grid W x H, the images' offset and stride, the cells'
//   offset, the total energy E (sum of luminance x texel area), the offset
//   of the CDF over images by energy (global sampling), the basis
//   support in cells n, and (28) the offset of its entries in a pixel's
//   state. All lengths in scene units.
//   Image m at offset + m stride (texel coordinates: x in [0, w], y in [0, h]):
//     the marginal CDF over columns, w + 1 floats (0 ... 1);
//     each column's CDF over rows, w x (h + 1);
//     the RGB radiance per texel, 3 w h ((y w + x) order);
//     the summed-area table S(x, y) = sum over x' < x, y' < y of luminance x
//     texel area, as hi + lo (hi a multiple of 2^-12 of the total, so that
//     sums of hi are exact in float), (w + 1)(h + 1) floats each;
//     the energy E_m, and the point where both CDFs are 1/2 (texel coords).
//   Cells at the cells' offset: (W + n - 1) x (H + n - 1) reference
//   positions on S (texel coordinates, 2 floats each): the mean of the
//   half-way points of the images whose basis overlaps the cell.
//
// The pixel's state, per luminaire at its offset: A(p), the sum of A_m over
// the images (Eq. 12); the count of images whose box is not empty; with
// cell visibility, every cell's v (section 6.2), row by row. A host makes
// each entry by svo_luminaire_state, one entry per call, and gives it back
// by `float svo_lum_state(uint pixel, uint k, SVO_IN(SvoShadingPoint) p)`
// (p: the pixel's shading point): the Vulkan host makes every entry of a
// pixel before its samples, the native one an entry when it is first read,
// from p. The cells' cones then run once per pixel, not per image or
// per batch of samples, and no invocation keeps them in an array
// (prelude.glsl's rule: lavapipe holds private arrays in memory).
#ifndef SVO_LUMINAIRE_GLSL
#define SVO_LUMINAIRE_GLSL
#include "forward.glsl"
#include "luminaire_tables.glsl"

// Sample i's uniform pair in dimension pair `dim` (Fig. 8's two sequences).
SVO_FN vec2 svo_lum_rand(uint pixel, uint i, uint dim, uint sequence, uint seed) {
  if (sequence == SVO_LUM_SEQ_HALTON) return svo_sample_2d(pixel, seed, i, dim);
  uint h = svo_pcg_hash(svo_pcg_hash(pixel * 9781u + seed) + i * 6271u + dim * 1013u);
  return vec2(svo_unit_float(h), svo_unit_float(svo_pcg_hash(h)));
}

// A world point on S from texel coordinates, and on U from U's coordinates.
SVO_FN vec3 svo_lum_on_s(SvoLumInfo f, vec2 t) {
  vec2 s = svo_lum_from_texel(f, t);
  return f.centre + s.x * f.x + s.y * f.y;
}
SVO_FN vec3 svo_lum_on_u(SvoLumInfo f, vec2 u) { return f.centre + u.x * f.x + u.y * f.y - f.delta * f.z; }

// The visibility of the luminaire's point q from the G-buffer point, by a
// cone that widens to `width` at q.
SVO_FN float svo_lum_visible(SvoShadingPoint p, vec3 q, float width) {
  vec3 d = q - p.position;
  float dist = length(d);
  if (!(dist > 0.0f)) return 1.0f;
  vec3 l = d / dist;
  return svo_visibility(p.position, l, dist, p.radius, 0.5f * width / dist, dot(p.n, l), SVO_MODE_PREFILTERED).visible;
}

// The BRDF times the cosine towards the luminaire's point q, both parts.
SVO_FN vec3 svo_lum_brdf(SvoShadingPoint p, SvoLobe lobe, vec3 q) {
  SvoForwardSum b = svo_forward_brdf_cos(p, lobe, normalize(q - p.position));
  return b.diffuse + b.specular;
}

// The options in the tables' header.
struct SvoLumOptions {
  uint count;
  uint sampler_kind;
  uint search;
  uint depth;
  uint visibility;
  uint sequence;
  uint k;
  uint kmax;
  uint seed;
  bool balanced;  // the restricted samplers, which balance the images by A_m (Eq. 12)
};

SVO_FN SvoLumOptions svo_lum_options() {
  SvoLumOptions o;
  o.count = svo_lum_uint(0u);
  o.sampler_kind = svo_lum_uint(1u);
  uint search = svo_lum_uint(2u);
  o.search = search & 255u;
  o.depth = search >> 8u;
  uint vis = svo_lum_uint(3u);
  o.visibility = vis & 255u;
  o.sequence = vis >> 8u;
  o.k = max(svo_lum_uint(4u), 1u);
  o.kmax = svo_lum_uint(5u);
  o.seed = svo_lum_uint(6u);
  o.balanced = o.sampler_kind == SVO_LUM_SAMPLER_RESTRICTED || o.sampler_kind == SVO_LUM_SAMPLER_BOX;
  return o;
}

// The reference position of cell (a, b) on S, as a world point.
SVO_FN vec3 svo_lum_cell_point(SvoLumInfo f, uint a, uint b) {
  uint at = f.cells + 2u * (b * (f.grid_w + f.n - 1u) + a);
  return svo_lum_on_s(f, vec2(svo_lum_table(at), svo_lum_table(at + 1u)));
}

// Where the line from the point (at `pl` in S's frame) to cell (a, b)'s
// centre on U crosses S, as a world point: the cone of --luminaire-visibility
// cells-on-u aims there, so that it follows the light that reaches this
// point through the cell, wherever on S that light passes. The paper's
// reference position (svo_lum_cell_point) is one point on S for every
// shaded point, as a shadow map needs: right where S is small beside the
// scene, but where S spans a bare LED's whole beam, the outer cells' images
// hold oblique light far out on S, and a cone to their reference position
// passes beside the occluder between the point and the die, or meets one
// that is not there.
SVO_FN vec3 svo_lum_cell_seen(SvoLumInfo f, uint a, uint b, vec3 pl) {
  vec2 u = svo_lum_basis_centre(f, 0u) - 0.5f * float(f.n) * f.spacing + (vec2(float(a), float(b)) + 0.5f) * f.spacing;
  vec2 s = vec2(pl) + (u - vec2(pl)) * (pl.z / (pl.z + f.delta));
  return f.centre + s.x * f.x + s.y * f.y;
}

// The material a sample shades: where the pixel shows two, sample i's draw.
SVO_FN SvoLobe svo_lum_lobe(SvoShadingPoint p, SvoGBuffer g, uint pixel, uint i, SvoLumOptions o) {
  bool mixed = g.material != g.material2 && g.material_mix < 1.0f;
  bool second = mixed && svo_sample_1d(pixel, o.seed, i, 7u) >= g.material_mix;
  SvoMaterial mat = svo_scene_material(second ? g.material2 : g.material);
  return svo_sample_lobe(p, mat, svo_lum_rand(pixel, i, 2u, o.sequence, o.seed));
}

// What every image's share depends on at a point: where it is in S's frame,
// whether it is on S (and where: texel coordinates), and the balance of
// Eq. 12 (A(p), and the images whose box is not empty).
struct SvoLumAt {
  vec3 pl;
  bool on_s;
  vec2 t_on_s;
  float area_total;
  uint nonempty;
};

// Image m (its tables at img) at the point, for sampling restricted to its
// box: the box (texel coordinates; on S the whole image) and what it sends
// the point, > 0 where it draws samples: A_m for the balanced samplers, 1
// where the box is not empty for uniform sampling, and on S (Eq. 9) 1
// where the image is lit at the point.
struct SvoLumReach {
  vec4 box;
  float amount;
};

SVO_FN SvoLumReach svo_lum_reach(SvoLumInfo f, uint m, uint img, SvoLumAt at, SvoLumOptions o) {
  SvoLumReach r;
  r.box = vec4(0.0f, 0.0f, float(f.w), float(f.h));
  r.amount = 0.0f;
  if (at.on_s) {
    vec3 c = svo_lum_texel_colour(f, img, at.t_on_s);
    r.amount = c.x + c.y + c.z > 0.0f ? 1.0f : 0.0f;
    return r;
  }
  r.box = svo_lum_box(f, m, at.pl);
  if (!(r.box.z > r.box.x) || !(r.box.w > r.box.y)) return r;
  r.amount = o.balanced ? svo_lum_area(f, img, r.box) : 1.0f;
  return r;
}

// Whether some image whose basis covers cell (a, b) draws samples at the
// point in svo_luminaire_shade (svo_lum_reach; global sampling may draw
// any image). A cell no image needs is never read, so its cone is not
// traced: its entry is a NaN, so that a change that reads it after all
// shows at once (the visibility tests).
SVO_FN bool svo_lum_cell_needed(SvoLumInfo f, uint a, uint b, SvoLumAt at, SvoLumOptions o) {
  if (o.sampler_kind == SVO_LUM_SAMPLER_GLOBAL) return true;
  vec2 t = at.t_on_s;
  if (at.on_s && !(t.x >= 0.0f && t.y >= 0.0f && t.x < float(f.w) && t.y < float(f.h))) return false;
  // Image (i, j)'s basis covers cells [i, i + n) x [j, j + n).
  for (uint j = b + 1u > f.n ? b + 1u - f.n : 0u; j <= min(b, f.grid_h - 1u); ++j) {
    for (uint i = a + 1u > f.n ? a + 1u - f.n : 0u; i <= min(a, f.grid_w - 1u); ++i) {
      uint m = j * f.grid_w + i;
      if (svo_lum_reach(f, m, svo_lum_image(f, m), at, o).amount > 0.0f) return true;
    }
  }
  return false;
}

// Entry k of the state of the pixel whose shading point is p (the layout
// above; svo_lum_uint(7u) entries). checked: a cell entry that no sample can
// read is a NaN, its cone not traced (a host that makes every entry first);
// otherwise the cone is traced (a host that makes an entry when a sample
// reads it).
SVO_FN float svo_lum_state_entry(SVO_IN(SvoShadingPoint) p, uint k, bool checked) {
  SvoLumOptions o = svo_lum_options();
  uint l = 0u;
  while (l + 1u < o.count && svo_lum_uint(SVO_LUM_HEADER + SVO_LUM_BLOCK * (l + 1u) + 28u) <= k) ++l;
  SvoLumInfo f = svo_lum_info(l);
  k -= f.state;
  vec3 pl = svo_lum_local(f, p.position);
  float eps = 1.0e-5f * f.delta;
  if (pl.z < -eps) return 0.0f;  // behind S
  bool on_s = pl.z <= eps;
  if (k < 2u) {
    // A(p) and the images whose box is not empty, as svo_luminaire_shade
    // balances them (Eq. 12); neither is read on S or by global sampling.
    if (on_s || o.sampler_kind == SVO_LUM_SAMPLER_GLOBAL) return 0.0f;
    float area_total = 0.0f;
    uint nonempty = 0u;
    for (uint m = 0u; m < f.grid_w * f.grid_h; ++m) {
      vec4 box = svo_lum_box(f, m, pl);
      if (box.z > box.x && box.w > box.y) ++nonempty;
      if (o.balanced && k == 0u) area_total += svo_lum_area(f, svo_lum_image(f, m), box);
    }
    return k == 0u ? area_total : float(nonempty);
  }
  // v of cell k - 2: one cone towards the cell's reference position (section
  // 6.2), or along the line to the cell on U (cells-on-u).
  uint cell_w = f.grid_w + f.n - 1u;
  uint a = (k - 2u) % cell_w;
  uint b = (k - 2u) / cell_w;
  if (checked) {
    SvoLumAt at;
    at.pl = pl;
    at.on_s = on_s;
    at.t_on_s = svo_lum_to_texel(f, vec2(pl));
    at.area_total = 0.0f;  // (not read)
    at.nonempty = 0u;
    if (!svo_lum_cell_needed(f, a, b, at, o)) return uintBitsToFloat(0x7FC00000u);
  }
  float cell_width = f.spacing * pl.z / (pl.z + f.delta);
  if (o.visibility == SVO_LUM_VIS_CELLS) {
    return svo_lum_visible(p, svo_lum_cell_point(f, a, b), max(cell_width, f.extent.x / float(f.w)));
  }
  return svo_lum_visible(p, svo_lum_cell_seen(f, a, b, pl), cell_width);
}

// Entry k of the state of the pixel whose G-buffer texel is g.
SVO_FN float svo_luminaire_state(SvoGBuffer g, uint k) {
  if (!(g.coverage > 0.0f)) return 0.0f;
  return svo_lum_state_entry(svo_shading_point(g), k, true);
}

// Image m's share of a point's samples (svo_luminaire_shade): its box
// (texel coordinates; the whole image for global sampling) and K_m(p), 0
// for an image that sends the point nothing, and for m past the last.
struct SvoLumShare {
  uint m;
  uint img;
  vec4 box;
  uint km;
};

SVO_FN SvoLumShare svo_lum_share(SvoLumInfo f, uint m, SvoLumAt at, SvoLumOptions o) {
  SvoLumShare r;
  uint count = f.grid_w * f.grid_h;
  r.m = m;
  r.img = svo_lum_image(f, min(m, count - 1u));
  r.box = vec4(0.0f, 0.0f, float(f.w), float(f.h));
  r.km = 0u;
  if (o.sampler_kind == SVO_LUM_SAMPLER_GLOBAL) {
    // The image is drawn per sample.
    if (m == 0u) r.km = o.k;
    return r;
  }
  if (m >= count) return r;
  SvoLumReach reach = svo_lum_reach(f, m, r.img, at, o);
  r.box = reach.box;
  if (!(reach.amount > 0.0f)) return r;
  if (at.on_s) {
    // Eq. 9: the same share for every image that is lit at the point.
    r.km = max((o.k + count - 1u) / count, 1u);
  } else if (o.balanced) {
    // Eq. 12, at least one sample for an image that sends light (an image
    // of no sample would drop its share: a bias).
    r.km = max(uint(reach.amount / at.area_total * float(o.k) + 0.5f), 1u);
  } else {
    r.km = max((o.k + at.nonempty - 1u) / at.nonempty, 1u);
  }
  if (o.kmax > 0u) r.km = min(r.km, o.kmax);
  return r;
}

// The radiance the G-buffer point reflects towards the eye from luminaire
// l (Eq. 14, summed over the images), with o's sampler, search, sequence
// and visibility.
// Only samples [first, first + chunk) of the point's sequence count (a host
// may split them over several calls, forward.glsl's svo_forward_texel says
// why); each is weighted as in the whole estimate. The images' samples
// follow each other in one sequence, and one loop runs over the sample
// index, so that the lanes of a SIMD group shade their samples together
// while each walks its own images (a loop over images with a loop over
// their samples inside runs every lane's samples apart).
SVO_FN vec3 svo_luminaire_shade(SvoGBuffer g, SvoShadingPoint p, uint pixel, uint l, SvoLumOptions o, uint first,
                                uint chunk) {
  if (chunk == 0u) return vec3(0.0f);
  SvoLumInfo f = svo_lum_info(l);
  SvoLumAt at;
  at.pl = svo_lum_local(f, p.position);
  float eps = 1.0e-5f * f.delta;
  if (at.pl.z < -eps) return vec3(0.0f);  // behind S: the luminaire sends nothing there
  uint count = f.grid_w * f.grid_h;
  uint cell_w = f.grid_w + f.n - 1u;
  bool by_cell = o.visibility == SVO_LUM_VIS_CELLS || o.visibility == SVO_LUM_VIS_CELLS_ON_U;
  bool global = o.sampler_kind == SVO_LUM_SAMPLER_GLOBAL;
  at.on_s = at.pl.z <= eps;
  at.t_on_s = svo_lum_to_texel(f, vec2(at.pl));
  at.area_total = 0.0f;
  at.nonempty = 0u;
  if (!at.on_s && !global) {
    at.area_total = svo_lum_state(pixel, f.state, p);
    at.nonempty = uint(svo_lum_state(pixel, f.state + 1u, p));
    if (o.balanced && !(at.area_total > 0.0f)) return vec3(0.0f);
    if (at.nonempty == 0u) return vec3(0.0f);
  }
  vec2 t = at.t_on_s;
  if (at.on_s && !(t.x >= 0.0f && t.y >= 0.0f && t.x < float(f.w) && t.y < float(f.h))) return vec3(0.0f);
  float texel_width = f.extent.x / float(f.w);
  float half_support = 0.5f * float(f.n) * f.spacing;

  vec3 total = vec3(0.0f);
  SvoLumShare share = svo_lum_share(f, 0u, at, o);
  uint start = 0u;  // the index of the share's first sample
  uint passes = global ? 1u : count;
  float vis_m = 1.0f;
  bool vis_known = false;
  for (uint i = first; i - first < chunk; ++i) {
    while (share.m < passes && i - start >= share.km) {
      start += share.km;
      share = svo_lum_share(f, share.m + 1u, at, o);
      vis_known = false;
    }
    if (share.m >= passes) break;
    uint m = share.m;
    uint img = share.img;
    vec2 u = svo_lum_rand(pixel, i, 0u, o.sequence, o.seed);
    if (global) {
      // The image by its share of the energy (the CDF over images,
      // inverted: its integer part the image, the rest reused), then the
      // whole image.
      float x = svo_lum_invert(f, svo_lum_table_cdf(f.image_cdf), count, 0u, count, u.x, SVO_LUM_SEARCH_BINARY, 0u);
      m = min(uint(x), count - 1u);
      u.x = clamp(x - float(m), 0.0f, 0.99999994f);
      img = svo_lum_image(f, m);
      vis_known = false;
    }
    SvoLobe lobe = svo_lum_lobe(p, g, pixel, i, o);
    vec3 q;        // the light's point
    vec3 c;        // C_m there
    float weight;  // Psi_m x the solid angle's Jacobian / the density
    if (at.on_s) {
      // Eq. 9: u uniform over the support of Phi_m.
      vec2 uu = svo_lum_basis_centre(f, m) + (2.0f * u - 1.0f) * half_support;
      q = svo_lum_on_u(f, uu);
      float r = length(q - p.position);
      c = svo_lum_texel_colour(f, img, at.t_on_s);
      weight = svo_lum_basis(f, m, uu) * (f.delta + at.pl.z) / (r * r * r) * (4.0f * half_support * half_support);
    } else {
      vec4 box = share.box;
      vec3 s;
      if (o.sampler_kind == SVO_LUM_SAMPLER_UNIFORM) {
        s = vec3(mix(vec2(box), vec2(box.z, box.w), u), 1.0f / ((box.z - box.x) * (box.w - box.y)));
      } else {
        s = svo_lum_sample_box(f, img, box, u, o.search, o.depth, o.sampler_kind == SVO_LUM_SAMPLER_BOX);
      }
      if (!(s.z > 0.0f)) continue;
      vec2 sl = svo_lum_from_texel(f, vec2(s));
      vec2 uu = vec2(at.pl) + (sl - vec2(at.pl)) * ((at.pl.z + f.delta) / at.pl.z);
      float phi = svo_lum_basis(f, m, uu);
      if (!(phi > 0.0f)) continue;
      q = svo_lum_on_s(f, vec2(s));
      float r = length(q - p.position);
      c = svo_lum_texel_colour(f, img, vec2(s));
      // Delta / r^3 ds is the solid angle; the density per unit area of S
      // is the density per texel over the texel's area.
      weight = phi * at.pl.z / (r * r * r) * (f.texel_area / s.z);
      if (global) {
        float p_m = svo_lum_table(f.image_cdf + m + 1u) - svo_lum_table(f.image_cdf + m);
        weight /= p_m;
      }
    }
    vec3 contribution = c * weight * svo_lum_brdf(p, lobe, q);
    if (!(contribution.x + contribution.y + contribution.z > 0.0f)) continue;
    if (o.visibility == SVO_LUM_VIS_SAMPLES) {
      contribution *= svo_lum_visible(p, q, texel_width);
    } else if (by_cell && !vis_known) {
      // v_m: the mean of the cells' v (the state) under Phi_m's support.
      uint ci = m % f.grid_w;
      uint cj = m / f.grid_w;
      float v = 0.0f;
      for (uint b = cj; b < cj + f.n; ++b) {
        for (uint a = ci; a < ci + f.n; ++a) v += svo_lum_state(pixel, f.state + 2u + b * cell_w + a, p);
      }
      vis_m = v / float(f.n * f.n);
      vis_known = true;
    }
    total += contribution * ((by_cell ? vis_m : 1.0f) / float(share.km));
  }
  return total;
}

// The luminaires' light over the point's coverage, summed over luminaires:
// samples [first, first + chunk) of each.
SVO_FN vec3 svo_luminaires(SvoGBuffer g, uint pixel, uint first, uint chunk) {
  if (!(g.coverage > 0.0f)) return vec3(0.0f);
  SvoLumOptions o = svo_lum_options();
  SvoShadingPoint p = svo_shading_point(g);
  vec3 sum = vec3(0.0f);
  for (uint l = 0u; l < o.count; ++l) sum += svo_luminaire_shade(g, p, pixel, l, o, first, chunk);
  return g.coverage * sum;
}

// The pixel with samples [first, first + chunk): `base` is what the frame
// holds. over_colour: the frame's colour (the forward pass's), to which the
// luminaires' light adds; otherwise, at first = 0, the background's share
// (the trace pass's "background": rgb, 1 - coverage), to which the ambient
// term and the luminaires' light add; at first > 0, the earlier calls' sum.
SVO_FN vec4 svo_luminaire_texel(SvoGBuffer g, vec4 base, uint pixel, bool over_colour, uint first, uint chunk) {
  vec4 sum = base;
  if (!over_colour && first == 0u) {
    sum = vec4(vec3(base), 0.0f);
    if (g.coverage > 0.0f) sum += g.coverage * vec4(svo_forward_ambient(g), 1.0f);
  }
  return sum + vec4(svo_luminaires(g, pixel, first, chunk), 0.0f);
}

// Dense quadrature of the same integral (Eq. 4 with the BRDF) without
// visibility, for the tests and the benchmark's ground truth of one
// G-buffer: for each image, every texel of its projected support's box
// (Eq. 7: outside it Phi_m is 0), k x k points each. Lobes are drawn with
// u = (0.5, 0.5): exact for Lambert, Beckmann and GGX, whose lobe takes the
// voxel's slopes without sampling.
SVO_FN vec3 svo_luminaire_quadrature(SvoGBuffer g, uint l, uint k) {
  if (!(g.coverage > 0.0f)) return vec3(0.0f);
  SvoShadingPoint p = svo_shading_point(g);
  SvoLumInfo f = svo_lum_info(l);
  vec3 pl = svo_lum_local(f, p.position);
  if (!(pl.z > 1.0e-5f * f.delta)) return vec3(0.0f);
  bool mixed = g.material != g.material2 && g.material_mix < 1.0f;
  SvoLobe first = svo_sample_lobe(p, svo_scene_material(g.material), vec2(0.5f));
  SvoLobe second = svo_sample_lobe(p, svo_scene_material(g.material2), vec2(0.5f));
  uint count = f.grid_w * f.grid_h;
  vec3 sum = vec3(0.0f);
  for (uint m = 0u; m < count; ++m) {
    vec4 box = svo_lum_box(f, m, pl);
    if (!(box.z > box.x) || !(box.w > box.y)) continue;
    uint img = svo_lum_image(f, m);
    for (uint y = uint(box.y); y < min(uint(ceil(box.w)), f.h); ++y) {
      for (uint x = uint(box.x); x < min(uint(ceil(box.z)), f.w); ++x) {
        vec3 c = svo_lum_texel_colour(f, img, vec2(float(x), float(y)));
        if (!(c.x + c.y + c.z > 0.0f)) continue;
        for (uint j = 0u; j < k; ++j) {
          for (uint i = 0u; i < k; ++i) {
            vec2 t = vec2(float(x), float(y)) + (vec2(float(i), float(j)) + 0.5f) / float(k);
            vec2 sl = svo_lum_from_texel(f, t);
            float phi = svo_lum_basis(f, m, vec2(pl) + (sl - vec2(pl)) * ((pl.z + f.delta) / pl.z));
            if (!(phi > 0.0f)) continue;
            vec3 q = svo_lum_on_s(f, t);
            float r = length(q - p.position);
            vec3 b = svo_lum_brdf(p, first, q);
            if (mixed) b = g.material_mix * b + (1.0f - g.material_mix) * svo_lum_brdf(p, second, q);
            sum += c * phi * b * (pl.z / (r * r * r));
          }
        }
      }
    }
  }
  return g.coverage * sum * (f.texel_area / float(k * k));
}

#endif
