// Occlusion of a cone element by the voxel's mean plane, Heitz & Neyret
// section 5.4 and Fig. 7. In the cone frame (z along the axis, the element
// centred at z_d with radius r and extremities z_d +- l), the plane
//   x nx + y ny + (z - z_d) nz + hbar = 0
// covers the ray through the footprint point (wx, wy) of the unit disk iff
//   wx cos(theta) + wy sin(theta) <= v,  v = (|nz| l - hbar) / (r sqrt(nx^2 + ny^2)).
// The mask table is indexed by (theta, v).
#ifndef SVO_CONE_MASK_GLSL
#define SVO_CONE_MASK_GLSL
#include "trig.glsl"

// v is clamped to +-SVO_MASK_V_ALL outside (-1, 1): every point of the disk is
// covered (v >= 1) or none is (v <= -1).
SVO_CONST float SVO_MASK_V_ALL = 2.0f;

struct SvoMaskParams {
  float theta;  // direction of (nx, ny) in the footprint, in [-pi, pi]
  float v;      // signed offset of the covering half-plane, in [-2, 2]
};

// n: unit mean normal in the cone frame; hbar: signed distance of the element
// centre to the plane; radius > 0; half_length: l above; kappa: the surface's
// curvature along the axis, d^2 f / dz^2 of its distance f (> 0 convex).
// Never divides by zero: a plane facing the cone (nx = ny = 0) gives all or
// nothing.
//
// With kappa, f(z) = hbar + nx x + ny y + nz z + kappa z^2 / 2 along the ray
// through (x, y): a convex surface falls away from its tangent plane, so the
// ray meets it iff nx x + ny y <= max over |z| <= l of -(nz z + kappa z^2 / 2)
// less hbar. That maximum ("reach") is nz^2 / (2 kappa) where the ray's
// closest approach lies within the element (kappa > 0, |nz| < kappa l), else
// |nz| l - kappa l^2 / 2; kappa = 0 gives the plane's |nz| l. The plane
// alone covers too much of a convex silhouette: its tangent plane reaches
// past the surface by kappa l^2 / 2.
SVO_FN SvoMaskParams svo_cone_mask_params_curved(vec3 n, float hbar, float radius, float half_length, float kappa) {
  float nz = abs(n.z);
  float reach = (kappa > 0.0f && nz < kappa * half_length) ? nz * nz / (2.0f * kappa)
                                                           : nz * half_length - 0.5f * kappa * half_length * half_length;
  float num = reach - hbar;
  float den = radius * sqrt(n.x * n.x + n.y * n.y);
  SvoMaskParams p;
  if (abs(num) < den) {
    p.theta = svo_atan2(n.y, n.x);
    p.v = num / den;
  } else {
    p.theta = 0.0f;
    p.v = num >= 0.0f ? SVO_MASK_V_ALL : -SVO_MASK_V_ALL;
  }
  return p;
}

// The mean plane alone (paper Fig. 7).
SVO_FN SvoMaskParams svo_cone_mask_params(vec3 n, float hbar, float radius, float half_length) {
  return svo_cone_mask_params_curved(n, hbar, radius, half_length, 0.0f);
}

// Whether footprint point w (unit disk) is covered.
SVO_FN bool svo_mask_covers(vec2 w, SvoMaskParams p) {
  return w.x * cos(p.theta) + w.y * sin(p.theta) <= p.v;
}

// Exact covered fraction of the unit disk for offset v: the area of
// {x <= v} inside the disk over pi; 0 for v <= -1, 1 for v >= 1.
// For v <= 0 it is the segment (2 phi - sin 2 phi) / (2 pi), phi = acos(-v),
// with phi = 2 atan2(sqrt((1 + v)/2), sqrt((1 - v)/2)) exact near v = -1 and a
// series for x - sin x when the segment is thin (no cancellation); v > 0 by symmetry.
SVO_FN float svo_mask_coverage(float v) {
  float c = clamp(v, -1.0f, 1.0f);
  float u = -abs(c);
  float phi = 2.0f * svo_atan2(sqrt(0.5f * (1.0f + u)), sqrt(0.5f * (1.0f - u)));
  float x = 2.0f * phi;
  float segment;
  if (x < 1.0f) {
    float x2 = x * x;
    float s = 1.0f / 39916800.0f;
    s = s * x2 - 1.0f / 362880.0f;
    s = s * x2 + 1.0f / 5040.0f;
    s = s * x2 - 1.0f / 120.0f;
    s = s * x2 + 1.0f / 6.0f;
    segment = x * x2 * s;  // x - sin x
  } else {
    segment = x + 2.0f * u * sqrt(max(0.0f, 1.0f - u * u));  // sin 2 phi = -2 u sqrt(1 - u^2)
  }
  float f = segment / (2.0f * SVO_PI);
  return c > 0.0f ? 1.0f - f : f;
}

#endif
