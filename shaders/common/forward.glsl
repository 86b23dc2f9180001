// The forward-shading pass's kernel (render::ForwardPass, DESIGN 10.2): every
// covered pixel of the G-buffer shaded with a fixed number of samples of the
// environment and the material, combined by multiple importance sampling
// (power heuristic, one BRDF sample and one environment sample each), plus
// the lights, and one point per sample of the area light (area_light.glsl);
// the background is the environment seen through the pixel.
// Each pixel shades with its materials (the G-buffer's two and their mix,
// svo_scene_material). Host
// contract: tracer.glsl's (params, the octree, for visibility cones), plus
// `shade` (SvoShadeParams) and svo_table (distribution.glsl).
//
// Pre-filtering carries over: the voxel's slope covariance (the G-buffer's,
// footprint included) widens the microfacet lobes (variances add: Beckmann
// alpha^2 + 2 sigma^2, GGX likewise), and for the Phong NDF and measured
// BRDFs each sample draws its normal from the voxel's Gaussian slope
// distribution. The diffuse part is the voxel's rough Lambert term with
// Smith masking and the Eq. 17 colour abar(v, l) per light direction.
#ifndef SVO_FORWARD_GLSL
#define SVO_FORWARD_GLSL
#include "area_light.glsl"
#include "environment.glsl"
#include "gbuffer.glsl"
#include "material.glsl"
#include "sequence.glsl"
#include "sg.glsl"
#include "shading.glsl"
#include "visibility.glsl"

// A G-buffer point as the samples see it.
struct SvoShadingPoint {
  vec3 v;   // unit, towards the eye
  vec3 n;   // unit mean normal
  vec3 tx;  // principal axes of the voxel slopes
  vec3 ty;
  vec2 sn2;  // voxel slope variances along tx, ty
  vec3 vl;   // v in (tx, ty, n)
  float lambda_v;
  vec3 abar;
  vec3 a_s;
  float radius;  // the pixel's footprint radius at the point
  vec3 position;
};

SVO_FN SvoShadingPoint svo_shading_point(SvoGBuffer g) {
  SvoShadingPoint p;
  p.position = g.position;
  p.v = normalize(vec3(params.eye) - g.position);
  float nl = length(g.normal);
  p.n = nl > 0.0f ? g.normal / nl : p.v;
  vec3 t = g.tangent;
  vec3 b = cross(p.n, t);
  vec3 cov = max(g.slope_cov, vec3(0.0f, 0.0f, -1.0e30f));
  float angle = 0.5f * svo_atan2(2.0f * cov.z, cov.x - cov.y);
  float ca = cos(angle);
  float sa = sin(angle);
  p.tx = ca * t + sa * b;
  p.ty = ca * b - sa * t;
  p.sn2 = svo_principal_variances(cov, ca, sa);
  p.vl = vec3(dot(p.v, p.tx), dot(p.v, p.ty), dot(p.v, p.n));
  p.lambda_v = svo_smith_lambda_dir(p.vl, p.sn2);
  p.abar = g.abar;
  p.a_s = g.a_s;
  p.radius = params.eye.w * g.depth;
  return p;
}

// The specular lobe's frame and material for one sample: the voxel slopes
// added to the microfacet lobe's variances, or a normal drawn from them.
struct SvoLobe {
  vec3 t;
  vec3 b;
  vec3 n;
  SvoMaterial mat;
};

SVO_FN SvoLobe svo_sample_lobe(SvoShadingPoint p, SvoMaterial mat, vec2 u) {
  SvoLobe lobe;
  lobe.mat = mat;
  lobe.t = p.tx;
  lobe.b = p.ty;
  lobe.n = p.n;
  if (mat.kind == SVO_BRDF_BECKMANN || mat.kind == SVO_BRDF_GGX) {
    lobe.mat.alpha2 = mat.alpha2 + 2.0f * p.sn2;
  } else if (mat.kind != SVO_BRDF_LAMBERT && p.sn2.x + p.sn2.y > 0.0f) {
    // Box-Muller: a slope from the voxel's Gaussian.
    float r = sqrt(-2.0f * log(max(1.0f - u.x, 1.0e-30f)));
    vec2 slope = r * vec2(cos(2.0f * SVO_PI * u.y), sin(2.0f * SVO_PI * u.y)) * sqrt(p.sn2);
    lobe.n = normalize(p.n - slope.x * p.tx - slope.y * p.ty);
    SvoFrame f = svo_tangent_frame(lobe.n);
    lobe.t = f.t;
    lobe.b = f.b;
  }
  return lobe;
}

SVO_FN vec3 svo_to_lobe(SvoLobe lobe, vec3 w) { return vec3(dot(w, lobe.t), dot(w, lobe.b), dot(w, lobe.n)); }

// The BRDF times the cosine for light from l (world, unit), its diffuse
// and specular parts apart (the lobe-aware filter filters them apart,
// lobe_filter.glsl).
struct SvoForwardSum {
  vec3 diffuse;
  vec3 specular;
};

SVO_FN SvoForwardSum svo_forward_brdf_cos(SvoShadingPoint p, SvoLobe lobe, vec3 l) {
  vec3 ll = vec3(dot(l, p.tx), dot(l, p.ty), dot(l, p.n));
  SvoForwardSum r;
  r.diffuse = vec3(0.0f);
  r.specular = vec3(0.0f);
  float lambert = svo_rough_lambert(p.vl, ll, p.sn2);
  if (lambert > 0.0f) {
    float lambda_l = svo_smith_lambda_dir(ll, p.sn2);
    vec3 a = svo_attribute_vl3(p.abar, p.a_s, p.lambda_v + lambda_l);
    r.diffuse = a * lobe.mat.diffuse * (lambert / SVO_PI) / (1.0f + lambda_l);
  }
  if (lobe.mat.kind != SVO_BRDF_LAMBERT) {
    vec3 ls = svo_to_lobe(lobe, l);
    r.specular = svo_specular_lobe(lobe.mat, svo_to_lobe(lobe, p.v), ls) * max(ls.z, 0.0f);
  }
  return r;
}

SVO_FN float svo_forward_sum_total(SvoForwardSum f) {
  vec3 t = f.diffuse + f.specular;
  return t.x + t.y + t.z;
}

// sum + k f, part by part.
SVO_FN SvoForwardSum svo_forward_madd(SvoForwardSum sum, SvoForwardSum f, vec3 k) {
  SvoForwardSum r;
  r.diffuse = sum.diffuse + k * f.diffuse;
  r.specular = sum.specular + k * f.specular;
  return r;
}

SVO_FN float svo_power_heuristic(float a, float b) {
  float a2 = a * a;
  float b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Whether the environment (or a light) is seen from p along l.
SVO_FN float svo_forward_visible(SvoShadingPoint p, vec3 l, float dist, float spread) {
  return svo_visibility(p.position, l, dist, p.radius, spread, dot(p.n, l), SVO_MODE_PREFILTERED).visible;
}

// The lights' share for one lobe.
SVO_FN SvoForwardSum svo_forward_lights(SvoShadingPoint p, SvoLobe lobe, bool shadows) {
  SvoForwardSum sum;
  sum.diffuse = vec3(0.0f);
  sum.specular = vec3(0.0f);
  for (uint k = 0u; k < params.tree.w; ++k) {
    SvoLightSample light = svo_light_at(k, p.position);
    SvoForwardSum f = svo_forward_brdf_cos(p, lobe, light.l);
    vec3 e = light.e;
    if (svo_forward_sum_total(f) > 0.0f && shadows) e *= svo_forward_visible(p, light.l, light.dist, light.spread);
    sum = svo_forward_madd(sum, f, e);
  }
  return sum;
}

// A material's specular lobes in half-vector space about the normal, as
// up to 3 (sharpness, amplitude) pairs in a vec3 each and their count:
// the microfacet NDFs one lobe (svo_ndf_sharpness), a measured BRDF its SG
// fit (the table at mat.sg_fit: count, then sharpness and amplitude per
// lobe), the Lambert material the diffuse lobe's sharpness.
struct SvoHalfLobes {
  vec3 sharpness;
  vec3 amplitude;
  uint count;
};

SVO_FN SvoHalfLobes svo_material_lobes(SvoMaterial mat) {
  SvoHalfLobes h;
  h.sharpness = vec3(0.0f);
  h.amplitude = vec3(0.0f);
  h.count = 1u;
  h.amplitude.x = 1.0f;
  if (mat.kind == SVO_BRDF_LAMBERT) {
    h.sharpness.x = 2.133f;
  } else if (mat.kind == SVO_BRDF_MERL) {
    uint n = mat.sg_fit != 0u ? min(uint(svo_table(mat.sg_fit) + 0.5f), 3u) : 0u;
    if (n == 0u) {
      h.sharpness.x = 100.0f;  // no fit: a moderately glossy lobe
    } else {
      h.count = n;
      for (uint k = 0u; k < n; ++k) {
        h.sharpness[k] = svo_table(mat.sg_fit + 1u + 2u * k);
        h.amplitude[k] = svo_table(mat.sg_fit + 2u + 2u * k);
      }
    }
  } else {
    h.sharpness.x = svo_ndf_sharpness(mat.kind, mat.alpha2.x, mat.exponent, 0.0f);
  }
  return h;
}

// Adaptive sampling for pre-convolved shading (Bagher et al. 2013, section
// 2.5, Eq. 10): with SVO_SHADE_PRECONVOLVED a measured BRDF is still
// sampled, from its own distribution alone, but each sample reads the map
// pre-convolved at the BRDF's maximum frequency, so that the integrand
// keeps only the frequencies the BRDF passes and fewer samples reach a
// given variance. The price is a bias: the lookup widens the BRDF's
// sharpest lobe (its sharpness halves), measured in docs/RESULTS.md.
//
// The sharpness of the SG kernel that material `mat`'s samples at p read
// the pre-convolved map with: the reflection lobe (svo_reflection_lobe) of
// the sharpest lobe of its SG fit (svo_material_lobes), widened by the
// voxel's slopes as svo_ndf_sharpness widens an NDF. 0, the map read as it
// is, without pre-convolved maps, for the analytic lobes (looked up once
// each, svo_forward_preconvolved) and where the kernel would be sharper
// than the maps' sharpest level.
SVO_FN float svo_filtered_sharpness(SvoShadingPoint p, SvoMaterial mat) {
  if ((shade.sampling.z & SVO_SHADE_PRECONVOLVED) == 0u || mat.kind != SVO_BRDF_MERL) return 0.0f;
  float lh = svo_material_lobes(mat).sharpness.x;
  lh = lh / (1.0f + lh * 0.5f * max(p.sn2.x + p.sn2.y, 0.0f));
  float kappa = svo_reflection_lobe(p.n, p.v, lh).sharpness;
  uint at = floatBitsToUint(shade.env_xform.z);
  float sharpest = svo_table(at + 1u) * exp2(svo_table(at) - 1.0f);
  return kappa <= sharpest ? kappa : 0.0f;
}

// The radiance a sample along l reads: the map pre-convolved at kappa
// (svo_filtered_sharpness), or as it is where kappa is 0.
SVO_FN vec3 svo_env_filtered(vec3 l, float kappa) {
  return kappa > 0.0f ? svo_env_preconvolved(shade, l, kappa) : svo_env_radiance(shade, l);
}

// The directional albedo of the lobe's specular part seen from vs (in
// the lobe's frame): int f_s(v, l) l.z dl by 16 micronormals drawn from
// D(m) m.z on a fixed 4 x 4 stratified grid, the same for every pixel, so
// that it is smooth across the image (a deterministic quadrature; masking,
// shadowing and Fresnel as the sampled pass has them).
SVO_FN vec3 svo_specular_albedo(SvoMaterial mat, vec3 vs) {
  vec3 sum = vec3(0.0f);
  if (!(vs.z > 0.0f)) return sum;
  for (uint k = 0u; k < 16u; ++k) {
    vec3 m = svo_sample_microfacet(mat, vec2((float(k % 4u) + 0.5f) * 0.25f, (float(k / 4u) + 0.5f) * 0.25f));
    float vm = dot(vs, m);
    vec3 l = 2.0f * vm * m - vs;
    float pdf = svo_material_ndf(mat, m) * m.z / max(4.0f * vm, 1.0e-6f);
    if (vm > 0.0f && l.z > 0.0f && pdf > 0.0f) sum += svo_specular_lobe(mat, vs, l) * (l.z / pdf);
  }
  return sum * (1.0f / 16.0f);
}

// Pre-convolved shading (SVO_SHADE_PRECONVOLVED) of one material, times
// `share`, without samples: the diffuse part is the voxel's colour seen
// from the eye (abar with Smith masking) times the albedo times the
// irradiance over pi; the specular part the reflection lobe (the NDF's SG
// widened by the voxel slopes, about reflect(-v, n), svo_reflection_lobe)
// looked up in the environment pre-convolved at its sharpness, times the
// lobe's directional albedo (svo_specular_albedo). With environment
// shadows each part is seen through one cone: the specular along the
// lobe's axis as wide as its deviation, the diffuse along the normal, a
// radian wide. An approximation (the lobe's shape an SG about the mirror
// direction, the diffuse without Smith's masking), measured against the
// sampled pass in tests/gpu/forward_test.cpp. Lights as in the sampled
// pass, through the material's lobe without a drawn slope.
SVO_FN SvoForwardSum svo_forward_preconvolved(SvoShadingPoint p, SvoMaterial mat, float share) {
  bool env_shadows = (shade.sampling.z & SVO_SHADE_ENV_SHADOWS) != 0u;
  SvoLobe frame = svo_sample_lobe(p, mat, vec2(0.0f));  // the voxel slopes added, no slope drawn
  SvoForwardSum r = svo_forward_lights(p, frame, (shade.sampling.z & SVO_SHADE_LIGHT_SHADOWS) != 0u);
  vec3 irradiance = svo_env_irradiance(shade, p.n);
  if (env_shadows && irradiance.x + irradiance.y + irradiance.z > 0.0f)
    irradiance *= svo_forward_visible(p, p.n, 3.0e38f, 1.0f);
  r.diffuse += svo_attribute_vl3(p.abar, p.a_s, p.lambda_v) * mat.diffuse * irradiance;
  if (mat.kind != SVO_BRDF_LAMBERT) {
    float lh = svo_ndf_sharpness(mat.kind, 0.5f * (mat.alpha2.x + mat.alpha2.y), mat.exponent,
                                 0.5f * max(p.sn2.x + p.sn2.y, 0.0f));
    SvoSG lobe = svo_reflection_lobe(p.n, p.v, lh);
    vec3 l = svo_env_preconvolved(shade, lobe.axis, lobe.sharpness);
    if (env_shadows && l.x + l.y + l.z > 0.0f)
      l *= svo_forward_visible(p, lobe.axis, 3.0e38f, min(inversesqrt(max(lobe.sharpness, 1.0f)), 1.0f));
    r.specular += svo_specular_albedo(frame.mat, svo_to_lobe(frame, p.v)) * l;
  }
  r.diffuse *= share;
  r.specular *= share;
  return r;
}

// The share of samples [first, first + count) of the radiance leaving the
// G-buffer point towards the eye, diffuse and specular apart: their sum
// over `spp` samples (the bandwidth-adaptive pass's per-pixel count).
// Pre-convolved (SVO_SHADE_PRECONVOLVED): the whole of it in the share
// holding sample 0, nothing in the others; measured BRDFs are still
// sampled, against the pre-convolved map (svo_filtered_sharpness).
SVO_FN SvoForwardSum svo_forward_samples_of(SvoGBuffer g, uint pixel, uint first, uint count, uint spp) {
  SvoShadingPoint p = svo_shading_point(g);
  SvoMaterial first_material = svo_scene_material(g.material);
  SvoMaterial second_material = svo_scene_material(g.material2);
  bool mixed = g.material != g.material2 && g.material_mix < 1.0f;
  spp = max(spp, 1u);
  uint seed = shade.sampling.y;
  bool env_shadows = (shade.sampling.z & SVO_SHADE_ENV_SHADOWS) != 0u;
  bool light_shadows = (shade.sampling.z & SVO_SHADE_LIGHT_SHADOWS) != 0u;
  SvoForwardSum sum;
  sum.diffuse = vec3(0.0f);
  sum.specular = vec3(0.0f);
  if ((shade.sampling.z & SVO_SHADE_PRECONVOLVED) != 0u && first_material.kind != SVO_BRDF_MERL &&
      second_material.kind != SVO_BRDF_MERL) {
    if (first != 0u) return sum;
    float share = mixed ? clamp(g.material_mix, 0.0f, 1.0f) : 1.0f;
    sum = svo_forward_preconvolved(p, first_material, share);
    if (mixed) {
      SvoForwardSum b = svo_forward_preconvolved(p, second_material, 1.0f - share);
      sum.diffuse += b.diffuse;
      sum.specular += b.specular;
    }
    return sum;
  }
  for (uint i = first; i < min(first + count, spp); ++i) {
    // Where the pixel shows two materials, each sample shades one of them,
    // drawn by its share: the estimate of their mix.
    bool second = mixed && svo_sample_1d(pixel, seed, i, 7u) >= g.material_mix;
    SvoLobe lobe = svo_sample_lobe(p, second ? second_material : first_material, svo_sample_2d(pixel, seed, i, 0u));
    vec3 vs = svo_to_lobe(lobe, p.v);
    SvoForwardSum lit = svo_forward_lights(p, lobe, light_shadows);
    sum.diffuse += lit.diffuse;
    sum.specular += lit.specular;
    // One point of the area light, drawn from its texels (Bagher et al.'s
    // direct sampling of area lights, section 4.3).
    if (shade.area.y != 0u) {
      SvoAreaSample a = svo_area_sample(shade, p.position, svo_sample_2d(pixel, seed, i, 8u));
      if (a.pdf > 0.0f) {
        SvoForwardSum f = svo_forward_brdf_cos(p, lobe, a.l);
        vec3 k = a.radiance / a.pdf;
        if (svo_forward_sum_total(f) > 0.0f && light_shadows) k *= svo_forward_visible(p, a.l, a.dist, 0.0f);
        sum = svo_forward_madd(sum, f, k);
      }
    }
    if (shade.env.y == 0u) continue;
    // A measured BRDF against the pre-convolved map (Eq. 10): the map
    // filtered at kappa, seen through a cone as wide as the kernel, and
    // the BRDF's sample alone, as with SVO_SHADE_BRDF_SAMPLING.
    float kappa = svo_filtered_sharpness(p, lobe.mat);
    float spread = kappa > 0.0f ? min(inversesqrt(kappa), 1.0f) : 0.0f;
    bool brdf_only = kappa > 0.0f || (shade.sampling.z & SVO_SHADE_BRDF_SAMPLING) != 0u;
    // One sample of the material's lobes.
    vec4 b = svo_sample_material(lobe.mat, p.abar, vs,
                                 vec3(svo_sample_2d(pixel, seed, i, 2u), svo_sample_1d(pixel, seed, i, 4u)));
    if (b.w > 0.0f) {
      vec3 l = b.x * lobe.t + b.y * lobe.b + b.z * lobe.n;
      SvoForwardSum f = svo_forward_brdf_cos(p, lobe, l);
      if (svo_forward_sum_total(f) > 0.0f) {
        float w = brdf_only ? 1.0f : svo_power_heuristic(b.w, svo_env_pdf(shade, l));
        vec3 k = svo_env_filtered(l, kappa) * (w / b.w);
        if (env_shadows && k.x + k.y + k.z > 0.0f) k *= svo_forward_visible(p, l, 3.0e38f, spread);
        sum = svo_forward_madd(sum, f, k);
      }
    }
    if (brdf_only) continue;
    // One sample of the environment.
    vec4 e = svo_env_sample(shade, svo_sample_2d(pixel, seed, i, 5u));
    if (e.w > 0.0f) {
      vec3 l = vec3(e);
      SvoForwardSum f = svo_forward_brdf_cos(p, lobe, l);
      if (svo_forward_sum_total(f) > 0.0f) {
        float pb = svo_material_pdf(lobe.mat, p.abar, vs, svo_to_lobe(lobe, l));
        vec3 k = svo_env_filtered(l, kappa) * (svo_power_heuristic(e.w, pb) / e.w);
        if (env_shadows && k.x + k.y + k.z > 0.0f) k *= svo_forward_visible(p, l, 3.0e38f, spread);
        sum = svo_forward_madd(sum, f, k);
      }
    }
  }
  float inv = 1.0f / float(spp);
  sum.diffuse *= inv;
  sum.specular *= inv;
  return sum;
}

// The same over shade.sampling.x samples (the forward pass's).
SVO_FN SvoForwardSum svo_forward_samples(SvoGBuffer g, uint pixel, uint first, uint count) {
  return svo_forward_samples_of(g, pixel, first, count, shade.sampling.x);
}

// The G-buffer texel that texel `low` of an image at 1/scale of the
// frame's size stands for: the one at its centre.
SVO_FN uint svo_scaled_texel(uint low, uint scale) {
  uint lw = (params.image.x + scale - 1u) / scale;
  uint x = min((low % lw) * scale + scale / 2u, params.image.x - 1u);
  uint y = min((low / lw) * scale + scale / 2u, params.image.y - 1u);
  return y * params.image.x + x;
}

// The background's share of pixel `pixel` (`background`: the trace pass's
// share, rgb, and 1 - coverage): the environment seen through the pixel
// centre in place of the constant background.
SVO_FN vec3 svo_forward_background(vec4 background, uint pixel) {
  if (shade.env.y == 0u) return vec3(background);
  vec2 at = vec2(float(pixel % params.image.x) + 0.5f, float(pixel / params.image.x) + 0.5f);
  vec2 ndc = at / vec2(float(params.image.x), float(params.image.y)) * 2.0f - 1.0f;
  vec3 dir = normalize(vec3(params.cam_w) + ndc.x * vec3(params.cam_u) - ndc.y * vec3(params.cam_v));
  return background.w * svo_env_background(shade, dir);
}

// The ambient term of a covered G-buffer point (unweighted by coverage).
SVO_FN vec3 svo_forward_ambient(SvoGBuffer g) {
  SvoShadingPoint p = svo_shading_point(g);
  return vec3(params.ambient) * svo_attribute_vl3(p.abar, p.a_s, p.lambda_v);
}

// The pixel from samples [first, first + count) of shade.sampling.x: the
// surface's share plus the background's (svo_forward_background) plus the
// ambient term; `previous`, what the earlier samples gave, when first > 0.
// A host may run the samples in one call or in several (lavapipe stops
// every loop of an invocation once their iterations together pass 65535:
// llvmpipe's loop limiter, LP_MAX_TGSI_LOOP_ITERATIONS).
SVO_FN vec4 svo_forward_texel(SvoGBuffer g, vec4 background, uint pixel, uint first, uint count, vec4 previous) {
  vec4 sum = previous;
  if (first == 0u) {
    sum = vec4(svo_forward_background(background, pixel), 0.0f);
    if (g.coverage > 0.0f) sum += g.coverage * vec4(svo_forward_ambient(g), 1.0f);
  }
  if (!(g.coverage > 0.0f)) return sum;
  SvoForwardSum f = svo_forward_samples(g, pixel, first, count);
  return sum + vec4(g.coverage * (f.diffuse + f.specular), 0.0f);
}

// The same with the surface's diffuse part (the ambient term included) and
// specular part apart, each times coverage, coverage in w, and nothing of
// the background (the lobe-aware filter adds it after filtering the two).
struct SvoForwardSplit {
  vec4 diffuse;
  vec4 specular;
};

SVO_FN SvoForwardSplit svo_forward_split_texel(SvoGBuffer g, uint pixel, uint first, uint count,
                                               SvoForwardSplit previous) {
  SvoForwardSplit sum = previous;
  if (first == 0u) {
    sum.diffuse = vec4(0.0f);
    sum.specular = vec4(0.0f);
    if (g.coverage > 0.0f) {
      sum.diffuse = g.coverage * vec4(svo_forward_ambient(g), 1.0f);
      sum.specular = vec4(0.0f, 0.0f, 0.0f, g.coverage);
    }
  }
  if (!(g.coverage > 0.0f)) return sum;
  SvoForwardSum f = svo_forward_samples(g, pixel, first, count);
  sum.diffuse += vec4(g.coverage * f.diffuse, 0.0f);
  sum.specular += vec4(g.coverage * f.specular, 0.0f);
  return sum;
}

#endif
