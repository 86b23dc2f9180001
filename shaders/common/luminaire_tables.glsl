// The tables of the light-field luminaires (luminaire.glsl's header gives
// their layout) and the sampling of one image: the projected support of a
// basis (Eq. 7), A_m(p) from the summed-area tables (Eq. 10), restricted
// CDFs (Eq. 8) inverted by the modified secant or binary search (section 5).
// Host contract: `float svo_lum_table(uint i)`.
#ifndef SVO_LUMINAIRE_TABLES_GLSL
#define SVO_LUMINAIRE_TABLES_GLSL
#include "prelude.glsl"

SVO_CONST uint SVO_LUM_SAMPLER_RESTRICTED = 0u;
SVO_CONST uint SVO_LUM_SAMPLER_UNIFORM = 1u;
SVO_CONST uint SVO_LUM_SAMPLER_GLOBAL = 2u;
SVO_CONST uint SVO_LUM_SAMPLER_BOX = 3u;
SVO_CONST uint SVO_LUM_SEARCH_SECANT = 0u;
SVO_CONST uint SVO_LUM_SEARCH_BINARY = 1u;
SVO_CONST uint SVO_LUM_SEARCH_ILLINOIS = 2u;
SVO_CONST uint SVO_LUM_SEARCH_CLASSIC = 3u;
SVO_CONST uint SVO_LUM_VIS_NONE = 0u;
SVO_CONST uint SVO_LUM_VIS_CELLS = 1u;
SVO_CONST uint SVO_LUM_VIS_SAMPLES = 2u;
SVO_CONST uint SVO_LUM_VIS_CELLS_ON_U = 3u;
SVO_CONST uint SVO_LUM_SEQ_HALTON = 0u;
SVO_CONST uint SVO_LUM_SEQ_RANDOM = 1u;
SVO_CONST uint SVO_LUM_HEADER = 8u;
SVO_CONST uint SVO_LUM_BLOCK = 32u;

SVO_FN uint svo_lum_uint(uint i) { return floatBitsToUint(svo_lum_table(i)); }
SVO_FN vec3 svo_lum_vec3(uint i) { return vec3(svo_lum_table(i), svo_lum_table(i + 1u), svo_lum_table(i + 2u)); }

struct SvoLumInfo {
  vec3 centre;
  float delta;
  vec3 x;
  float spacing;
  vec3 y;
  uint basis;  // 0: B-spline, 1: quadratic (luminaire.h, LuminaireBasis)
  vec3 z;
  float texel_area;
  vec2 extent;
  uint w;
  uint h;
  uint grid_w;
  uint grid_h;
  uint images;
  uint stride;
  uint cells;
  float energy;
  uint image_cdf;
  uint n;      // cells of a basis's support per axis
  uint state;  // the offset of its entries in a pixel's state (luminaire.glsl)
};

SVO_FN SvoLumInfo svo_lum_info(uint l) {
  uint o = SVO_LUM_HEADER + SVO_LUM_BLOCK * l;
  SvoLumInfo f;
  f.centre = svo_lum_vec3(o);
  f.delta = svo_lum_table(o + 3u);
  f.x = svo_lum_vec3(o + 4u);
  f.spacing = svo_lum_table(o + 7u);
  f.y = svo_lum_vec3(o + 8u);
  f.basis = svo_lum_uint(o + 11u);
  f.z = svo_lum_vec3(o + 12u);
  f.texel_area = svo_lum_table(o + 15u);
  f.extent = vec2(svo_lum_table(o + 16u), svo_lum_table(o + 17u));
  f.w = svo_lum_uint(o + 18u);
  f.h = svo_lum_uint(o + 19u);
  f.grid_w = svo_lum_uint(o + 20u);
  f.grid_h = svo_lum_uint(o + 21u);
  f.images = svo_lum_uint(o + 22u);
  f.stride = svo_lum_uint(o + 23u);
  f.cells = svo_lum_uint(o + 24u);
  f.energy = svo_lum_table(o + 25u);
  f.image_cdf = svo_lum_uint(o + 26u);
  f.n = svo_lum_uint(o + 27u);
  f.state = svo_lum_uint(o + 28u);
  return f;
}

// Offsets of image m's tables.
SVO_FN uint svo_lum_image(SvoLumInfo f, uint m) { return f.images + m * f.stride; }
SVO_FN uint svo_lum_cond(SvoLumInfo f, uint img, uint column) { return img + f.w + 1u + column * (f.h + 1u); }
SVO_FN uint svo_lum_colour(SvoLumInfo f, uint img) { return img + f.w + 1u + f.w * (f.h + 1u); }
SVO_FN uint svo_lum_sat(SvoLumInfo f, uint img) { return svo_lum_colour(f, img) + 3u * f.w * f.h; }
SVO_FN uint svo_lum_tail(SvoLumInfo f, uint img) { return svo_lum_sat(f, img) + 2u * (f.w + 1u) * (f.h + 1u); }

// phi(x) of the basis (luminaire.cpp, luminaire_basis_phi).
SVO_FN float svo_lum_phi(uint basis, float x) {
  float a = abs(x);
  if (basis == 1u) return a < 1.0f ? 1.0f - a * a : 0.0f;
  if (a < 0.5f) return 0.75f - a * a;
  if (a < 1.5f) return 0.5f * (1.5f - a) * (1.5f - a);
  return 0.0f;
}

// The centre of basis m on U (z = -delta from S), and Phi_m(u).
SVO_FN vec2 svo_lum_basis_centre(SvoLumInfo f, uint m) {
  return vec2(float(m % f.grid_w) - 0.5f * float(f.grid_w - 1u), float(m / f.grid_w) - 0.5f * float(f.grid_h - 1u)) *
         f.spacing;
}
SVO_FN float svo_lum_basis(SvoLumInfo f, uint m, vec2 u) {
  vec2 x = (u - svo_lum_basis_centre(f, m)) / f.spacing;
  return svo_lum_phi(f.basis, x.x) * svo_lum_phi(f.basis, x.y);
}

// S's local coordinates <-> texel coordinates.
SVO_FN vec2 svo_lum_to_texel(SvoLumInfo f, vec2 s) { return (s / f.extent + 0.5f) * vec2(float(f.w), float(f.h)); }
SVO_FN vec2 svo_lum_from_texel(SvoLumInfo f, vec2 t) { return (t / vec2(float(f.w), float(f.h)) - 0.5f) * f.extent; }

// A point in the luminaire's frame: across S, and Delta, its height above S.
SVO_FN vec3 svo_lum_local(SvoLumInfo f, vec3 p) {
  vec3 d = p - f.centre;
  return vec3(dot(d, f.x), dot(d, f.y), dot(d, f.z));
}

// The projection of basis m's support onto S from a point at `pl` above S
// (Eq. 7), in texel coordinates and clipped to the image: xy the low
// corner, zw the high one; empty when z <= x or w <= y.
SVO_FN vec4 svo_lum_box(SvoLumInfo f, uint m, vec3 pl) {
  float half_support = 0.5f * float(f.n) * f.spacing;
  vec2 c = svo_lum_basis_centre(f, m);
  float k = pl.z / (pl.z + f.delta);
  vec2 lo = vec2(pl) + (c - half_support - vec2(pl)) * k;
  vec2 hi = vec2(pl) + (c + half_support - vec2(pl)) * k;
  vec2 tl = clamp(svo_lum_to_texel(f, lo), vec2(0.0f), vec2(float(f.w), float(f.h)));
  vec2 th = clamp(svo_lum_to_texel(f, hi), vec2(0.0f), vec2(float(f.w), float(f.h)));
  return vec4(tl, th);
}

// The summed-area table's sum over whole texels [x0, x1) x [y0, y1): the
// hi parts are multiples of one quantum below 2^13 of them, so that their
// sums are exact, and the lo parts carry the rest.
SVO_FN float svo_lum_sat_box(SvoLumInfo f, uint img, uint x0, uint x1, uint y0, uint y1) {
  uint hi = svo_lum_sat(f, img);
  uint lo = hi + (f.w + 1u) * (f.h + 1u);
  uint stride = f.w + 1u;
  uint a = y0 * stride + x0;
  uint b = y0 * stride + x1;
  uint c = y1 * stride + x0;
  uint d = y1 * stride + x1;
  float h = (svo_lum_table(hi + d) - svo_lum_table(hi + c)) - (svo_lum_table(hi + b) - svo_lum_table(hi + a));
  float l = (svo_lum_table(lo + d) - svo_lum_table(lo + c)) - (svo_lum_table(lo + b) - svo_lum_table(lo + a));
  return h + l;
}

// A_m(p) over a box in texel coordinates (Eq. 10): the integral of the
// piecewise-constant luminance, as sums over whole texels (the box's whole
// columns and rows, less the parts of its first, plus its last) so that no
// two large sums cancel; never negative, exactly 0 where the box holds no
// texel of luminance > 0.
SVO_FN float svo_lum_area(SvoLumInfo f, uint img, vec4 box) {
  if (!(box.z > box.x) || !(box.w > box.y)) return 0.0f;
  uint x0 = uint(box.x);
  uint x1 = min(uint(box.z), f.w - 1u);
  uint y0 = uint(box.y);
  uint y1 = min(uint(box.w), f.h - 1u);
  float fx0 = box.x - float(x0);
  float fx1 = box.z - float(x1);
  float fy0 = box.y - float(y0);
  float fy1 = box.w - float(y1);
  // Columns: [x0, x1) whole, minus fx0 of column x0, plus fx1 of column x1.
  float sum = 0.0f;
  for (uint i = 0u; i < 3u; ++i) {
    uint ca = i == 0u ? x0 : (i == 1u ? x0 : x1);
    uint cb = i == 0u ? x1 : ca + 1u;
    float wx = i == 0u ? 1.0f : (i == 1u ? -fx0 : fx1);
    if (cb <= ca || wx == 0.0f) continue;
    for (uint j = 0u; j < 3u; ++j) {
      uint ra = j == 0u ? y0 : (j == 1u ? y0 : y1);
      uint rb = j == 0u ? y1 : ra + 1u;
      float wy = j == 0u ? 1.0f : (j == 1u ? -fy0 : fy1);
      if (rb <= ra || wy == 0.0f) continue;
      sum += wx * wy * svo_lum_sat_box(f, img, ca, cb, ra, rb);
    }
  }
  return max(sum, 0.0f);
}

// The piecewise-linear CDF of n intervals at `at` (n + 1 floats) at x in [0, n].
SVO_FN float svo_lum_cdf(uint at, uint n, float x) {
  float c = clamp(x, 0.0f, float(n));
  uint i = min(uint(c), n - 1u);
  float a = svo_lum_table(at + i);
  return a + (svo_lum_table(at + i + 1u) - a) * (c - float(i));
}

// A piecewise-linear CDF over texels to invert: a table of n + 1 floats at
// `at` (the images' marginal and column CDFs), or, `rows` set, the mass of
// image `img` in columns [0, x) and rows [rows.x, rows.y] from the
// summed-area table (svo_lum_area): the marginal of a box's own rows.
struct SvoLumCdf {
  uint at;
  uint img;
  bool box;
  vec2 rows;
};

SVO_FN SvoLumCdf svo_lum_table_cdf(uint at) {
  SvoLumCdf c;
  c.at = at;
  c.img = 0u;
  c.box = false;
  c.rows = vec2(0.0f);
  return c;
}

// The CDF at x in [0, n] (not normalised when c.box).
SVO_FN float svo_lum_cdf_value(SvoLumInfo f, SvoLumCdf c, uint n, float x) {
  if (c.box) return svo_lum_area(f, c.img, vec4(0.0f, c.rows.x, clamp(x, 0.0f, float(n)), c.rows.y));
  return svo_lum_cdf(c.at, n, x);
}

// Inverts the CDF for u in [cdf(lo), cdf(hi)] between texels lo and hi
// (lo < hi): the x where the piecewise-linear CDF reaches u. Secant: the
// paper's modified secant method, each step the chord's root, stopping at
// an interval of one texel, where the CDF is linear (section 5); it is
// false position, which keeps one end where the CDF bends one way over the
// interval. Illinois: the same chord, but an end kept twice in a row has
// its CDF value moved halfway to u for the next chord, so that neither end
// stays (Dowell and Jarratt 1971). Binary: halving. `depth` > 0 stops after
// that many steps and returns the chord's root in the interval left
// (Fig. 5's comparison at equal depth). Classic: halving that, stopped
// wider than one texel, returns the interval's midpoint, as a search that
// does not use the CDF's linearity would (Fig. 5's "classical binary
// search"); at one texel it interpolates, as every inversion does.
SVO_FN float svo_lum_invert(SvoLumInfo f, SvoLumCdf cdf, uint n, uint lo, uint hi, float u, uint method, uint depth) {
  float clo = svo_lum_cdf_value(f, cdf, n, float(lo));
  float chi = svo_lum_cdf_value(f, cdf, n, float(hi));
  // The chord's ends (Illinois moves them towards u) and the end the last
  // step replaced (0 none, 1 lo, 2 hi).
  float wlo = clo;
  float whi = chi;
  uint moved = 0u;
  uint steps = 0u;
  // The secant's worst case is linear in the interval: after a bisection's
  // worth of steps it halves instead (only when depth is unlimited).
  uint guard = 24u;
  while (hi - lo > 1u && (depth == 0u || steps < depth)) {
    uint mid;
    bool halving = method == SVO_LUM_SEARCH_BINARY || method == SVO_LUM_SEARCH_CLASSIC;
    if (!halving && (depth > 0u || steps < guard) && whi > wlo) {
      float t = (u - wlo) / (whi - wlo);
      mid = lo + uint(t * float(hi - lo));
      mid = clamp(mid, lo + 1u, hi - 1u);
    } else {
      mid = (lo + hi) / 2u;
    }
    float c = svo_lum_cdf_value(f, cdf, n, float(mid));
    bool illinois = method == SVO_LUM_SEARCH_ILLINOIS;
    if (c <= u) {
      lo = mid;
      clo = c;
      wlo = c;
      if (illinois && moved == 1u) whi = u + 0.5f * (whi - u);
      moved = 1u;
    } else {
      hi = mid;
      chi = c;
      whi = c;
      if (illinois && moved == 2u) wlo = u + 0.5f * (wlo - u);
      moved = 2u;
    }
    ++steps;
  }
  if (method == SVO_LUM_SEARCH_CLASSIC && hi - lo > 1u) return 0.5f * float(lo + hi);
  float t = chi > clo ? clamp((u - clo) / (chi - clo), 0.0f, 1.0f) : 0.5f;
  return float(lo) + t * float(hi - lo);
}

// A sample x of the CDF (n intervals) restricted to [a, b] (Eq. 8): x, and
// its density over x in texel units (0: nothing to sample).
SVO_FN vec2 svo_lum_sample_1d(SvoLumInfo f, SvoLumCdf cdf, uint n, float a, float b, float u, uint method, uint depth) {
  float c0 = svo_lum_cdf_value(f, cdf, n, a);
  float c1 = svo_lum_cdf_value(f, cdf, n, b);
  if (!(c1 > c0)) return vec2(0.0f);
  float target = c0 + u * (c1 - c0);
  uint lo = min(uint(a), n - 1u);
  uint hi = min(uint(ceil(b)), n);
  if (hi <= lo) hi = lo + 1u;
  float x = clamp(svo_lum_invert(f, cdf, n, lo, hi, target, method, depth), a, b);
  uint i = min(uint(x), n - 1u);
  float slope = svo_lum_cdf_value(f, cdf, n, float(i + 1u)) - svo_lum_cdf_value(f, cdf, n, float(i));
  return vec2(x, slope / (c1 - c0));
}

// A point of image `img` drawn from its CDFs restricted to `box` (texel
// coordinates): xy the point, z its density per unit texel area (0: none).
// The paper's Eq. 8 (in_box false): the image's marginal over columns
// restricted to the box's columns, then the column's CDF restricted to its
// rows; its density is C_m / A_m only where every column holds the same
// share of its energy in the box's rows, and the estimator divides by the
// density itself. in_box: the marginal of the box's own rows, from the
// summed-area table, so that the density is exactly C_m / A_m (Eq. 10).
SVO_FN vec3 svo_lum_sample_box(SvoLumInfo f, uint img, vec4 box, vec2 u, uint method, uint depth, bool in_box) {
  SvoLumCdf marginal = svo_lum_table_cdf(img);
  if (in_box) {
    marginal.img = img;
    marginal.box = true;
    marginal.rows = vec2(box.y, box.w);
  }
  vec2 sx = svo_lum_sample_1d(f, marginal, f.w, box.x, box.z, u.x, method, depth);
  if (!(sx.y > 0.0f)) return vec3(0.0f);
  uint column = min(uint(sx.x), f.w - 1u);
  vec2 sy = svo_lum_sample_1d(f, svo_lum_table_cdf(svo_lum_cond(f, img, column)), f.h, box.y, box.w, u.y, method, depth);
  if (!(sy.y > 0.0f)) return vec3(0.0f);
  return vec3(sx.x, sy.x, sx.y * sy.y);
}

SVO_FN vec3 svo_lum_texel_colour(SvoLumInfo f, uint img, vec2 t) {
  uint x = min(uint(t.x), f.w - 1u);
  uint y = min(uint(t.y), f.h - 1u);
  return svo_lum_vec3(svo_lum_colour(f, img) + 3u * (y * f.w + x));
}

#endif
