// Materials (DESIGN section 10.2): a diffuse part tinted by the voxels' abar
// plus one specular lobe: Beckmann or GGX microfacets (Cook-Torrance with
// Schlick's Fresnel and height-correlated Smith masking), the Phong NDF with
// Kelemen & Szirmay-Kalos's visibility term, or a measured BRDF (merl.glsl).
// Evaluation, importance sampling and pdf, in a local frame whose z is the
// lobe's normal. Host contract: distribution.glsl's (svo_table), and
// `shade` (SvoShadeParams) for svo_scene_material.
#ifndef SVO_MATERIAL_GLSL
#define SVO_MATERIAL_GLSL
#include "beckmann.glsl"
#include "merl.glsl"
#include "shade_params.glsl"
#include "smith.glsl"

// Material `index` of the scene (the G-buffer's material indices), read from
// the table SvoShadeParams points at; the parameters' own material where
// there is no table (one material for the whole frame).
SVO_FN SvoMaterial svo_scene_material(uint index) {
  if (shade.material.w == 0u) return svo_material_of(shade);
  uint at = shade.sampling.w + min(index, shade.material.w - 1u) * SVO_MATERIAL_FLOATS;
  SvoMaterial m;
  m.kind = floatBitsToUint(svo_table(at));
  m.merl = floatBitsToUint(svo_table(at + 1u));
  m.merl_sampling = floatBitsToUint(svo_table(at + 2u));
  m.exponent = svo_table(at + 3u);
  m.diffuse = vec3(svo_table(at + 4u), svo_table(at + 5u), svo_table(at + 6u));
  float alpha = svo_table(at + 7u);
  m.alpha2 = vec2(alpha * alpha);
  m.f0 = vec3(svo_table(at + 8u), svo_table(at + 9u), svo_table(at + 10u));
  m.sg_fit = floatBitsToUint(svo_table(at + 11u));
  return m;
}

SVO_FN float svo_luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// Schlick's approximation of the Fresnel reflectance at cos(theta) = c.
SVO_FN vec3 svo_fresnel_schlick(vec3 f0, float c) {
  float m = clamp(1.0f - c, 0.0f, 1.0f);
  float m2 = m * m;
  return f0 + (vec3(1.0f) - f0) * (m2 * m2 * m);
}

// GGX (Trowbridge-Reitz) NDF with squared roughness a2 per axis; int D m.z = 1.
SVO_FN float svo_ggx_d(vec3 m, vec2 a2) {
  if (!(m.z > 0.0f)) return 0.0f;
  vec2 s = max(a2, vec2(1.0e-7f));
  float k = m.x * m.x / s.x + m.y * m.y / s.y + m.z * m.z;
  return 1.0f / (SVO_PI * sqrt(s.x * s.y) * k * k);
}

// Smith's Lambda of the GGX NDF for direction w.
SVO_FN float svo_ggx_lambda(vec3 w, vec2 a2) {
  float z2 = w.z * w.z;
  if (!(z2 > 0.0f)) return 3.0e38f;
  float t = (a2.x * w.x * w.x + a2.y * w.y * w.y) / z2;
  return 0.5f * (sqrt(1.0f + t) - 1.0f);
}

// The Phong NDF (e + 2) / (2 pi) cos^e; int D m.z = 1.
SVO_FN float svo_phong_d(vec3 m, float e) {
  if (!(m.z > 0.0f)) return 0.0f;
  return (e + 2.0f) / (2.0f * SVO_PI) * pow(m.z, e);
}

// The NDF of the material's lobe at micronormal m.
SVO_FN float svo_material_ndf(SvoMaterial mat, vec3 m) {
  if (mat.kind == SVO_BRDF_BECKMANN) return svo_beckmann_d(m, max(0.5f * mat.alpha2, vec2(SVO_MIN_SLOPE_VARIANCE)));
  if (mat.kind == SVO_BRDF_GGX) return svo_ggx_d(m, mat.alpha2);
  return svo_phong_d(m, mat.exponent);
}

// The specular lobe f_s(v, l) (no cosine); 0 where v or l is at or below the plane.
SVO_FN vec3 svo_specular_lobe(SvoMaterial mat, vec3 v, vec3 l) {
  if (!(v.z > 0.0f) || !(l.z > 0.0f)) return vec3(0.0f);
  if (mat.kind == SVO_BRDF_LAMBERT) return vec3(0.0f);
  if (mat.kind == SVO_BRDF_MERL) return svo_merl_eval(mat.merl, l, v);
  vec3 h = v + l;
  float hl = length(h);
  if (!(hl > 0.0f)) return vec3(0.0f);
  h = h / hl;
  float vh = max(dot(v, h), 0.0f);
  vec3 f = svo_fresnel_schlick(mat.f0, vh);
  if (mat.kind == SVO_BRDF_PHONG) {
    // Kelemen & Szirmay-Kalos 2001: G / (n.v n.l) ~ 1 / (h.l)^2.
    return f * (svo_phong_d(h, mat.exponent) / (4.0f * max(vh * vh, 1.0e-4f)));
  }
  float g2;
  float d;
  if (mat.kind == SVO_BRDF_BECKMANN) {
    vec2 s2 = max(0.5f * mat.alpha2, vec2(SVO_MIN_SLOPE_VARIANCE));
    d = svo_beckmann_d(h, s2);
    g2 = svo_smith_g2(svo_smith_lambda_dir(v, s2), svo_smith_lambda_dir(l, s2));
  } else {
    d = svo_ggx_d(h, mat.alpha2);
    g2 = 1.0f / (1.0f + svo_ggx_lambda(v, mat.alpha2) + svo_ggx_lambda(l, mat.alpha2));
  }
  return f * (d * g2 / (4.0f * v.z * l.z));
}

// The whole BRDF of a flat point of colour `tint` (the reference's, and the
// furnace and reciprocity tests'): tint diffuse / pi plus the lobe.
SVO_FN vec3 svo_material_brdf(SvoMaterial mat, vec3 tint, vec3 v, vec3 l) {
  if (!(v.z > 0.0f) || !(l.z > 0.0f)) return vec3(0.0f);
  return tint * mat.diffuse * (1.0f / SVO_PI) + svo_specular_lobe(mat, v, l);
}

// A micronormal drawn from the lobe's D(m) m.z with uniform u.
SVO_FN vec3 svo_sample_microfacet(SvoMaterial mat, vec2 u) {
  float phi = 2.0f * SVO_PI * u.y;
  if (mat.kind == SVO_BRDF_PHONG) {
    float c = pow(max(u.x, 1.0e-30f), 1.0f / (mat.exponent + 2.0f));
    float s = sqrt(max(1.0f - c * c, 0.0f));
    return vec3(s * cos(phi), s * sin(phi), c);
  }
  // Slopes: Gaussian (Beckmann, variance alpha^2 / 2 per axis) or the
  // GGX slope density 1 / (pi (1 + r^2)^2) scaled per axis.
  float r = mat.kind == SVO_BRDF_BECKMANN ? sqrt(-log(max(1.0f - u.x, 1.0e-30f)))
                                          : sqrt(u.x / max(1.0f - u.x, 1.0e-30f));
  vec2 slope = r * vec2(cos(phi), sin(phi)) * sqrt(mat.alpha2);
  return normalize(vec3(-slope.x, -slope.y, 1.0f));
}

// Probability of picking the specular lobe over the diffuse one for view v.
SVO_FN float svo_specular_share(SvoMaterial mat, vec3 tint, vec3 v) {
  if (mat.kind == SVO_BRDF_LAMBERT) return 0.0f;
  float ws = mat.kind == SVO_BRDF_MERL ? 0.5f : svo_luminance(svo_fresnel_schlick(mat.f0, max(v.z, 0.0f)));
  float wd = svo_luminance(tint * mat.diffuse);
  if (!(wd > 0.0f)) return 1.0f;
  return clamp(ws / (ws + wd), 0.1f, 0.9f);
}

// The solid-angle density of svo_sample_material's directions at l.
SVO_FN float svo_material_pdf(SvoMaterial mat, vec3 tint, vec3 v, vec3 l) {
  if (!(v.z > 0.0f) || !(l.z > 0.0f)) return 0.0f;
  float ps = svo_specular_share(mat, tint, v);
  float pdf = (1.0f - ps) * l.z / SVO_PI;
  if (ps > 0.0f) {
    if (mat.kind == SVO_BRDF_MERL) {
      pdf += ps * svo_merl_pdf(mat.merl_sampling, v, l);
    } else {
      vec3 h = normalize(v + l);
      float vh = dot(v, h);
      if (vh > 0.0f) pdf += ps * svo_material_ndf(mat, h) * h.z / (4.0f * vh);
    }
  }
  return pdf;
}

// A direction for view v (uniform u: xy the direction, z the lobe) and its
// density (w; 0: no direction).
SVO_FN vec4 svo_sample_material(SvoMaterial mat, vec3 tint, vec3 v, vec3 u) {
  if (!(v.z > 0.0f)) return vec4(0.0f);
  float ps = svo_specular_share(mat, tint, v);
  vec3 l;
  if (u.z < ps) {
    if (mat.kind == SVO_BRDF_MERL) {
      l = vec3(svo_merl_sample(mat.merl_sampling, v, vec2(u)));
    } else {
      vec3 m = svo_sample_microfacet(mat, vec2(u));
      l = 2.0f * dot(v, m) * m - v;
    }
  } else {
    float r = sqrt(u.x);
    float phi = 2.0f * SVO_PI * u.y;
    l = vec3(r * cos(phi), r * sin(phi), sqrt(max(1.0f - u.x, 0.0f)));
  }
  if (!(l.z > 0.0f)) return vec4(0.0f);
  return vec4(l, svo_material_pdf(mat, tint, v, l));
}

#endif
