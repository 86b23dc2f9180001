// MERL measured BRDFs (Matusik et al. 2003, "A Data-Driven Reflectance
// Model"; DESIGN 10.2): evaluation from the database's table, nearest sample
// as the reference code BRDFRead.cpp looks it up, and tabulated importance
// sampling by numerical inversion of the BRDF's cumulative distribution
// (Bagher et al. 2013, section 3.3). Host contract: distribution.glsl's
// (`float svo_table(uint i)`). Directions are unit vectors in the local frame
// of the surface (normal +z), both pointing away from it: wi towards the
// light, wo towards the viewer.
//
// The values at table offset o (render::append_merl_tables): RGB interleaved,
// 3 floats per sample, sample k = phi_d + 180 (theta_d + 90 theta_h) (phi_d
// fastest, as in the files), already multiplied by the MERL scales, missing
// samples 0.
// The sampling tables at offset s: SVO_MERL_BINS distributions of
// SVO_MERL_NU x SVO_MERL_NV cells (distribution.glsl's layout), one per
// elevation bin of wo, over (u, v) = ((phi_i - phi_o) / 2 pi, theta_i / (pi/2))
// of the luminance of f cos(theta_i) sin(theta_i), floored so that every
// direction of the upper hemisphere has pdf > 0.
#ifndef SVO_MERL_GLSL
#define SVO_MERL_GLSL
#include "distribution.glsl"

SVO_CONST uint SVO_MERL_THETA_H = 90u;
SVO_CONST uint SVO_MERL_THETA_D = 90u;
SVO_CONST uint SVO_MERL_PHI_D = 180u;
SVO_CONST uint SVO_MERL_BINS = 32u;  // elevation bins of wo in [0, pi/2]
SVO_CONST uint SVO_MERL_NU = 64u;    // cells of phi_i - phi_o in [0, 2 pi)
SVO_CONST uint SVO_MERL_NV = 32u;    // cells of theta_i in [0, pi/2]
// Sampled and looked-up elevations keep this margin (radians) from the pole,
// so that the solid-angle pdf (a 1/sin(theta) Jacobian) stays finite there;
// sampled ones keep it from the horizon too, so that their cos(theta) > 0.
SVO_CONST float SVO_MERL_MIN_THETA = 1.0e-5f;

// Half/difference angles (Rusinkiewicz 1998) as the reference code computes
// them (std_coords_to_half_diff_coords): theta_h the elevation of the half
// vector h; theta_d, phi_d the elevation and azimuth of wi in the frame of h
// (wi rotated by -phi_h about the normal, then by -theta_h about the
// binormal). phi_d in [-pi, pi]. wi + wo must not vanish.
struct SvoMerlAngles {
  float theta_h;
  float theta_d;
  float phi_d;
};

SVO_FN SvoMerlAngles svo_merl_angles(vec3 wi, vec3 wo) {
  vec3 i = normalize(wi);
  vec3 h = normalize(i + normalize(wo));
  float r = length(vec2(h.x, h.y));      // sin(theta_h); cos(theta_h) = h.z
  float cp = r > 0.0f ? h.x / r : 1.0f;  // cos(phi_h) (phi_h = atan2(0, 0) = 0 at the pole)
  float sp = r > 0.0f ? h.y / r : 0.0f;
  float tx = i.x * cp + i.y * sp;
  float ty = i.y * cp - i.x * sp;
  vec3 d = vec3(tx * h.z - i.z * r, ty, i.z * h.z + tx * r);
  float dr = length(vec2(d.x, d.y));
  SvoMerlAngles a;
  a.theta_h = atan(r, h.z);
  a.theta_d = atan(dr, d.z);
  a.phi_d = dr > 0.0f ? atan(d.y, d.x) : 0.0f;
  return a;
}

// The sample index of the angles, as lookup_brdf_val computes it: theta_h
// through the square-root mapping (index floor(90 sqrt(theta_h / (pi/2)))),
// theta_d and phi_d linear, phi_d folded to [0, pi) by reciprocity, each
// truncated (nearest sample below) and clamped to the table.
SVO_FN uint svo_merl_index(SvoMerlAngles a) {
  float th = a.theta_h <= 0.0f ? 0.0f : sqrt(a.theta_h / (0.5f * SVO_PI) * 90.0f * 90.0f);
  uint ih = uint(clamp(th, 0.0f, float(SVO_MERL_THETA_H - 1u)));
  uint id = uint(clamp(a.theta_d / (0.5f * SVO_PI) * 90.0f, 0.0f, float(SVO_MERL_THETA_D - 1u)));
  float pd = a.phi_d < 0.0f ? a.phi_d + SVO_PI : a.phi_d;
  uint ip = uint(clamp(pd / SVO_PI * float(SVO_MERL_PHI_D), 0.0f, float(SVO_MERL_PHI_D - 1u)));
  return ip + SVO_MERL_PHI_D * (id + SVO_MERL_THETA_D * ih);
}

// The BRDF (1/sr, RGB) of the table at o for light from wi seen from wo; 0
// when either direction is at or below the surface.
SVO_FN vec3 svo_merl_eval(uint o, vec3 wi, vec3 wo) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return vec3(0.0f);
  uint k = o + 3u * svo_merl_index(svo_merl_angles(wi, wo));
  return vec3(svo_table(k), svo_table(k + 1u), svo_table(k + 2u));
}

// The elevation bin of wo (the sampling distribution that serves it).
SVO_FN uint svo_merl_bin(vec3 wo) {
  float t = atan(length(vec2(wo.x, wo.y)), wo.z);
  return uint(clamp(t / (0.5f * SVO_PI) * float(SVO_MERL_BINS), 0.0f, float(SVO_MERL_BINS - 1u)));
}

// The azimuth of w in (-pi, pi], 0 at the pole.
SVO_FN float svo_merl_azimuth(vec3 w) { return (w.x != 0.0f || w.y != 0.0f) ? atan(w.y, w.x) : 0.0f; }

// The solid-angle density (1/sr) with which svo_merl_sample(s, wo, .) draws
// wi; 0 when either direction is at or below the surface, > 0 (and finite)
// everywhere above it.
SVO_FN float svo_merl_pdf(uint s, vec3 wo, vec3 wi) {
  if (!(wi.z > 0.0f) || !(wo.z > 0.0f)) return 0.0f;
  float rel = (svo_merl_azimuth(wi) - svo_merl_azimuth(wo)) * (0.5f / SVO_PI);
  rel = rel - floor(rel);
  float theta = max(atan(length(vec2(wi.x, wi.y)), wi.z), SVO_MERL_MIN_THETA);
  uint o = s + svo_merl_bin(wo) * svo_dist2d_floats(SVO_MERL_NU, SVO_MERL_NV);
  float p = svo_dist2d_pdf(o, SVO_MERL_NU, SVO_MERL_NV, vec2(rel, theta / (0.5f * SVO_PI)));
  // (u, v) covers [0, 2 pi) x [0, pi/2]: d omega = sin(theta) (pi^2) du dv.
  return p / (SVO_PI * SVO_PI * sin(theta));
}

// A direction wi drawn for wo with uniform u (xyz), and its solid-angle pdf
// (w, exactly svo_merl_pdf(s, wo, wi)). For wo at or below the surface:
// (0, 0, 1) with pdf 0.
SVO_FN vec4 svo_merl_sample(uint s, vec3 wo, vec2 u) {
  if (!(wo.z > 0.0f)) return vec4(0.0f, 0.0f, 1.0f, 0.0f);
  uint o = s + svo_merl_bin(wo) * svo_dist2d_floats(SVO_MERL_NU, SVO_MERL_NV);
  vec3 p = svo_dist2d_sample(o, SVO_MERL_NU, SVO_MERL_NV, u);
  float phi = svo_merl_azimuth(wo) + 2.0f * SVO_PI * p.x;
  float theta = clamp(p.y * (0.5f * SVO_PI), SVO_MERL_MIN_THETA, 0.5f * SVO_PI - SVO_MERL_MIN_THETA);
  float st = sin(theta);
  vec3 wi = vec3(st * cos(phi), st * sin(phi), cos(theta));
  return vec4(wi, svo_merl_pdf(s, wo, wi));
}

#endif
