// The shared-math probe: one input vec4 gives SVO_PROBE_OUTPUTS vec4 of
// results, computed by shaders/selftest/math_probe.comp on the GPU and by the
// C++ build of this same function on the CPU (render/math_probe.h), so that the
// two can be compared value for value. Layout: std430 arrays of vec4.
#ifndef SVO_PROBE_GLSL
#define SVO_PROBE_GLSL
#include "beckmann.glsl"
#include "cone_mask.glsl"
#include "sg.glsl"

SVO_CONST int SVO_PROBE_WORKGROUP = 64;
SVO_CONST int SVO_PROBE_OUTPUTS = 5;


// in = (mu, sigma, x, y): mu = cot(theta) of a direction, sigma its slope
// standard deviation, x a free argument in [-12, 12] (erf, heights), y one in
// [-1, 1]. Output k of the result holds (names in render/math_probe.cpp):
//  0: erf(x), erfc(x), g(x; sigma), s(x; sigma)
//  1: Lambda(mu, sigma), Lambda_a(mu), G1, attribute_vl(0.6, 0.4 y, Lambda)
//  2: Lambda_dir, Beckmann D, specular BRDF, Lambda_cos
//  3: mask theta, mask v, mask coverage(v), erfcx(|x| + 0.84375)
//  4: spherical Gaussians (sg.glsl) of sharpness 10^(x/3) about +z and
//     100 sigma about a direction up to 90 degrees away (y, nearer for
//     sharp lobes): the exact
//     product integral, Eq. 11 and Eq. 12 at beta 1, Iwasaki's integral
// Directions are built with +, *, / and sqrt only (no built-in trig, whose
// precision Vulkan leaves loose). Beckmann D and the specular lobe are probed
// inside the lobe (slopes within 4 sigma, at most 0.25): in the far tail D = exp(-e) turns
// the ulp-level differences Vulkan allows in sqrt and division into relative
// differences of about 2e ulp, which would say nothing about our source.
SVO_FN vec4 svo_probe_row(vec4 in_, int k) {
  float mu = in_.x;
  float sigma = in_.y;
  float x = in_.z;
  float y = in_.w;
  if (k == 0) {
    return vec4(svo_erf(x), svo_erfc(x), svo_height_cdf(x, sigma), svo_height_sigmoid(x, sigma));
  }
  if (k == 1) {
    float lambda = svo_smith_lambda(mu, sigma);
    return vec4(lambda, svo_smith_lambda_a(mu), svo_smith_g1(lambda), svo_attribute_vl(0.6f, 0.4f * y, lambda));
  }
  // Unit direction with cot(theta) = mu and azimuth given rationally by t = x / 12.
  float t = x / 12.0f;
  float inv = 1.0f / (1.0f + t * t);
  float r = 1.0f / sqrt(1.0f + mu * mu);
  vec3 w = vec3((1.0f - t * t) * inv * r, 2.0f * t * inv * r, mu * r);
  vec2 s2 = vec2(sigma * sigma, 0.25f * sigma * sigma + 1.0e-4f);
  if (k == 2) {
    // Specular: a view within 30 degrees of the normal, a micronormal at
    // slopes (4 y sigma_x, -2 t sigma_y) clamped to 0.25, the light mirrored
    // about it, so that n.l >= 0.36 and the half vector is that micronormal.
    vec3 v = normalize(vec3(0.5f * t, 0.3f * y, 1.0f));
    vec2 slope = clamp(vec2(4.0f * y * sqrt(s2.x), -2.0f * t * sqrt(s2.y)), vec2(-0.25f), vec2(0.25f));
    vec3 m = normalize(vec3(-slope.x, -slope.y, 1.0f));
    vec3 l = 2.0f * dot(v, m) * m - v;
    // The BRDF recomputes the half vector; its rounding (~1e-7) moves D by
    // about 4e-7 / sigma relative, so the lobe is probed with sigma >= 0.1.
    vec2 s2_lobe = s2 + vec2(0.01f);
    return vec4(svo_smith_lambda_dir(w, s2), svo_beckmann_d(m, s2), svo_specular_brdf(v, l, s2_lobe),
                svo_smith_lambda_cos(mu * r, sigma));
  }
  if (k == 4) {
    SvoSG a = svo_sg(vec3(0.0f, 0.0f, 1.0f), exp2(x * 1.10730936f), 1.0f);  // 10^(x/3)
    SvoSG b = svo_sg(vec3(0.0f, 0.0f, 1.0f), 100.0f * sigma, 1.0f);
    // Axes apart by 2 atan(t): the product's exponent l (1 - cos) stays
    // above about -8 (l = la lb / (la + lb)), where a weight still matters;
    // further out an ulp of the exponent is a relative difference of its size.
    float l = a.sharpness * b.sharpness / max(a.sharpness + b.sharpness, 1.0e-30f);
    float t = y * min(1.0f, 2.0f / sqrt(max(l, 1.0e-30f)));
    b.axis = vec3(2.0f * t, 0.0f, 1.0f - t * t) / (1.0f + t * t);
    return vec4(svo_sg_product_integral(a, b), svo_weight_eq11(a, b, 1.0f), svo_weight_eq12(a, b, 1.0f),
                svo_sg_product_integral_approx(a, b));
  }
  SvoMaskParams p = svo_cone_mask_params(w, y, 0.5f + sigma, 0.5f + 0.25f * sigma);
  return vec4(p.theta, p.v, svo_mask_coverage(p.v), svo_erfcx_large(abs(x) + SVO_ERF_SPLIT));
}

#endif
