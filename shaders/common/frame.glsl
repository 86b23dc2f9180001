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

#endif
