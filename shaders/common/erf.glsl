// erf and erfc in float (GLSL has neither).
// Contract, checked by tests/numerics/erf_test.cpp over [-12, 12]:
//  - absolute error of svo_erf and svo_erfc at most 2e-7 against std::erf/erfc;
//  - for x >= 0, svo_erfc has relative error below 1e-6 until it leaves
//    float's normal range (x >= 10 returns 0); tails of g(h) rely on it.
// Coefficients: scripts/fit_erfc.py (Maclaurin series below 0.84375, a refitted
// Numerical-Recipes-style form t * exp(-x^2 + Q(t)) above).
#ifndef SVO_ERF_GLSL
#define SVO_ERF_GLSL
#include "prelude.glsl"

SVO_CONST float SVO_ERF_SPLIT = 0.84375f;

// erf(x) for |x| < SVO_ERF_SPLIT: x * P(x^2), P the Maclaurin series to z^10,
// summed as x + x (P - 1) so that the leading 2/sqrt(pi), which float rounds
// by 5e-8, only enters through its small remainder 0.128379167.
SVO_FN float svo_erf_small(float x) {
  float z = x * x;
  float p = 1.480719282e-08f;
  p = p * z - 1.636584469e-07f;
  p = p * z + 1.646211437e-06f;
  p = p * z - 1.492565036e-05f;
  p = p * z + 1.205533298e-04f;
  p = p * z - 8.548327023e-04f;
  p = p * z + 5.223977625e-03f;
  p = p * z - 2.686617065e-02f;
  p = p * z + 1.128379167e-01f;
  p = p * z - 3.761263890e-01f;
  p = p * z + 1.283791671e-01f;
  return x + x * p;
}

// Q(t) of the form erfc(x) = t * exp(-x^2 + Q(t)), t = 1 / (1 + x/2), x >= SVO_ERF_SPLIT.
SVO_FN float svo_erfc_q(float t) {
  float q = 3.110706540e-01f;
  q = q * t - 1.102567568e+00f;
  q = q * t + 1.409114106e+00f;
  q = q * t - 6.903142918e-01f;
  q = q * t + 1.583853767e-01f;
  q = q * t - 1.990789350e-01f;
  q = q * t - 7.826693427e-02f;
  q = q * t + 8.270452253e-02f;
  q = q * t + 3.750269304e-01f;
  q = q * t + 9.999995403e-01f;
  q = q * t - 1.265512122e+00f;
  return q;
}

// Scaled complementary error function erfcx(x) = exp(x^2) erfc(x), x >= SVO_ERF_SPLIT.
SVO_FN float svo_erfcx_large(float x) {
  float t = 1.0f / (1.0f + 0.5f * x);
  return t * exp(svo_erfc_q(t));
}

// erfc(x) for x >= SVO_ERF_SPLIT, relative accuracy; 0 from x = 10 on (erfc(10) < 2.1e-45).
// exp(-x^2) is split as exp(-z^2) exp((z - x)(z + x)) with z = x cut to 12
// significant bits, so that z^2 is exact: a rounded x^2 near 81 would cost
// 5e-6 relative (ulp(81) / 2).
SVO_FN float svo_erfc_large(float x) {
  if (x >= 10.0f) return 0.0f;
  float t = 1.0f / (1.0f + 0.5f * x);
  float z = uintBitsToFloat(floatBitsToUint(x) & 0xFFFFF000u);
  return t * exp(-z * z) * exp((z - x) * (z + x) + svo_erfc_q(t));
}

SVO_FN float svo_erfc(float x) {
  float ax = abs(x);
  if (ax < SVO_ERF_SPLIT) return 1.0f - svo_erf_small(x);
  float r = svo_erfc_large(ax);
  return x > 0.0f ? r : 2.0f - r;
}

SVO_FN float svo_erf(float x) {
  float ax = abs(x);
  if (ax < SVO_ERF_SPLIT) return svo_erf_small(x);
  float r = 1.0f - svo_erfc_large(ax);
  return x > 0.0f ? r : -r;
}

#endif
