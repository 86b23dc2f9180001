// The cone tracer (Heitz & Neyret Algorithm 1, DESIGN section 8): one cone
// per pixel through the bricked octree, A-buffer masks for sub-pixel
// occlusion, shading by Eq. 13 with the Eq. 17 attribute. The same tracer
// source (shaders/common/tracer.glsl) runs on the GPU (GpuRenderer, Vulkan
// compute) and on the CPU (render_cpu, for tests).
#pragma once

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/pass.h"
#include "svo/render/vk_context.h"

namespace svo::render {

// Values are shared with the shaders: never renumber.
enum class Mode : uint32_t {
  Prefiltered = 0,  // ours: quadrilinear statistics, masks, Eq. 17, roughness from slope variance
  Nearest = 1,      // binary voxels at the nearest level, no interpolation
  Alpha = 2,        // coverage as opacity, front-to-back blending (thickens silhouettes)
  Mip = 3,          // our geometry, plain averaged colour and normal
  RayMarch = 4,     // supersampling baseline: RenderSettings::spp rays per pixel marching the finest level
};
const char* mode_name(Mode mode);                   // "prefiltered", ...
std::optional<Mode> parse_mode(std::string_view name);  // nullopt for an unknown name

// A pinhole camera, or a thin lens when aperture > 0.
struct Camera {
  glm::vec3 eye{0, 0, 3};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  float fov_deg = 40;    // vertical field of view
  float aperture = 0;    // lens radius, scene units (0: pinhole)
  float focus = 0;       // focus distance along the view axis, scene units (used when aperture > 0)
};

constexpr int kMaxLights = 4;

struct Light {
  bool point = false;
  // Directional: the direction towards the light (normalised by the renderer).
  // Point: the light's position.
  glm::vec3 vector{0.4f, 0.8f, 0.6f};
  // Directional: irradiance at normal incidence. Point: intensity (irradiance = radiance / distance^2).
  glm::vec3 radiance{3, 3, 3};
  // Size of the light for soft shadows. Directional: angular radius (radians). Point: radius (scene units).
  float size = 0.02f;
};

struct RenderSettings {
  uint32_t width = 512;
  uint32_t height = 512;
  Camera camera;
  Mode mode = Mode::Prefiltered;
  bool shadows = false;
  std::vector<Light> lights = std::vector<Light>(1);  // at most kMaxLights; default: one Light{}
  glm::vec3 ambient{0.08f, 0.08f, 0.1f};  // unshadowed ambient irradiance / pi, times abar
  glm::vec3 background{0.02f, 0.02f, 0.03f};  // radiance of the bits no element set
  float specular = 0.04f;  // weight of the Beckmann lobe added to the Lambertian term (white)
  // Prefiltered and alpha modes: weight of the normals' spread over each
  // cone's footprint, added to the voxels' slope variance (tracer.glsl,
  // svo_footprint_slope_covariance): 1 is the second-order theory, 0 leaves
  // the voxels' statistics alone (the paper's model). In [0, 4].
  float footprint_spread = 1.0f;
  // Prefiltered and alpha modes: occlusion masks bend with the surface's
  // curvature along the cone (cone_mask.glsl), and a mean normal turned
  // away from the eye is laid into the silhouette plane (tracer.glsl,
  // svo_shade). false: the voxels' mean planes and normals as they are.
  bool curved_masks = true;
  bool front_facing = true;
  // Prefiltered and alpha modes: the elements of a cone at least about a
  // finest voxel wide shade with half the normal at their own centre and
  // half that at the point all of them share (tracer.glsl, svo_shade).
  // false: the shared point's alone.
  bool element_normals = true;
  // Prefiltered mode: each element shades the part of the footprint it
  // covers first, at the centre of its fresh mask bits and with their
  // spread (tracer.glsl, svo_footprint_part). false: at the cone's axis,
  // with the whole footprint's spread.
  bool covered_part = true;
  // Prefiltered mode: the voxel size, in cone radii, of the level shading
  // reads (occlusion reads sqrt(2) radii). In [0.25, 4].
  float shading_voxel = 1.0f;
  uint32_t spp = 1;  // RayMarch: rays per pixel, a square (1, 4, 16, 64, ...)
  bool gbuffer = false;  // fill Frame::gbuffer
  bool display = false;  // GPU only: run the display pass and fill Frame::display
  uint32_t max_steps = 4096;  // per pixel, a safety bound on cone elements
};

// One G-buffer texel: coverage-weighted averages over the elements that set
// bits of the pixel's mask (coverage 0: no surface, the other fields 0).
struct GBufferTexel {
  float depth = 0;  // distance along the view ray, scene units
  glm::vec3 position{0};
  glm::vec3 normal{0};  // filtered mean normal (not renormalised)
  float slope_variance = 0;  // total: sigma_n^2 (isotropic mean) + sigma_rho^2
  glm::vec3 abar{0};
  float coverage = 0;  // covered fraction of the pixel's footprint
};

struct Frame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec4> colour;  // row-major, top row first; linear RGB radiance, alpha = coverage
  std::vector<GBufferTexel> gbuffer;  // empty unless requested
  std::vector<uint32_t> steps;  // cone elements visited per pixel (shadow cones included)
  std::vector<uint32_t> display;  // when requested: 8-bit sRGB RGBA per pixel (DisplayPass)
  double gpu_ms = -1;   // GPU time of the trace from timestamp queries; -1 when unknown (CPU)
  double wall_ms = 0;   // host time of render(), uploads of settings and read-back included
  uint64_t covered_pixels = 0;  // pixels with coverage > 0
  double steps_per_pixel = 0;   // mean over all pixels
};

// The Vulkan tracer. Uploads the octree once (node pool and brick pools,
// split across several storage buffers within the device's
// maxStorageBufferRange); render() may be called many times. A frame is a
// chain of passes (pass.h): the tracer, the passes added, and the display
// pass when asked for.
class GpuRenderer {
 public:
  struct Options {
    // Lowers the size of one brick buffer below the device's limit (0: the
    // device's); tests use it to split pools.
    uint64_t max_buffer_bytes = 0;
    // Read pools beyond one storage buffer through buffer device addresses
    // when the device has them (false: separate storage buffers, slower).
    bool device_address = true;
  };
  // Throws vk::Error naming the limit when the octree cannot fit on the device.
  GpuRenderer(vk::Context& context, const octree::Octree& tree) : GpuRenderer(context, tree, Options{}) {}
  GpuRenderer(vk::Context& context, const octree::Octree& tree, const Options& options);
  ~GpuRenderer();
  GpuRenderer(const GpuRenderer&) = delete;
  GpuRenderer& operator=(const GpuRenderer&) = delete;

  // Throws std::invalid_argument for bad settings (size 0 or above the
  // device's limits, too many lights), vk::Error for Vulkan failures.
  Frame render(const RenderSettings& settings);

  // Appends a pass that runs after the tracer (and before the display pass)
  // on every frame. Throws std::invalid_argument when it reads an image that
  // no earlier pass writes.
  void add_pass(std::unique_ptr<Pass> pass);
  // The images of the last frame (read them through their mapped buffers).
  FrameImages& images();

  std::size_t pool_bytes() const;    // device memory held by the octree pools
  uint32_t pool_buffers() const;     // buffers the bricks are split across
  const char* pool_access() const;   // "single", "address" or "switch": how the tracer reads them

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The same tracer on the CPU (multithreaded, slow): the reference for the GPU path in tests.
Frame render_cpu(const octree::Octree& tree, const RenderSettings& settings);

}  // namespace svo::render
