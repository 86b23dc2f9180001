// Specular lobe-aware filtering and upsampling (Tokuyoshi 2015, DESIGN
// 10.5; render::LobeFilterPass): the kernels of a cross-bilateral filter
// (Eq. 1) and of joint bilateral upsampling whose directional weight
// compares the two pixels' reflection lobes (Eq. 11, 12, 13), with the
// normal-aware weight of Eq. 4 as the baseline, times a depth weight
// (Eq. 3) and a screen-space kernel.
//
// The forward pass writes the surface's diffuse and specular radiance
// apart (forward.glsl, svo_forward_split_texel), at 1/1, 1/2 or 1/4 of the
// frame's size; this filter smooths each with its own lobes (the diffuse
// image with the diffuse lobe about the normal, for which Eq. 12 is the
// normal-aware weight, the paper's supplement; the specular image with the
// reflection lobes) and adds them to the background at full size, as the
// paper's section 5 filters the specular buffer apart. Steps, each a kernel
// over the frame's texels:
//   lobes      every pixel's lobes from the G-buffer, once (SvoPixelLobe)
//   rows       the horizontal half of the separable filter (2R + 1 taps)
//   columns    the vertical half, weighting each row result by its total
//              weight (so that the two halves are one 2D kernel whose
//              weights are the product of the two), and the composite
//   upsample   the 2 x 2 input texels about the pixel (bilinear screen
//              kernel); a pixel whose total weight falls under the
//              threshold is shaded again at full size (the paper's Fig. 16)
// Values are filtered per unit coverage and multiplied by the pixel's own.
//
// Host contract: forward.glsl's, plus `filter_params` (SvoFilterParams) and the
// readers svo_filter_gbuffer(texel), svo_filter_lobe(texel),
// svo_filter_background(texel) (full size), svo_filter_diffuse(texel) and
// svo_filter_specular(texel) (the step's input: the forward pass's images
// for rows and upsample, the rows' output for columns).
#ifndef SVO_LOBE_FILTER_GLSL
#define SVO_LOBE_FILTER_GLSL
#include "forward.glsl"
#include "lobe_filter_types.glsl"
#include "sg.glsl"

SVO_FN SvoASG svo_pixel_asg(SVO_IN(SvoPixelLobe) l) {
  return svo_asg(l.asg_x, cross(l.axis, l.asg_x), l.axis, l.asg_lx, l.asg_ly, 1.0f);
}

// Eq. 11 for two pixels' SG mixtures sharing each pixel's axis:
// alpha_ij / sqrt(alpha_ii alpha_jj), alpha the exact product integrals.
SVO_FN float svo_mixture_alpha(SVO_IN(SvoPixelLobe) a, SVO_IN(SvoPixelLobe) b) {
  float sum = 0.0f;
  for (uint k = 0u; k < uint(a.mix_count); ++k)
    for (uint m = 0u; m < uint(b.mix_count); ++m)
      sum += svo_sg_product_integral(svo_sg(a.axis, a.mix_sharpness[k], a.mix_amplitude[k]),
                                     svo_sg(b.axis, b.mix_sharpness[m], b.mix_amplitude[m]));
  return sum;
}

// The lobes of a G-buffer texel (SvoPixelLobe, after smoothing with kappa).
SVO_FN SvoPixelLobe svo_pixel_lobe(SvoGBuffer g) {
  SvoPixelLobe r;
  r.axis = vec3(0.0f, 0.0f, 1.0f);
  r.sharpness = 0.0f;
  r.normal = vec3(0.0f);
  r.depth = 0.0f;
  r.mix_sharpness = vec3(0.0f);
  r.mix_count = 0.0f;
  r.mix_amplitude = vec3(0.0f);
  r.asg_ly = 0.0f;
  r.asg_x = vec3(1.0f, 0.0f, 0.0f);
  r.asg_lx = 0.0f;
  r.asg_norm = 0.0f;
  r.mix_norm = 0.0f;
  if (!(g.coverage > 0.0f)) return r;
  SvoShadingPoint p = svo_shading_point(g);
  vec2 sn2 = filter_params.adapt.z > 0.5f ? vec2(0.0f) : max(p.sn2, vec2(0.0f));
  float sigma2 = 0.5f * (sn2.x + sn2.y);
  r.normal = p.n;
  r.depth = max(g.depth, 1.0e-30f);
  SvoSG probe = svo_reflection_lobe(p.n, p.v, 1.0f);
  r.axis = probe.axis;
  float jacobian = probe.sharpness;  // 1 / (4 |n.v|), clamped
  float kappa = filter_params.weights.w;
  // The two materials' lobes, each widened by the voxel slopes, weighted
  // by the materials' shares; at most three kept (the largest energies).
  SvoMaterial first = svo_scene_material(g.material);
  SvoHalfLobes a = svo_material_lobes(first);
  SvoHalfLobes b = svo_material_lobes(svo_scene_material(g.material2));
  float share = g.material != g.material2 ? clamp(g.material_mix, 0.0f, 1.0f) : 1.0f;
  float energy_sum = 0.0f;
  float variance_sum = 0.0f;
  uint n = 0u;
  for (uint k = 0u; k < 6u; ++k) {
    bool from_a = k < 3u;
    uint m = from_a ? k : k - 3u;
    if (m >= (from_a ? a.count : b.count)) continue;
    float lh = from_a ? a.sharpness[m] : b.sharpness[m];
    float amp = (from_a ? a.amplitude[m] * share : b.amplitude[m] * (1.0f - share));
    if (!(amp > 0.0f)) continue;
    lh = lh / (1.0f + lh * sigma2);
    float l = lh * jacobian;
    // The lobe's energy (its integral) decides which lobes are kept and
    // how the single lobe merges them (variances averaged by energy).
    float energy = amp / max(l, 1.0e-6f);
    energy_sum += energy;
    variance_sum += energy / max(l, 1.0e-6f);
    SvoSG s = svo_sg_smooth(svo_sg(r.axis, l, amp), kappa);
    if (n < 3u) {
      r.mix_sharpness[n] = s.sharpness;
      r.mix_amplitude[n] = s.amplitude;
      ++n;
    } else {
      // Replace the weakest kept lobe if this one carries more.
      uint weakest = 0u;
      for (uint q = 1u; q < 3u; ++q)
        if (r.mix_amplitude[q] / max(r.mix_sharpness[q], 1.0e-6f) <
            r.mix_amplitude[weakest] / max(r.mix_sharpness[weakest], 1.0e-6f))
          weakest = q;
      if (s.amplitude / max(s.sharpness, 1.0e-6f) >
          r.mix_amplitude[weakest] / max(r.mix_sharpness[weakest], 1.0e-6f)) {
        r.mix_sharpness[weakest] = s.sharpness;
        r.mix_amplitude[weakest] = s.amplitude;
      }
    }
  }
  r.mix_count = float(n);
  float merged = energy_sum > 0.0f ? energy_sum / variance_sum : 2.133f;
  r.sharpness = svo_sg_smooth(svo_sg(r.axis, merged, 1.0f), kappa).sharpness;
  // The anisotropic lobe (Eq. 13): the first material's main lobe widened
  // by the voxel slopes along their principal axes (tx, ty) apart. An SG of
  // sharpness l is exp(-l theta^2 / 2) near its axis, an ASG of bandwidth
  // lambda exp(-lambda theta^2): lambda = l / 2 per axis.
  float l0 = a.sharpness.x;
  float lx = 0.5f * jacobian * l0 / (1.0f + l0 * sn2.x);
  float ly = 0.5f * jacobian * l0 / (1.0f + l0 * sn2.y);
  vec3 x = p.tx - dot(p.tx, r.axis) * r.axis;
  float xl = length(x);
  r.asg_x = xl > 1.0e-4f ? x / xl : svo_tangent_frame(r.axis).t;
  SvoASG asg = svo_asg_smooth(svo_asg(r.asg_x, cross(r.axis, r.asg_x), r.axis, lx, ly, 1.0f), kappa);
  r.asg_lx = asg.lx;
  r.asg_ly = asg.ly;
  SvoASG unit = svo_pixel_asg(r);
  r.asg_norm = sqrt(svo_asg_product_integral(unit, unit));
  r.mix_norm = sqrt(svo_mixture_alpha(r, r));
  return r;
}

SVO_FN float svo_weight_mixture(SVO_IN(SvoPixelLobe) a, SVO_IN(SvoPixelLobe) b, float beta) {
  float norm = a.mix_norm * b.mix_norm;
  float q = norm > 0.0f ? clamp(svo_mixture_alpha(a, b) / norm, 0.0f, 1.0f) : 0.0f;
  return pow(q, beta);
}

// Eq. 13 with the pixels' own normalisations (SvoPixelLobe::asg_norm).
SVO_FN float svo_weight_asg(SVO_IN(SvoPixelLobe) a, SVO_IN(SvoPixelLobe) b, float beta) {
  float norm = a.asg_norm * b.asg_norm;
  float q = norm > 0.0f ? clamp(svo_asg_product_integral(svo_pixel_asg(a), svo_pixel_asg(b)) / norm, 0.0f, 1.0f)
                        : 0.0f;
  return pow(q, beta);
}

// The weights of sample pixel b for target pixel a: x for the diffuse
// image, y for the specular one, each with the depth weight.
SVO_FN vec2 svo_filter_weights(SVO_IN(SvoPixelLobe) a, SVO_IN(SvoPixelLobe) b) {
  if (!(b.depth > 0.0f) || !(a.depth > 0.0f)) return vec2(0.0f);
  float dz = (a.depth - b.depth) / (a.depth * max(filter_params.weights.z, 1.0e-6f));
  float w = exp(-0.5f * dz * dz);
  uint mode = filter_params.mode.x;
  float beta = filter_params.weights.x;
  if (mode == SVO_FILTER_NONE) return vec2(w);
  if (mode == SVO_FILTER_NORMAL) return vec2(w * svo_weight_normal(a.normal, b.normal, filter_params.weights.y));
  // The diffuse lobes: Eq. 12 for two lobes of one sharpness l is the
  // normal-aware weight of variance 2 / (beta l) (the paper's supplement),
  // which the host computes once (adapt.w; svo_filter_diffuse_variance).
  float wd = filter_params.adapt.w > 0.0f ? svo_weight_normal(a.normal, b.normal, filter_params.adapt.w) : 1.0f;
  float ws;
  if (mode == SVO_FILTER_LOBE) {
    ws = svo_weight_eq12(svo_sg(a.axis, a.sharpness, 1.0f), svo_sg(b.axis, b.sharpness, 1.0f), beta);
  } else if (mode == SVO_FILTER_MIXTURE) {
    ws = svo_weight_mixture(a, b, beta);
  } else {
    ws = svo_weight_asg(a, b, beta);
  }
  return w * vec2(wd, ws);
}

// What a filter step gives a texel: the diffuse and specular values per
// unit coverage (rgb) with their total weights (w), or, from the last step,
// the frame's colour (diffuse) and the totals (specular: x diffuse, y
// specular, z 1 where the pixel was shaded again).
struct SvoFilterOut {
  vec4 diffuse;
  vec4 specular;
};

// The sums of the 2R + 1 taps about `texel` along a row or a column
// (full size): diffuse and specular, rgb the weighted values and w the
// weights. The rows read the forward pass's images (values per unit
// coverage: rgb / w); the columns read the rows' results (averages in
// rgb, weighted by their totals in w).
SVO_FN SvoFilterOut svo_filter_line(uint texel, bool columns) {
  uint w = params.image.x;
  int at = columns ? int(texel / w) : int(texel % w);
  int size = columns ? int(params.image.y) : int(w);
  int stride = columns ? int(w) : 1;
  int radius = int(filter_params.mode.y);
  SvoPixelLobe a = svo_filter_lobe(texel);
  SvoFilterOut sum;
  sum.diffuse = vec4(0.0f);
  sum.specular = vec4(0.0f);
  for (int k = -radius; k <= radius; ++k) {
    if (at + k < 0 || at + k >= size) continue;
    uint j = uint(int(texel) + k * stride);
    SvoPixelLobe b = svo_filter_lobe(j);
    if (!(b.depth > 0.0f)) continue;
    vec4 dj = svo_filter_diffuse(j);
    vec4 sj = svo_filter_specular(j);
    if (!columns && !(dj.w > 0.0f)) continue;
    vec2 wt = svo_filter_screen(float(k), filter_params.adapt.y) * svo_filter_weights(a, b);
    if (columns) {
      wt *= vec2(dj.w, sj.w);
      sum.diffuse += vec4(wt.x * vec3(dj), wt.x);
      sum.specular += vec4(wt.y * vec3(sj), wt.y);
    } else {
      sum.diffuse += vec4(wt.x * vec3(dj) / dj.w, wt.x);
      sum.specular += vec4(wt.y * vec3(sj) / sj.w, wt.y);
    }
  }
  return sum;
}

// A row about texel `texel` (input at 1/1): averages and totals.
SVO_FN SvoFilterOut svo_filter_rows_texel(uint texel) {
  SvoFilterOut sum = svo_filter_line(texel, false);
  float norm = filter_params.screen.x;
  vec4 d = sum.diffuse;
  vec4 s = sum.specular;
  SvoFilterOut o;
  o.diffuse = d.w > 0.0f ? vec4(vec3(d) / d.w, d.w / norm) : vec4(0.0f);
  o.specular = s.w > 0.0f ? vec4(vec3(s) / s.w, s.w / norm) : vec4(0.0f);
  return o;
}

// The column of 2R + 1 row results about `texel`, each weighted by its
// own total, and the composite: the background plus coverage times the
// filtered diffuse and specular values.
SVO_FN SvoFilterOut svo_filter_columns_texel(uint texel) {
  SvoFilterOut sum = svo_filter_line(texel, true);
  float norm = filter_params.screen.x;
  vec4 d = sum.diffuse;
  vec4 s = sum.specular;
  SvoGBuffer g = svo_filter_gbuffer(texel);
  vec3 colour = svo_forward_background(svo_filter_background(texel), texel);
  if (g.coverage > 0.0f) {
    if (d.w > 0.0f) colour += g.coverage * vec3(d) / d.w;
    if (s.w > 0.0f) colour += g.coverage * vec3(s) / s.w;
  }
  SvoFilterOut o;
  o.diffuse = vec4(colour, g.coverage);
  o.specular = vec4(d.w / norm, s.w / norm, 0.0f, 0.0f);
  return o;
}

// Joint bilateral upsampling from input texels at 1/scale of the frame's
// size: the 2 x 2 input texels about the pixel, each standing for the
// G-buffer texel at its centre; bilinear screen weights. Below the
// threshold of total weight the pixel is shaded again (forward.glsl).
SVO_FN SvoFilterOut svo_filter_upsample_texel(uint texel) {
  uint w = params.image.x;
  uint h = params.image.y;
  uint scale = max(filter_params.mode.z, 1u);
  uint lw = (w + scale - 1u) / scale;
  uint lh = (h + scale - 1u) / scale;
  uint x = texel % w;
  uint y = texel / w;
  SvoPixelLobe a = svo_filter_lobe(texel);
  vec2 u = (vec2(float(x), float(y)) + 0.5f) / float(scale) - 0.5f;
  vec2 base = floor(u);
  vec2 frac = u - base;
  vec4 d = vec4(0.0f);
  vec4 s = vec4(0.0f);
  vec4 d0 = vec4(0.0f);  // the screen weights alone: where no tap has weight and nothing is shaded again
  vec4 s0 = vec4(0.0f);
  for (uint k = 0u; k < 4u; ++k) {
    int cx = int(base.x) + int(k & 1u);
    int cy = int(base.y) + int(k >> 1u);
    if (cx < 0 || cy < 0 || cx >= int(lw) || cy >= int(lh)) continue;
    float f = ((k & 1u) != 0u ? frac.x : 1.0f - frac.x) * ((k >> 1u) != 0u ? frac.y : 1.0f - frac.y);
    uint low = uint(cy) * lw + uint(cx);
    SvoPixelLobe b = svo_filter_lobe(svo_scaled_texel(low, scale));
    vec4 dj = svo_filter_diffuse(low);
    vec4 sj = svo_filter_specular(low);
    if (!(dj.w > 0.0f)) continue;
    vec2 wt = f * svo_filter_weights(a, b);
    d += vec4(wt.x * vec3(dj) / dj.w, wt.x);
    s += vec4(wt.y * vec3(sj) / sj.w, wt.y);
    d0 += vec4(f * vec3(dj) / dj.w, f);
    s0 += vec4(f * vec3(sj) / sj.w, f);
  }
  vec3 dv = d.w > 0.0f ? vec3(d) / d.w : (d0.w > 0.0f ? vec3(d0) / d0.w : vec3(0.0f));
  vec3 sv = s.w > 0.0f ? vec3(s) / s.w : (s0.w > 0.0f ? vec3(s0) / s0.w : vec3(0.0f));
  SvoGBuffer g = svo_filter_gbuffer(texel);
  vec3 colour = svo_forward_background(svo_filter_background(texel), texel);
  float again = 0.0f;
  if (g.coverage > 0.0f) {
    // Threshold 0: never shaded again (a pixel without weight keeps the
    // screen weights' average, or nothing where no tap is covered).
    float threshold = filter_params.adapt.x;
    if (threshold > 0.0f && (!(d.w >= threshold) || !(s.w >= threshold))) {
      SvoForwardSplit empty;
      empty.diffuse = vec4(0.0f);
      empty.specular = vec4(0.0f);
      SvoForwardSplit f = svo_forward_split_texel(g, texel, 0u, shade.sampling.x, empty);
      colour += vec3(f.diffuse) + vec3(f.specular);
      again = 1.0f;
    } else {
      colour += g.coverage * (dv + sv);
    }
  }
  SvoFilterOut o;
  o.diffuse = vec4(colour, g.coverage);
  o.specular = vec4(d.w, s.w, again, 0.0f);
  return o;
}

#endif
