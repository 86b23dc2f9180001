// The tangent frame of a mean normal, derived deterministically from it
// (Duff et al. 2017, "Building an orthonormal basis, revisited"). Anisotropic
// slope covariances in the octree are expressed in this frame, so the
// voxelizer and the renderer must build it identically.
#ifndef SVO_FRAME_GLSL
#define SVO_FRAME_GLSL
#include "prelude.glsl"

struct SvoFrame {
  vec3 t;  // first tangent (slope axis x)
  vec3 b;  // second tangent (slope axis y)
};

SVO_FN SvoFrame svo_tangent_frame(vec3 n) {
  float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sign + n.z);
  float c = n.x * n.y * a;
  SvoFrame f;
  f.t = vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  f.b = vec3(c, sign + n.y * n.y * a, -n.y);
  return f;
}

// r C r2^T for rows r, r2 and the symmetric 2x2 covariance (xx, yy, xy).
SVO_FN float svo_cov_form(vec2 r, vec3 c, vec2 r2) {
  return r.x * (c.x * r2.x + c.z * r2.y) + r.y * (c.z * r2.x + c.y * r2.y);
}

// A slope covariance (xx, yy, xy) in the frame of unit n, for the normals
// turned around (-n), in the frame of -n: slopes s' = M s with
// M = -[[t.t2, b.t2], [t.b2, b.b2]] (t, b of n; t2, b2 of -n), M C M^T.
// The voxelizer turns a sheet's far side with it (two_sided), the tracer a
// two-sided shell's far half (svo_turn_to_eye).
SVO_FN vec3 svo_turned_slope_covariance(vec3 n, vec3 c) {
  SvoFrame f = svo_tangent_frame(n);
  SvoFrame g = svo_tangent_frame(-n);
  vec2 r0 = vec2(-dot(f.t, g.t), -dot(f.b, g.t));
  vec2 r1 = vec2(-dot(f.t, g.b), -dot(f.b, g.b));
  return vec3(svo_cov_form(r0, c, r0), svo_cov_form(r1, c, r1), svo_cov_form(r0, c, r1));
}

#endif
