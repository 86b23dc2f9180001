// Piecewise-constant 2D distributions over [0, 1]^2 (pbrt-v4's
// PiecewiseConstant2D), read from the shading tables (host contract:
// `float svo_table(uint i)`, the floats render::ShadingTables holds). A
// distribution of nu x nv cells at offset o is laid out as
//   o:                          f, nv rows of nu values (>= 0)
//   o + nu nv:                  each row's CDF, nv x (nu + 1) (0 ... 1)
//   o + nu nv + nv (nu + 1):    the marginal CDF over rows, nv + 1 (0 ... 1)
//   then one float:             the mean of f over the square
// A row whose f is all zero has a uniform CDF (never NaN) and no mass in the
// marginal, so that it is never drawn; a cell of f > 0 always has pdf > 0.
#ifndef SVO_DISTRIBUTION_GLSL
#define SVO_DISTRIBUTION_GLSL
#include "prelude.glsl"

SVO_FN uint svo_dist2d_floats(uint nu, uint nv) { return nu * nv + nv * (nu + 1u) + nv + 2u; }

// The last index i in [0, n) with cdf[i] <= u (cdf: n + 1 floats at `at`):
// its interval has positive width whenever the CDF rises past u.
SVO_FN uint svo_find_interval(uint at, uint n, float u) {
  uint lo = 0u;
  uint hi = n;  // invariant: cdf[lo] <= u (cdf[0] = 0 <= u), and i < hi
  while (hi - lo > 1u) {
    uint mid = (lo + hi) / 2u;
    if (svo_table(at + mid) <= u) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// A point of [0, 1)^2 drawn from the distribution at `o` with uniform u:
// xy the point, z its density over the square (f / mean; 0 only where f is).
SVO_FN vec3 svo_dist2d_sample(uint o, uint nu, uint nv, vec2 u) {
  uint cond = o + nu * nv;
  uint marg = cond + nv * (nu + 1u);
  float mean = svo_table(marg + nv + 1u);
  float uy = min(u.y, 0.99999994f);
  uint iv = svo_find_interval(marg, nv, uy);
  float c0 = svo_table(marg + iv);
  float dv = svo_table(marg + iv + 1u) - c0;
  float fv = dv > 0.0f ? clamp((uy - c0) / dv, 0.0f, 0.99999994f) : 0.5f;
  uint row = cond + iv * (nu + 1u);
  float ux = min(u.x, 0.99999994f);
  uint iu = svo_find_interval(row, nu, ux);
  float r0 = svo_table(row + iu);
  float du = svo_table(row + iu + 1u) - r0;
  float fu = du > 0.0f ? clamp((ux - r0) / du, 0.0f, 0.99999994f) : 0.5f;
  float f = svo_table(o + iv * nu + iu);
  return vec3((float(iu) + fu) / float(nu), (float(iv) + fv) / float(nv), mean > 0.0f ? f / mean : 0.0f);
}

// The row-major index of the cell of an nu x nv grid over [0, 1]^2 that
// holds p (clamped to the grid).
SVO_FN uint svo_grid_cell(vec2 p, uint nu, uint nv) {
  uint iu = min(uint(max(p.x, 0.0f) * float(nu)), nu - 1u);
  uint iv = min(uint(max(p.y, 0.0f) * float(nv)), nv - 1u);
  return iv * nu + iu;
}

// The density over the square at p (the z of svo_dist2d_sample there).
SVO_FN float svo_dist2d_pdf(uint o, uint nu, uint nv, vec2 p) {
  float mean = svo_table(o + nu * nv + nv * (nu + 1u) + nv + 1u);
  return mean > 0.0f ? svo_table(o + svo_grid_cell(p, nu, nv)) / mean : 0.0f;
}

#endif
