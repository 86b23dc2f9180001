// The cone tracer (Heitz & Neyret Algorithm 1, DESIGN section 8): one cone
// per pixel through the bricked octree, A-buffer masks for sub-pixel
// occlusion, shading by Eq. 13 with the Eq. 17 attribute. The same tracer
// source (shaders/common/tracer.glsl) runs on two hosts: a Vulkan device
// (GpuRenderer, compute) and the CPU (NativeRenderer, compiled as C++).
// make_renderer picks the host a command asks for.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/luminaire.h"
#include "svo/render/octree_access.h"
#include "svo/render/pass.h"
#include "svo/render/shading.h"
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
const char* mode_name(Mode mode);                       // "prefiltered", ...
std::optional<Mode> parse_mode(std::string_view name);  // nullopt for an unknown name

// A pinhole camera, or a thin lens when aperture > 0.
struct Camera {
  glm::vec3 eye{0, 0, 3};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  float fov_deg = 40;  // vertical field of view
  float aperture = 0;  // lens radius, scene units (0: pinhole)
  float focus = 0;     // focus distance along the view axis, scene units (used when aperture > 0)
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
  glm::vec3 ambient{0.08f, 0.08f, 0.1f};              // unshadowed ambient irradiance / pi, times abar
  glm::vec3 background{0.02f, 0.02f, 0.03f};          // radiance of the bits no element set
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
  // Prefiltered mode: a part of the footprint across a crease (two flat
  // faces, the normal turning fast) is shaded as its two halves, weighted
  // by where its own normal lies between theirs (svo_shade). false: at one
  // point, with one lobe.
  bool crease_split = true;
  // Prefiltered mode: the voxel size, in cone radii, of the level shading
  // reads (occlusion reads sqrt(2) radii). In [0.25, 4].
  float shading_voxel = 1.0f;
  uint32_t spp = 1;      // RayMarch: rays per pixel, a square (1, 4, 16, 64, ...)
  // With a lens (camera.aperture > 0), cone modes: the lens is split into
  // lens_parts x lens_parts parts, a cone each, averaged (tracer.glsl,
  // svo_lens_parts). 0: chosen from the blur's width inside the domain
  // (1 to 4). At most 8.
  uint32_t lens_parts = 0;
  bool gbuffer = false;  // trace the G-buffer and fill Frame::gbuffer
  bool display = false;  // run the display pass and fill Frame::display
  // Multisample anti-aliasing: 1, 2 or 4 samples per pixel side. Above 1
  // the chain runs at msaa x msaa samples per pixel (a cone per sample, as
  // narrow as the sample) and Frame::colour is their box-filtered mean;
  // the passes' images stay at the samples' size. Forward shading then
  // shades every sample; adaptive shading only where the predicted
  // bandwidth asks for more than a pixel (Bagher et al. 2013, Fig. 19).
  uint32_t msaa = 1;
  uint32_t max_steps = 4096;  // per pixel, a safety bound on cone elements
  // The shading passes' environment, material and sampling (ForwardPass).
  ShadingOptions shading;
  // The lobe-aware filter's weight and parameters (LobeFilterPass).
  FilterOptions filter;
  // The luminaires and their sampling (LuminairePass).
  LuminaireOptions luminaire;
  // Bandwidth-adaptive shading (AdaptivePass).
  AdaptiveOptions adaptive;
};

// One G-buffer texel (shaders/common/gbuffer.glsl, which says what each
// field holds): coverage-weighted averages over the elements that set bits
// of the pixel's mask (coverage 0: no surface, the other fields 0).
struct GBufferTexel {
  float depth = 0;  // distance along the view ray, scene units
  glm::vec3 position{0};
  glm::vec3 normal{0};     // filtered mean normal (not renormalised)
  float coverage = 0;      // covered fraction of the pixel's footprint
  glm::vec3 tangent{0};    // unit, perpendicular to the normal: the frame of slope_cov
  float sigma_rho2 = 0;    // the micro-BRDF's slope variance
  glm::vec3 slope_cov{0};  // (xx, yy, xy) in (tangent, normal x tangent), without sigma_rho2
  glm::vec3 abar{0};
  glm::vec3 a_s{0};
  uint32_t material = 0;   // the material the pixel shows most (an index into the scene's materials)
  uint32_t material2 = 0;  // the second
  float material_mix = 0;  // the first's share of the two (0 where nothing is covered)
  // The mean per-axis slope variance with the micro-BRDF's.
  float slope_variance() const { return 0.5f * (slope_cov.x + slope_cov.y) + sigma_rho2; }
};

// vec4s of one texel of the "gbuffer" image (SVO_GBUFFER_VEC4S).
constexpr std::size_t kGBufferVec4s = 6;
// The texel at `texel` (kGBufferVec4s vec4s), unpacked by gbuffer.glsl:
// as the shared GLSL takes it, and as the hosts' files take it.
inline svo::math::SvoGBuffer gbuffer_at(const glm::vec4* t) {
  return svo::math::svo_gbuffer_unpack(t[0], t[1], t[2], t[3], t[4], t[5]);
}
GBufferTexel unpack_gbuffer(const glm::vec4* texel);

struct PassTime {
  std::string name;
  double ms = -1;  // device timestamps on Vulkan, wall clock natively; negative: unknown
};

struct Frame {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec4> colour;      // row-major, top row first; linear RGB radiance, alpha = coverage
  std::vector<GBufferTexel> gbuffer;  // empty unless requested
  std::vector<uint32_t> steps;        // cone elements visited per pixel (shadow cones included)
  std::vector<uint32_t> display;      // when requested: 8-bit sRGB RGBA per pixel (DisplayPass)
  std::vector<PassTime> passes;       // each pass's time, in the order they ran
  double ms = -1;                     // the passes' time together (-1 when one is unknown)
  double gpu_ms = -1;                 // the same from GPU timestamps; -1 on the native host or without timestamps
  double wall_ms = 0;                 // host time of render(), uploads of settings and read-back included
  uint64_t covered_pixels = 0;        // pixels with coverage > 0
  double steps_per_pixel = 0;         // mean over all pixels
};

// The frame's time as commands report it: the passes' (GPU timestamps on a
// Vulkan device, wall clock natively), or the wall clock of render() when a
// pass's time is unknown.
inline double frame_ms(const Frame& frame) { return frame.ms >= 0 ? frame.ms : frame.wall_ms; }
// What frame_ms measured: "GPU", "native" or "wall".
inline const char* frame_clock(const Frame& frame, Host host) {
  return frame.gpu_ms >= 0 ? "GPU" : frame.ms >= 0 && host == Host::Native ? "native" : "wall";
}

// A renderer: the cone tracer and the passes added after it, on one host.
// render() may be called many times; the octree is prepared once.
class Renderer {
 public:
  virtual ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Runs the chain: the tracer, the passes added, the display pass when
  // settings.display. The G-buffer is traced when settings.gbuffer or when
  // an added pass reads it. Throws std::invalid_argument for bad settings
  // (size 0 or above the device's limits, too many lights), vk::Error for
  // Vulkan failures.
  Frame render(const RenderSettings& settings);

  // Appends a pass that runs after the tracer (and before the display pass)
  // on every frame. Throws std::invalid_argument naming the pass and the
  // image when it reads an image that no earlier pass writes, or reads it
  // with another type than it is written.
  void add_pass(std::unique_ptr<Pass> pass);

  // The images of the last frame (FrameImages::read them by name).
  FrameImages& images();
  // Names of the images the chain writes (the display pass's included).
  std::vector<std::string> image_names() const;

  Host host() const { return host_; }
  const std::string& device_name() const { return device_name_; }
  // "native", or the Vulkan device's type ("discrete", "integrated", "cpu", ...).
  const std::string& device_type() const { return device_type_; }
  // Vulkan validation messages so far (empty without validation and natively).
  std::vector<std::string> validation_messages() const;

 protected:
  Renderer(Host host, vk::Context* context, std::unique_ptr<vk::Context> owned);
  // Called once each by the host's constructor, in this order.
  void set_octree(std::unique_ptr<OctreeAccess> octree) { octree_ = std::move(octree); }
  void set_trace(std::unique_ptr<Pass> trace);  // the first pass
  const OctreeAccess& octree() const { return *octree_; }
  vk::Context* vulkan() const { return context_; }

 private:
  std::unique_ptr<vk::Context> owned_context_;  // declared first: outlives every buffer below
  vk::Context* context_;
  Host host_;
  std::string device_name_, device_type_;
  std::unique_ptr<OctreeAccess> octree_;
  std::vector<std::unique_ptr<Pass>> passes_;
  std::map<std::string, ImageDesc> written_;  // images the chain writes so far
  bool gbuffer_read_ = false;                 // an added pass reads "gbuffer"
  DisplayPass display_;
  FrameImages images_;
};

// The Vulkan host. Uploads the octree once (node pool and brick pools,
// split across several storage buffers within the device's
// maxStorageBufferRange).
class GpuRenderer : public Renderer {
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
  // The same, owning its context.
  GpuRenderer(std::unique_ptr<vk::Context> context, const octree::Octree& tree, const Options& options);

  std::size_t pool_bytes() const;   // device memory held by the octree pools
  uint32_t pool_buffers() const;    // buffers the bricks are split across
  const char* pool_access() const;  // "single", "address" or "switch": how the tracer reads them

 private:
  GpuRenderer(std::unique_ptr<vk::Context> owned, vk::Context* context, const octree::Octree& tree,
              const Options& options);
};

// The native host: the tracer of shaders/common compiled as C++, every pass
// parallel over texels with TBB. Packs the octree once.
class NativeRenderer : public Renderer {
 public:
  explicit NativeRenderer(const octree::Octree& tree);
};

// The host a command runs on. `device`: "" for the default (a discrete GPU,
// then an integrated one, then the native host; Vulkan's CPU device,
// lavapipe, only when named), "native", or a Vulkan device's index or a
// case-insensitive substring of its name (vk::select_device).
struct DeviceOptions {
  std::string device;
  bool validation = false;  // Vulkan only: the Khronos validation layer
  GpuRenderer::Options gpu;
};

// What `device` selects, without opening it: "native" or the Vulkan
// device's index as a string. Throws vk::Error naming the selector and the
// devices there are when it matches none.
std::string resolve_device(const std::string& device);

// A renderer on the device `options` select; with validation and no device
// named, the best Vulkan device. Throws vk::Error as resolve_device does,
// std::invalid_argument for validation on the native host.
std::unique_ptr<Renderer> make_renderer(const octree::Octree& tree, const DeviceOptions& options);

// The lens parts a side that a frame of `settings` traces (RenderSettings::
// lens_parts, or, for 0, the tracer's choice): 1 without a lens or in
// raymarch mode; else enough that no part's cone is wider inside the
// domain than a quarter of the coarsest voxel / sqrt(2) (an eighth where
// the octree's provenance says "two_sided": its shells swell under a
// wide cone), at most 4.
uint32_t lens_parts(const octree::Octree& tree, const RenderSettings& settings);

// One frame on the native host (for tests): NativeRenderer(tree).render(settings).
Frame render_cpu(const octree::Octree& tree, const RenderSettings& settings);

}  // namespace svo::render
