// The bandwidth-adaptive pass's kernels (Bagher et al. 2013, DESIGN 10.3;
// render::AdaptivePass): the bandwidth buffer from the G-buffer (section
// 3.1), its min- and max-filtered mips, and shading coarse to fine with
// bilateral upsampling (section 3.2, Fig. 8). Host contract: forward.glsl's
// (params, the octree, `shade`, svo_table), plus `adapt`
// (SvoAdaptiveParams) and svo_bw_table (the bandwidth tables: the
// environment's angular bandwidth map and the BRDFs' tables, built by
// render/src/bandwidth.cpp); for the shading kernels also
// svo_adaptive_gbuffer(pixel) (a G-buffer texel), svo_adaptive_bandwidth(level,
// q) and svo_adaptive_pyramid(level, q) (texels of the two pyramids).
#ifndef SVO_BANDWIDTH_GLSL
#define SVO_BANDWIDTH_GLSL
#include "bandwidth_ops.glsl"
#include "forward.glsl"

// The side of a pixel in radians (the paper's f_x / W): the tracer's pixel
// cone has the pixel's area, radius eye.w per unit distance.
SVO_FN float svo_bw_pixel_angle() { return params.eye.w * sqrt(SVO_PI); }

// The environment's angular bandwidth towards d (cycles per radian), 0
// without a map (the tables' map has the environment's layout, coarser).
SVO_FN float svo_bw_environment(vec3 d) {
  if (adapt.tables.z == 0u) return 0.0f;
  vec2 uv = svo_env_uv(shade, d);
  uint x = min(uint(uv.x * float(adapt.tables.y)), adapt.tables.y - 1u);
  uint y = min(uint(uv.y * float(adapt.tables.z)), adapt.tables.z - 1u);
  return svo_bw_table(adapt.tables.x + y * adapt.tables.y + x);
}

// The area light's spatial bandwidth (cycles per scene unit, on its plane)
// at uv (svo_area_sample's), 0 without the grid.
SVO_FN float svo_bw_area(vec2 uv) {
  if (adapt.area.z == 0u) return 0.0f;
  return svo_bw_table(adapt.area.x + svo_grid_cell(uv, adapt.area.y, adapt.area.z));
}

// The BRDF's angular bandwidth (cycles per radian) for light from ll seen
// from vl, both in the lobe's frame: the nearest entry of material
// `index`'s table (render::brdf_bandwidth), 16 view elevations x 16 x 16
// light directions on the equal-area disk, azimuth relative to the view's.
SVO_FN float svo_bw_brdf(uint index, vec3 ll, vec3 vl) {
  if (adapt.frame.y == 0u) return SVO_BW_INFINITE;
  uint m = min(index, adapt.frame.y - 1u);
  float tv = acos(clamp(vl.z, 0.0f, 1.0f)) * (2.0f / SVO_PI);
  uint i = min(uint(tv * 16.0f), 15u);
  float phi = svo_atan2(ll.y, ll.x) - svo_atan2(vl.y, vl.x);
  float r = sqrt(2.0f) * sin(0.5f * acos(clamp(ll.z, 0.0f, 1.0f)));
  vec2 xy = (r * vec2(cos(phi), sin(phi)) + 1.0f) * 8.0f;
  uint c = min(uint(max(xy.x, 0.0f)), 15u);
  uint row = min(uint(max(xy.y, 0.0f)), 15u);
  return svo_bw_table(adapt.tables.w + m * 4096u + (i * 16u + row) * 16u + c);
}

// The curvature (1 / scene units) between a pixel and its neighbour, the
// angle between their normals over their distance; -1 where the neighbour
// shows no surface.
SVO_FN float svo_bw_curvature_to(SvoGBuffer g, vec3 n, SvoGBuffer o) {
  if (!(o.coverage > 0.0f)) return -1.0f;
  float nl = length(o.normal);
  if (!(nl > 0.0f)) return -1.0f;
  float dist = length(o.position - g.position);
  if (!(dist > 0.0f)) return 0.0f;
  float cosine = clamp(dot(n, o.normal / nl), -1.0f, 1.0f);
  return acos(cosine) / dist;
}

// The smaller of the two sides' curvatures along one axis (a depth
// discontinuity on one side does not count), 0 where neither shows a surface.
SVO_FN float svo_bw_axis_curvature(SvoGBuffer g, vec3 n, SvoGBuffer a, SvoGBuffer b) {
  float ca = svo_bw_curvature_to(g, n, a);
  float cb = svo_bw_curvature_to(g, n, b);
  if (ca < 0.0f) return max(cb, 0.0f);
  if (cb < 0.0f) return ca;
  return min(ca, cb);
}

// The spatial bandwidth of the voxels' colour seen at the pixel, in cycles
// per pixel: the luminance gradient of abar (central differences) over 2 pi
// times the local amplitude (half the range of the five texels); 0 where
// the range is under 1% of the mean (Eq. 7's epsilon), at most 1/2.
SVO_FN float svo_bw_texture(SvoGBuffer g, SvoGBuffer x0, SvoGBuffer x1, SvoGBuffer y0, SvoGBuffer y1) {
  float c = svo_luminance(g.abar);
  float a0 = x0.coverage > 0.0f ? svo_luminance(x0.abar) : c;
  float a1 = x1.coverage > 0.0f ? svo_luminance(x1.abar) : c;
  float b0 = y0.coverage > 0.0f ? svo_luminance(y0.abar) : c;
  float b1 = y1.coverage > 0.0f ? svo_luminance(y1.abar) : c;
  float hi = max(max(max(a0, a1), max(b0, b1)), c);
  float lo = min(min(min(a0, a1), min(b0, b1)), c);
  float mean = 0.2f * (c + a0 + a1 + b0 + b1);
  if (!(hi - lo > 0.01f * mean)) return 0.0f;
  float grad = length(vec2(a1 - a0, b1 - b0)) * 0.5f;
  return min(grad / (SVO_PI * (hi - lo)), 0.5f);
}

// The bandwidth buffer's texel (section 3.1) for G-buffer texel `pixel`
// and its four neighbours: x the level at which it may be shaded (Eq. 6,
// 11, unfloored: log2(1 / (2 b_p)) within [0, coarsest]), y its sample
// count N_p (Eq. 9: the variance bound over n_b directions, or with
// SVO_ADAPTIVE_MEASURED their sample variance halved (a forward sample
// draws two directions), aiming at tau (L + 0.01)^2, the per-pixel relMSE
// of svo compare), z that bound for one sample relative to (L + 0.01)^2 (L
// the pixel's luminance as the n_b directions estimate it), w the
// screen-space curvature (radians per pixel). The n_b directions are drawn
// from the environment and the BRDF (one-sample mixture, density the
// average of the two; the BRDF alone with SVO_SHADE_BRDF_SAMPLING, whose
// samples draw one direction), weighted by lambda_i = L_i rho cos / pdf (Eq. 5, so
// that the weighted mean estimates the integral's); the lights count as
// directions of unbounded angular bandwidth in Eq. 5 and add no variance
// (every sample evaluates them). The area light adds n_b directions of
// its own, drawn as a sample draws its point (svo_area_sample): its light
// leaves with the texture's spatial bandwidth over the ray's cosine and
// none angular, and is transported to the point (Eq. 4, T_d with d the
// distance; Bagher et al. section 4.3); its estimator's variance adds to
// the environment's (a sample draws one point of it besides its
// directions). With the pre-convolved map, a measured
// BRDF's directions are drawn from it alone and read the map filtered at
// kappa (Eq. 10: the light's band is at most the kernel's; the measured
// variance is of one such direction, as a sample draws one), and the
// analytic lobes, looked up once, add no variance.
// Without a surface: the coarsest level, no samples (svo_bandwidth_pixel
// then sets silhouettes to level 0).
SVO_FN vec4 svo_bandwidth_texel(SvoGBuffer g, SvoGBuffer x0, SvoGBuffer x1, SvoGBuffer y0, SvoGBuffer y1, uint pixel) {
  uint coarsest = adapt.config.w;
  if (!(g.coverage > 0.0f)) return vec4(float(coarsest), 0.0f, 0.0f, 0.0f);
  bool finest = (adapt.config.z & SVO_ADAPTIVE_FINEST) != 0u;
  if (finest) return vec4(0.0f, float(max(shade.sampling.x, 1u)), 0.0f, 0.0f);
  SvoShadingPoint p = svo_shading_point(g);
  SvoMaterial mat = svo_scene_material(g.material);
  float pixel_angle = svo_bw_pixel_angle();
  float curvature = max(svo_bw_axis_curvature(g, p.n, x0, x1), svo_bw_axis_curvature(g, p.n, y0, y1));
  float cos_x = max(dot(p.n, p.v), SVO_BW_MIN_COS);
  // The texture's bandwidth per scene unit on the surface: a pixel spans
  // pixel_angle depth / cos_x along the surface's tilt.
  float t = svo_bw_texture(g, x0, x1, y0, y1) * cos_x / max(pixel_angle * g.depth, 1.0e-30f);
  float slope_rho =
      (adapt.config.z & SVO_ADAPTIVE_SLOPE_LIMIT) != 0u ? svo_bw_slope_limit(min(p.sn2.x, p.sn2.y)) : SVO_BW_INFINITE;
  // The lobe about the mean normal (u = 0: no slope drawn for the Phong and
  // measured lobes; the microfacet ones widen by the voxel's slopes).
  SvoLobe lobe = svo_sample_lobe(p, mat, vec2(0.0f));
  vec3 vs = svo_to_lobe(lobe, p.v);
  // A measured BRDF against the pre-convolved map (Eq. 10,
  // svo_filtered_sharpness): its samples alone, of the map filtered at
  // kappa, whose band is at most the kernel's.
  float kappa = svo_filtered_sharpness(p, mat);
  float kernel_limit = svo_bw_sg_limit(kappa);
  bool brdf_only = kappa > 0.0f || (shade.sampling.z & SVO_SHADE_BRDF_SAMPLING) != 0u;
  uint nb = max(adapt.config.x, 1u);
  uint seed = shade.sampling.y ^ 0x5bd1e995u;
  float sum_lambda = 0.0f;
  float sum_nu = 0.0f;
  float sum_var = 0.0f;
  float sum_x = 0.0f;  // the n_b directions' estimates chi / pdf, and their squares
  float sum_x2 = 0.0f;
  float sum_a = 0.0f;  // the same of the area light's n_b points
  float sum_a2 = 0.0f;
  uint lights = nb + params.tree.w;
  uint na = shade.area.y != 0u ? nb : 0u;
  for (uint i = 0u; i < lights + na; ++i) {
    vec3 l;
    float pdf = 1.0f;
    vec3 radiance;
    float nu_light;          // the light's angular bandwidth at the point
    vec2 nu_l = vec2(0.0f);  // and as it leaves the light, over distance d_l
    float d_l = 0.0f;
    if (i < nb) {
      if (shade.env.y == 0u) continue;
      vec2 u = svo_sample_2d(pixel, seed, i, 0u);
      bool from_env = !brdf_only && svo_sample_1d(pixel, seed, i, 2u) < 0.5f;
      if (from_env) {
        vec4 e = svo_env_sample(shade, u);
        if (!(e.w > 0.0f)) continue;
        l = vec3(e);
      } else {
        vec4 b = svo_sample_material(lobe.mat, p.abar, vs, vec3(u, svo_sample_1d(pixel, seed, i, 3u)));
        if (!(b.w > 0.0f)) continue;
        l = b.x * lobe.t + b.y * lobe.b + b.z * lobe.n;
      }
      pdf = svo_material_pdf(lobe.mat, p.abar, vs, svo_to_lobe(lobe, l));
      if (!brdf_only) pdf = 0.5f * (svo_env_pdf(shade, l) + pdf);
      if (!(pdf > 0.0f)) continue;
      radiance = svo_env_filtered(l, kappa);
      nu_light = min(svo_bw_environment(l), kernel_limit);
      nu_l.y = nu_light;
    } else if (i < lights) {
      SvoLightSample light = svo_light_at(i - nb, p.position);
      l = light.l;
      radiance = light.e;
      nu_light = SVO_BW_INFINITE;
      nu_l.y = nu_light;
    } else {
      SvoAreaSample a = svo_area_sample(shade, p.position, svo_sample_2d(pixel, seed, i - lights, 4u));
      if (!(a.pdf > 0.0f)) continue;
      l = a.l;
      pdf = a.pdf;
      radiance = a.radiance;
      nu_l = svo_bw_outgoing(vec2(svo_bw_area(a.uv), 0.0f), a.cos_l);
      d_l = a.dist;
      nu_light = svo_bw_transport(nu_l, d_l).y;
    }
    float cos_i = dot(l, p.n);
    if (!(cos_i > 0.0f)) continue;
    SvoForwardSum f = svo_forward_brdf_cos(p, lobe, l);
    float chi = svo_luminance(radiance * (f.diffuse + f.specular));
    if (!(chi > 0.0f)) continue;
    vec3 ll = svo_to_lobe(lobe, l);
    float rho = min(svo_bw_brdf(g.material, ll, vs), slope_rho);
    vec2 nu = svo_bw_one_bounce(nu_l, d_l, g.depth, curvature, cos_i, cos_x, t, rho);
    // Monte Carlo weights: lambda_i / pdf for the n_b directions and the
    // area light's n_b points, the lights' (deltas) as they are, each over
    // its count.
    bool lamp = i >= nb && i < lights;
    float w = lamp ? 1.0f : 1.0f / (pdf * float(nb));
    sum_lambda += w * chi;
    sum_nu += w * chi * nu.y;
    // The lights are evaluated, not sampled: no variance.
    if (!lamp) sum_var += w * svo_bw_variance_term(nu_light, rho, chi);
    if (i < nb) {
      sum_x += chi / pdf;
      sum_x2 += (chi / pdf) * (chi / pdf);
    } else if (!lamp) {
      sum_a += chi / pdf;
      sum_a2 += (chi / pdf) * (chi / pdf);
    }
  }
  float nu_a = sum_lambda > 0.0f ? sum_nu / sum_lambda : 0.0f;
  float b_p = svo_bw_image(nu_a, pixel_angle);
  // Nyquist: the image must be sampled at twice its bandwidth, 2 b_p (the
  // spectrum spans [-b_p, b_p]); Eq. 11 of that rate.
  // x holds log2(1 / (2 b_p)) within [0, coarsest], unfloored, so that b_p
  // can be read back; its floor is svo_bw_level's (readers floor it).
  float level = b_p > 0.0f ? clamp(log2(0.5f / b_p), 0.0f, float(coarsest)) : float(coarsest);
  float norm = (sum_lambda + 0.01f) * (sum_lambda + 0.01f);
  float rel = 4.0f * SVO_PI * SVO_PI * sum_var / norm;
  if ((adapt.config.z & SVO_ADAPTIVE_MEASURED) != 0u) {
    // The variance of one mixture sample, from the n_b directions; a
    // forward sample takes two (one from the BRDF, one from the map), or
    // one from the BRDF alone.
    float mean = sum_x / float(nb);
    rel = (brdf_only ? 1.0f : 0.5f) * max(sum_x2 / float(nb) - mean * mean, 0.0f) / norm;
    float mean_a = sum_a / float(nb);
    if (na > 0u) rel += max(sum_a2 / float(nb) - mean_a * mean_a, 0.0f) / norm;
  }
  // The analytic lobes against the pre-convolved map: one lookup each
  // (svo_forward_preconvolved), whatever the count.
  if ((shade.sampling.z & SVO_SHADE_PRECONVOLVED) != 0u && mat.kind != SVO_BRDF_MERL &&
      svo_scene_material(g.material2).kind != SVO_BRDF_MERL)
    rel = 0.0f;
  float np = clamp(ceil(rel / max(adapt.quality.x, 1.0e-12f)), max(adapt.quality.z, 1.0f), float(adapt.config.y));
  return vec4(level, np, rel, curvature * pixel_angle * g.depth);
}

// The bandwidth buffer's texel of a pixel of coverage `coverage` from the
// estimate made for it (svo_bandwidth_texel, at the pixel or at the pixel
// of its 2x2 block that the block's estimate was made at): nothing to
// shade without a surface; a silhouette (coverage under 1) at level 0.
SVO_FN vec4 svo_bandwidth_pixel(vec4 estimate, float coverage) {
  if (!(coverage > 0.0f)) return vec4(float(adapt.config.w), 0.0f, 0.0f, 0.0f);
  if (coverage < 0.999f) estimate.x = 0.0f;
  return estimate;
}

// The pixel of block `q` (`side` pixels a side) the block's estimate
// is made at: the most covered, the first of equals (row by row).
SVO_FN uvec2 svo_bandwidth_representative(uvec2 q, uint side) {
  uvec2 best = q * side;
  float most = -1.0f;
  for (uint k = 0u; k < side * side; ++k) {
    uvec2 at = q * side + uvec2(k % side, k / side);
    if (at.x >= params.image.x || at.y >= params.image.y) continue;
    float c = svo_adaptive_gbuffer(at.y * params.image.x + at.x).coverage;
    if (c > most) {
      most = c;
      best = at;
    }
  }
  return best;
}

// Texel `q` of level `level` of the bandwidth pyramid from the four of
// level - 1 it covers (present ones: the pyramid's sides round up): the
// level min-filtered, samples, variance and curvature max-filtered.
SVO_FN vec4 svo_bandwidth_reduce(vec4 a, vec4 b, vec4 c, vec4 d) {
  return vec4(min(min(a.x, b.x), min(c.x, d.x)), max(max(a.y, b.y), max(c.y, d.y)), max(max(a.z, b.z), max(c.z, d.z)),
              max(max(a.w, b.w), max(c.w, d.w)));
}

// The G-buffer pixel that texel (x, y) of level `level` stands for: the
// one at its centre (its top-left one at level 0), clamped to the frame.
SVO_FN uvec2 svo_adaptive_centre(uvec2 q, uint level) {
  uint s = 1u << level;
  return min(q * s + uvec2(s / 2u), uvec2(params.image.x - 1u, params.image.y - 1u));
}

// The radiance of the surface at G-buffer texel `pixel` from `spp`
// samples (diffuse and specular, without the ambient term and coverage).
SVO_FN vec3 svo_adaptive_shade(SvoGBuffer g, uint pixel, uint spp) {
  SvoForwardSum f = svo_forward_samples_of(g, pixel, 0u, spp, spp);
  return f.diffuse + f.specular;
}

// The weight of a parent texel for upsampling (section 3.2): g_z x g_a,
// times the bilinear weight by the caller. `offset`: from the pixel to the
// parent in screen pixels; `spacing`: the parents' spacing in pixels.
// g_z: a Gaussian of the parent's distance from the pixel's tangent plane
// (the depth difference a plane predicts does not count), deviation
// quality.y x spacing x the pixel's footprint; g_a: the anisotropic
// Gaussian narrower by cos theta_x along the screen-projected normal, where
// the surface is foreshortened and the image varies fastest.
SVO_FN float svo_adaptive_weight(SvoShadingPoint p, vec3 parent_position, vec2 offset, float spacing) {
  float footprint = svo_bw_pixel_angle() * length(p.position - vec3(params.eye));
  float sz = max(adapt.quality.y, 1.0e-6f) * spacing * max(footprint, 1.0e-30f);
  float dz = dot(p.n, parent_position - p.position) / sz;
  vec2 sn = vec2(dot(p.n, vec3(params.cam_u)), -dot(p.n, vec3(params.cam_v)));
  float sl = length(sn);
  vec2 e = sl > 1.0e-6f ? sn / sl : vec2(1.0f, 0.0f);
  vec2 v = offset / spacing;
  float along = dot(v, e);
  float across = dot(v, vec2(-e.y, e.x));
  float c = max(dot(p.n, p.v), 0.1f);
  return exp(-dz * dz - along * along / (c * c) - across * across);
}

// The texel size of level `level` of a pyramid over the frame.
SVO_FN uvec2 svo_adaptive_size(uint level) {
  uint s = 1u << level;
  return uvec2((params.image.x + s - 1u) / s, (params.image.y + s - 1u) / s);
}

// Texel `q` of level `level` of the shading pyramid (Fig. 8's pseudo-code),
// the coarser levels done: rgb the surface's radiance at its centre pixel
// (svo_adaptive_shade), alpha its state (SVO_ADAPTIVE_*). Pending where
// part of its pixels must be shaded finer; upsampled from the coarser
// level's computed texels (bilinear weights 9/16, 3/16, 3/16, 1/16 times
// svo_adaptive_weight) where all of them may be coarser; shaded with the
// level's N_p (max-filtered) where its level is this one, or where no
// coarser texel can stand for it (all weights under 1% of the largest).
// With `shade_now` false a texel to shade is only marked (rgb 0): the
// Vulkan host then takes its samples SVO_ADAPTIVE_SLOTS threads at a time
// (svo_adaptive_samples_of).
SVO_FN vec4 svo_adaptive_level_texel(uvec2 q, uint level, bool shade_now) {
  uvec2 c = svo_adaptive_centre(q, level);
  uint pixel = c.y * params.image.x + c.x;
  SvoGBuffer g = svo_adaptive_gbuffer(pixel);
  if (!(g.coverage > 0.0f)) return vec4(0.0f, 0.0f, 0.0f, SVO_ADAPTIVE_EMPTY);
  vec4 bw = svo_adaptive_bandwidth(level, q);
  uint r = uint(bw.x);
  if (r < level) return vec4(0.0f, 0.0f, 0.0f, SVO_ADAPTIVE_PENDING);
  if (r > level && level < adapt.config.w) {
    SvoShadingPoint p = svo_shading_point(g);
    uint up = level + 1u;
    uvec2 size = svo_adaptive_size(up);
    vec2 at = (vec2(q) + 0.5f) * 0.5f - 0.5f;
    vec2 base = floor(at);
    vec2 f = at - base;
    vec3 sum = vec3(0.0f);
    float wsum = 0.0f;
    for (uint k = 0u; k < 4u; ++k) {
      uvec2 d = uvec2(k & 1u, k >> 1u);
      ivec2 pq = ivec2(base) + ivec2(d);
      if (pq.x < 0 || pq.y < 0 || uint(pq.x) >= size.x || uint(pq.y) >= size.y) continue;
      vec4 a = svo_adaptive_pyramid(up, uvec2(pq));
      if (a.w != SVO_ADAPTIVE_SHADED && a.w != SVO_ADAPTIVE_UPSAMPLED) continue;
      float bil = (d.x == 1u ? f.x : 1.0f - f.x) * (d.y == 1u ? f.y : 1.0f - f.y);
      uvec2 pc = svo_adaptive_centre(uvec2(pq), up);
      SvoGBuffer pg = svo_adaptive_gbuffer(pc.y * params.image.x + pc.x);
      float w = bil * svo_adaptive_weight(p, pg.position, vec2(pc) - vec2(c), float(1u << up));
      sum += w * vec3(a);
      wsum += w;
    }
    if (wsum > 0.01f * 0.5625f) return vec4(sum / wsum, SVO_ADAPTIVE_UPSAMPLED);
  }
  if (!shade_now) return vec4(0.0f, 0.0f, 0.0f, SVO_ADAPTIVE_SHADED);
  return vec4(svo_adaptive_shade(g, pixel, uint(bw.y + 0.5f)), SVO_ADAPTIVE_SHADED);
}

// Share `slot` of SVO_ADAPTIVE_SLOTS of the samples of texel `q` of level
// `level`, marked to shade: contiguous chunks of its N_p samples, each sum
// already divided by N_p, so that the slots' sum is svo_adaptive_shade's
// (up to the order of the additions). On a GPU one texel's N_p samples
// (up to 256) in one thread, beside texels that are only upsampled, left
// the adaptive pass 15-20x slower per sample than forward shading on the
// H200 (2026-12-04); the slots spread them over threads.
SVO_FN vec3 svo_adaptive_samples_of(uvec2 q, uint level, uint slot) {
  uvec2 c = svo_adaptive_centre(q, level);
  uint pixel = c.y * params.image.x + c.x;
  uint spp = max(uint(svo_adaptive_bandwidth(level, q).y + 0.5f), 1u);
  uint chunk = (spp + SVO_ADAPTIVE_SLOTS - 1u) / SVO_ADAPTIVE_SLOTS;
  if (slot * chunk >= spp) return vec3(0.0f);
  SvoForwardSum f = svo_forward_samples_of(svo_adaptive_gbuffer(pixel), pixel, slot * chunk, chunk, spp);
  return f.diffuse + f.specular;
}

// The frame's pixel from level 0 of the shading pyramid, as the forward
// pass composes it (svo_forward_texel): the background's share, the
// ambient term, and the surface's radiance, by coverage.
SVO_FN vec4 svo_adaptive_compose(SvoGBuffer g, vec4 background, uint pixel, vec3 radiance) {
  vec4 sum = vec4(svo_forward_background(background, pixel), 0.0f);
  if (!(g.coverage > 0.0f)) return sum;
  sum += g.coverage * vec4(svo_forward_ambient(g), 1.0f);
  return sum + vec4(g.coverage * radiance, 0.0f);
}

// The shaded-pixel mask of Fig. 1d at pixel (x, y): x the level at which
// the pixel was shaded as some texel's centre (-1: never), y the samples it
// took, z its state at level 0.
SVO_FN vec4 svo_adaptive_mask(uvec2 xy) {
  vec4 m = vec4(-1.0f, 0.0f, svo_adaptive_pyramid(0u, xy).w, 0.0f);
  for (uint level = 0u; level <= adapt.config.w; ++level) {
    uvec2 q = xy >> level;
    if (any(notEqual(svo_adaptive_centre(q, level), xy))) continue;
    if (svo_adaptive_pyramid(level, q).w != SVO_ADAPTIVE_SHADED) continue;
    m.x = float(level);
    m.y = svo_adaptive_bandwidth(level, q).y;
  }
  return m;
}

#endif
