// Passes a command adds after the tracer by name (`svo render --pass NAME`),
// each a per-texel kernel of shaders/common run by both hosts.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "svo/render/pass.h"
#include "svo/render/shading.h"

namespace svo::render {

// The visible fraction of each light seen from every G-buffer point, by a
// visibility cone through the octree (shaders/common/visibility_pass.glsl):
// reads "gbuffer", writes "visibility" (Rgba32f: lights 1 to 4; 1 where a
// light is absent or the pixel has no surface).
class VisibilityPass : public Pass {
 public:
  VisibilityPass();
  ~VisibilityPass() override;
  std::string name() const override { return "visibility"; }
  std::vector<ImageDesc> reads() const override { return {gbuffer_image()}; }
  std::vector<ImageDesc> writes() const override { return {visibility_image()}; }
  double run(PassContext& context) override;
  static ImageDesc visibility_image() { return {"visibility", TexelFormat::Rgba32f}; }

 private:
  std::unique_ptr<vk::ComputeKernel> kernel_;  // made at the first run on a Vulkan host
};

// The images of the surface's diffuse and specular radiance apart (forward
// shading with ForwardOutput::split), at 1/scale of the frame's size:
// Rgba32f, rgb times coverage, coverage in A; nothing of the background.
inline ImageDesc diffuse_image(uint32_t scale = 1) { return {"diffuse", TexelFormat::Rgba32f, scale}; }
inline ImageDesc specular_image(uint32_t scale = 1) { return {"specular", TexelFormat::Rgba32f, scale}; }

// What the forward pass writes: the frame's colour, or (split) the
// diffuse part with the ambient term and the specular part apart, for the
// lobe-aware filter, at 1/1, 1/2 or 1/4 of the frame's size (each texel
// shaded at the G-buffer texel at its centre, shaders/common/forward.glsl,
// svo_scaled_texel).
struct ForwardOutput {
  bool split = false;
  uint32_t scale = 1;  // 1, 2, 4; other than 1 only when split
};

// Forward shading (DESIGN 10.2, shaders/common/forward.glsl): every covered
// pixel shaded with RenderSettings::shading's environment, material and
// samples per pixel (multiple importance sampling of the BRDF and the
// environment) plus the lights, over the background or the environment seen
// through the pixel: reads "gbuffer" and "background", writes "colour" (the
// frame's colour from then on); split: reads "gbuffer", writes "diffuse" and
// "specular".
class ForwardPass : public Pass {
 public:
  // @throw std::invalid_argument for a scale other than 1, 2, 4, or a
  //        reduced scale without split
  explicit ForwardPass(ForwardOutput output = {});
  ~ForwardPass() override;
  std::string name() const override { return output_.split ? "forward-split" : "forward"; }
  std::vector<ImageDesc> reads() const override;
  std::vector<ImageDesc> writes() const override;
  double run(PassContext& context) override;

 private:
  ForwardOutput output_;
  struct Cache;
  std::unique_ptr<Cache> cache_;  // the shading tables of the last options, and the Vulkan kernel and buffers
};

// Specular lobe-aware filtering and upsampling (Tokuyoshi 2015, DESIGN
// 10.5; shaders/common/lobe_filter.glsl), with RenderSettings::filter's
// weight and parameters: reads "gbuffer", "background", and "diffuse" and
// "specular" at 1/scale (ForwardPass with split); writes "colour" and
// "filter_weight" (Rgba32f: the total weights of the diffuse and the
// specular image, normalised to 1 for a neighbourhood of identical pixels,
// and 1 in z where upsampling shaded the pixel again), and at scale 1 the
// rows' results "filter_rows_diffuse" and "filter_rows_specular".
// At scale 1 a separable cross-bilateral filter of radius R; at 2 and 4,
// joint bilateral upsampling with adaptive recomputation.
class LobeFilterPass : public Pass {
 public:
  // @throw std::invalid_argument for a scale other than 1, 2, 4
  explicit LobeFilterPass(uint32_t scale = 1);
  ~LobeFilterPass() override;
  std::string name() const override { return scale_ == 1 ? "lobe-filter" : "lobe-upsample"; }
  std::vector<ImageDesc> reads() const override;
  std::vector<ImageDesc> writes() const override;
  double run(PassContext& context) override;
  static ImageDesc weight_image() { return {"filter_weight", TexelFormat::Rgba32f}; }

 private:
  uint32_t scale_;
  struct State;
  std::unique_ptr<State> state_;  // the shading tables, the lobes, and the Vulkan kernels and buffers
};

// Light-field luminaires (Lu et al. 2015, DESIGN 10.4; shaders/common/
// luminaire.glsl): every covered pixel lit by RenderSettings::luminaire's
// luminaires with its material, by position-dependent importance sampling
// and visibility cones through the octree. Over the colour: reads "gbuffer"
// and "colour" (the forward pass's) and adds to it; otherwise reads
// "gbuffer" and "background" and writes "colour" (the background's share,
// the ambient term and the luminaires' light).
class LuminairePass : public Pass {
 public:
  // The pixels' state (luminaire.glsl: A(p), the cells' visibility) is
  // made in bands of at most state_band_bytes (at least 64 pixels each).
  static constexpr uint64_t kStateBandBytes = uint64_t(64) << 20;
  explicit LuminairePass(bool over_colour = false, uint64_t state_band_bytes = kStateBandBytes);
  ~LuminairePass() override;
  std::string name() const override { return "luminaire"; }
  std::vector<ImageDesc> reads() const override;
  std::vector<ImageDesc> writes() const override { return {colour_image()}; }
  double run(PassContext& context) override;

 private:
  bool over_;
  uint64_t band_bytes_;
  struct Cache;
  std::unique_ptr<Cache> cache_;  // the shading and luminaire tables, and the Vulkan kernel and buffers
};

// Bandwidth-adaptive environment shading (Bagher et al. 2013, DESIGN
// 10.3; shaders/common/bandwidth.glsl) with RenderSettings::adaptive: the
// bandwidth buffer from the G-buffer (per pixel the level at which it may
// be shaded and its sample count), its mips, then shading coarse to fine,
// each texel shaded with its own sample count or upsampled from the coarser
// level. Reads "gbuffer" and "background"; writes "colour" (as the forward
// pass composes it), "bandwidth" (Rgba32f, SVO_ADAPTIVE_LEVELS levels: the
// level min-filtered (unfloored: log2(1 / (2 b_p)) within [0, coarsest]), N_p, the relative variance bound and the screen-space
// curvature max-filtered), "adaptive" (Rgba32f, the same levels: the
// surface's radiance and the texel's state, SVO_ADAPTIVE_*) and
// "adaptive_mask" (Rgba32f: the level each pixel was shaded at, -1 for
// none, and its samples; Fig. 1d).
class AdaptivePass : public Pass {
 public:
  AdaptivePass();
  ~AdaptivePass() override;
  std::string name() const override { return "adaptive"; }
  std::vector<ImageDesc> reads() const override { return {gbuffer_image(), background_image()}; }
  std::vector<ImageDesc> writes() const override {
    return {colour_image(), bandwidth_image(), pyramid_image(), mask_image()};
  }
  double run(PassContext& context) override;
  static ImageDesc bandwidth_image();
  static ImageDesc pyramid_image();
  static ImageDesc mask_image() { return {"adaptive_mask", TexelFormat::Rgba32f}; }
  // What the last frame did: texels shaded and their samples, over all levels.
  struct Stats {
    uint64_t shaded = 0, samples = 0, covered = 0;
    // Covered pixels by the level their bandwidth allows (Eq. 11), and
    // shaded texels by the level they were shaded at.
    std::array<uint64_t, 8> pixels_at_level{}, shaded_at_level{};
    // The input bandwidths (environment, BRDFs: once per input), the
    // bandwidth buffer and its mips, the levels and the composition.
    double tables_ms = 0, bandwidth_ms = 0, shading_ms = 0;
  };
  const Stats& stats() const { return stats_; }

 private:
  struct Cache;
  std::unique_ptr<Cache> cache_;  // the shading and bandwidth tables, and the Vulkan kernel and buffers
  Stats stats_;
};

// The names make_pass knows, in the order --help lists them.
std::vector<std::string> pass_names();

// A new pass by name. Throws std::invalid_argument naming the passes there are.
std::unique_ptr<Pass> make_pass(const std::string& name);

}  // namespace svo::render
