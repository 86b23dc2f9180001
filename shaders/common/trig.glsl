// atan2 in float from +, *, / only, so that the shaders and the C++ build round
// alike (Vulkan allows 4096 ulp for the built-in atan; lavapipe is ~2e-5 off).
// Absolute error below 3e-7 rad (tests/numerics/trig_test.cpp).
#ifndef SVO_TRIG_GLSL
#define SVO_TRIG_GLSL
#include "prelude.glsl"

// atan(t) for t in [0, 1]: t * A(t^2), coefficients from scripts/fit_constants.py.
SVO_FN float svo_atan_unit(float t) {
  float z = t * t;
  float a = -1.701170064e-03f;
  a = a * z + 1.048764925e-02f;
  a = a * z - 3.035186479e-02f;
  a = a * z + 5.708955593e-02f;
  a = a * z - 8.349724968e-02f;
  a = a * z + 1.093234150e-01f;
  a = a * z - 1.426001608e-01f;
  a = a * z + 1.999807528e-01f;
  a = a * z - 3.333327629e-01f;
  a = a * z + 9.999999972e-01f;
  return t * a;
}

// Angle of (x, y) in [-pi, pi]; 0 for (0, 0) (GLSL's atan(y, x) is undefined there).
SVO_FN float svo_atan2(float y, float x) {
  float ax = abs(x);
  float ay = abs(y);
  float hi = max(ax, ay);
  if (!(hi > 0.0f)) return 0.0f;
  float r = svo_atan_unit(min(ax, ay) / hi);
  if (ay > ax) r = 0.5f * SVO_PI - r;
  if (x < 0.0f) r = SVO_PI - r;
  return y < 0.0f ? -r : r;
}

#endif
