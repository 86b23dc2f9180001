#include "trace_setup.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "svo/octree/sampler.h"

namespace svo::render {

namespace {

// Bytes between samples of a channel in the pool: 3-byte encodings take a
// whole word, so that every read of the tracer is one aligned load.
uint32_t pool_stride(octree::Encoding encoding) {
  uint32_t size = octree::encoding_bytes(encoding);
  return size == 3 ? 4 : size;
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

const char* mode_name(Mode mode) {
  switch (mode) {
    case Mode::Prefiltered:
      return "prefiltered";
    case Mode::Nearest:
      return "nearest";
    case Mode::Alpha:
      return "alpha";
    case Mode::Mip:
      return "mip";
    case Mode::RayMarch:
      return "raymarch";
  }
  return "unknown";
}

std::optional<Mode> parse_mode(std::string_view name) {
  for (Mode m : {Mode::Prefiltered, Mode::Nearest, Mode::Alpha, Mode::Mip, Mode::RayMarch}) {
    if (name == mode_name(m)) return m;
  }
  return std::nullopt;
}

PackedOctree pack_octree(const octree::Octree& tree) {
  using octree::Channel;
  using octree::Encoding;
  PackedOctree p;
  if (tree.channel_index(Channel::Distance) < 0) throw std::invalid_argument("the octree has no distance channel");
  p.nodes.resize(tree.nodes.size());
  for (size_t i = 0; i < tree.nodes.size(); ++i) p.nodes[i] = {tree.nodes[i].children, tree.nodes[i].brick};
  const uint32_t edge = tree.samples_per_edge_with_faces(), samples = edge * edge * edge;  // per pool brick
  std::vector<uint32_t> offset(tree.channels.size());
  uint32_t bytes = 0;
  p.offsets_a = p.offsets_b = p.offsets_c = glm::uvec4(svo::math::SVO_ABSENT);
  for (size_t c = 0; c < tree.channels.size(); ++c) {
    offset[c] = bytes;
    const auto& info = tree.channels[c];
    switch (info.channel) {
      case Channel::Distance:
        p.offsets_a.x = bytes;
        break;
      case Channel::Normal:
        p.offsets_a.y = bytes;
        break;
      case Channel::HeightDev:
        p.offsets_a.z = bytes;
        p.encodings.x = uint32_t(info.encoding);
        break;
      case Channel::SlopeDev:
        p.offsets_a.w = bytes;
        p.encodings.y = uint32_t(info.encoding);
        break;
      case Channel::SlopeCov:
        p.offsets_b.x = bytes;
        break;
      case Channel::Colour:
        p.offsets_b.y = bytes;
        break;
      case Channel::ColourSlope:
        p.offsets_b.z = bytes;
        break;
      case Channel::Material:
        p.offsets_b.w = bytes;
        break;
      case Channel::ShadingNormal:
        p.offsets_c.x = bytes;
        break;
    }
    bytes += (samples * pool_stride(info.encoding) + 3u) & ~3u;
  }
  p.encodings.z = std::max<uint32_t>(1, uint32_t(tree.materials.size()));
  p.brick_bytes = bytes;
  p.brick_count = tree.brick_count;
  p.bricks.assign(size_t(p.brick_count) * p.brick_bytes + 4, 0);
  // The file stores B^3 samples per brick; the pool keeps (B + 1)^3, the
  // upper faces copied from the neighbouring bricks (encoded bytes, exact) or
  // reconstructed where those are absent (octree.h, sampler.h).
  const octree::BrickFaces faces(tree);
  tbb::enumerable_thread_specific<std::vector<octree::LatticeSource>> plans;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tree.nodes.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<octree::LatticeSource>& plan = plans.local();
    for (size_t n = r.begin(); n != r.end(); ++n) {
      const uint32_t b = tree.nodes[n].brick;
      if (b == octree::kNone) continue;
      faces.plan(uint32_t(n), plan);
      for (size_t c = 0; c < tree.channels.size(); ++c) {
        const uint32_t size = octree::encoding_bytes(tree.channels[c].encoding);
        const uint32_t stride = pool_stride(tree.channels[c].encoding);
        const bool distance = tree.channels[c].channel == Channel::Distance;
        const uint8_t* from = tree.brick_data[c].data();
        uint8_t* to = p.bricks.data() + size_t(b) * p.brick_bytes + offset[c];
        // Stored samples are copied; the reconstructed distances computed.
        auto copy = [&](auto bytes) {
          for (uint32_t i = 0; i < samples; ++i) {
            if (distance && plan[i].axes != 0) {
              octree::source_bytes(tree, c, plan[i], to + size_t(i) * stride);
            } else {
              std::memcpy(to + size_t(i) * stride, from + plan[i].sample * bytes.value, bytes.value);
            }
          }
        };
        switch (size) {
          case 1:
            copy(std::integral_constant<uint32_t, 1>());
            break;
          case 2:
            copy(std::integral_constant<uint32_t, 2>());
            break;
          case 3:
            copy(std::integral_constant<uint32_t, 3>());
            break;
          default:
            copy(std::integral_constant<uint32_t, 4>());
            break;
        }
      }
    }
  });
  return p;
}

namespace {

// Corner k (bit 0: x, 1: y, 2: z at the box's upper side) of the domain box.
glm::vec3 domain_corner(const TraceParams& p, uint32_t k) {
  return glm::vec3(p.domain) + p.domain.w * glm::vec3(float(k & 1u), float((k >> 1u) & 1u), float(k >> 2u));
}

}  // namespace

PixelRect domain_pixel_rect(const TraceParams& p) {
  const uint32_t width = p.image.x, height = p.image.y;
  const PixelRect whole{0, 0, width, height};
  if (p.cam_w.w > 0) return whole;
  // A point eye + s (w + x u - y v) is seen at ndc (x, y) (svo_pixel_direction).
  const glm::mat3 to_camera = glm::inverse(glm::mat3(glm::vec3(p.cam_w), glm::vec3(p.cam_u), -glm::vec3(p.cam_v)));
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  uint32_t behind = 0;
  for (uint32_t k = 0; k < 8; ++k) {
    const glm::vec3 corner = domain_corner(p, k);
    const glm::vec3 q = to_camera * (corner - glm::vec3(p.eye));
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) return whole;
    if (q.x < 0.0f) {
      behind += 1;
      continue;
    }
    if (!(q.x > 1e-4f * glm::length(corner - glm::vec3(p.eye)))) return whole;
    const glm::vec2 at = (glm::vec2(q.y, q.z) / q.x + 1.0f) * 0.5f * glm::vec2(float(width), float(height));
    lo = glm::min(lo, at);
    hi = glm::max(hi, at);
  }
  // The whole box behind the eye: every cone looks away from it.
  if (behind == 8) return PixelRect{};
  if (behind > 0) return whole;
  // Pixel i's centre is at i + 0.5; 2 pixels of margin on each side.
  auto first = [](float x, uint32_t n) { return uint32_t(std::clamp(std::floor(x) - 2.0f, 0.0f, float(n))); };
  auto end = [](float x, uint32_t n) { return uint32_t(std::clamp(std::ceil(x) + 2.0f, 0.0f, float(n))); };
  PixelRect r{first(lo.x, width), first(lo.y, height), end(hi.x, width), end(hi.y, height)};
  return r.empty() ? PixelRect{} : r;
}

bool cones_may_blend(const TraceParams& p) {
  using namespace svo::math;
  if (p.cam_w.w > 0 || (p.image.w & SVO_FLAG_SHADOWS) != 0u) return true;
  const float finest = p.material.z;
  float farthest = 0;
  for (uint32_t k = 0; k < 8; ++k) {
    const glm::vec3 corner = domain_corner(p, k);
    farthest = std::max(farthest, glm::length(corner - glm::vec3(p.eye)));
  }
  // svo_cone_radius and svo_step's element: r = max(k t, 1e-7 domain),
  // half length max(r, finest / 4) (finer where detail octaves are drawn).
  const float r = std::max(p.eye.w * farthest, 1.0e-7f * p.domain.w);
  const float voxel = (r + std::max(r, 0.25f * finest)) / SVO_SQRT2;
  return !(std::isfinite(voxel) && voxel <= 0.99f * finest);
}

namespace {

// Whether the octree's provenance (svo voxelize) says that some of its
// surface is drawn as a two-sided shell; false for files without it.
bool two_sided(const octree::Octree& tree) {
  if (tree.source.empty()) return false;
  const nlohmann::json j = nlohmann::json::parse(tree.source, nullptr, false);
  if (!j.is_object()) return false;
  const auto it = j.find("two_sided");
  return it != j.end() && it->is_boolean() && it->get<bool>();
}

}  // namespace

uint32_t lens_parts(const octree::Octree& tree, const RenderSettings& s) {
  const Camera& c = s.camera;
  if (s.mode == Mode::RayMarch || !(c.aperture > 0) || !(c.focus > 0)) return 1;
  if (s.lens_parts > 0) return s.lens_parts;
  // The widest the whole lens's cone gets inside the domain's bounding
  // sphere (the pixel's own footprint left out), against what a quarter of
  // the coarsest voxel / sqrt(2) resolves (tracer.glsl, svo_trace_pixel).
  const float reach = glm::length(c.eye - (tree.origin + glm::vec3(0.5f * tree.size)));
  const float half_diagonal = 0.5f * std::sqrt(3.0f) * tree.size;
  const float widest = c.aperture *
                       std::max(std::abs(reach + half_diagonal - c.focus),
                                std::abs(std::max(reach - half_diagonal, 0.0f) - c.focus)) /
                       c.focus;
  // Half that where the octree holds shells (a sheet drawn two-sided):
  // each part's cone reads a level whose shell is 1.25 of its voxels thick
  // (2 when this was measured), and the blurred sheet swells by about one
  // (the lion's strong blur at 256^3: 2 x 2 parts left 234 pixels off and
  // 4,422 specks, 4 x 4 none and 134).
  const float share = two_sided(tree) ? 0.125f : 0.25f;
  const float coarsest = tree.size / (float(tree.brick_size) * std::sqrt(2.0f));
  return uint32_t(std::clamp(std::ceil(widest / (share * coarsest)), 1.0f, 4.0f));
}

TraceParams make_trace_params(const octree::Octree& tree, const PackedOctree& packed, const RenderSettings& s) {
  if (s.width == 0 || s.height == 0) throw std::invalid_argument("image size must be at least 1x1");
  if (s.lights.size() > size_t(kMaxLights)) {
    throw std::invalid_argument("at most " + std::to_string(kMaxLights) + " lights, got " +
                                std::to_string(s.lights.size()));
  }
  const Camera& c = s.camera;
  if (!finite(c.eye) || !finite(c.target) || !finite(c.up)) throw std::invalid_argument("camera is not finite");
  glm::vec3 w = c.target - c.eye;
  if (!(glm::length(w) > 0)) throw std::invalid_argument("camera eye and target coincide");
  w = glm::normalize(w);
  glm::vec3 u = glm::cross(w, c.up);
  if (!(glm::length(u) > 1e-6f * glm::length(c.up))) throw std::invalid_argument("camera up is parallel to the view");
  u = glm::normalize(u);
  glm::vec3 v = glm::cross(u, w);
  if (!(c.fov_deg > 0 && c.fov_deg < 180)) throw std::invalid_argument("field of view must be in (0, 180) degrees");
  if (!(c.aperture >= 0) || (c.aperture > 0 && !(c.focus > 0))) {
    throw std::invalid_argument("depth of field needs an aperture >= 0 and a focus distance > 0");
  }
  const float tan_half = std::tan(glm::radians(c.fov_deg) * 0.5f);
  const float aspect = float(s.width) / float(s.height);
  TraceParams p{};
  // A disk of the pixel's area: radius = pixel side / sqrt(pi).
  const float pixel = 2.0f * tan_half / float(s.height);
  p.eye = glm::vec4(c.eye, pixel / std::sqrt(svo::math::SVO_PI));
  p.cam_u = glm::vec4(u * tan_half * aspect, 0);
  p.cam_v = glm::vec4(v * tan_half, 0);
  p.cam_w = glm::vec4(w, c.aperture);
  const uint32_t root = uint32_t(std::lround(std::sqrt(double(s.spp))));
  if (s.spp == 0 || root * root != s.spp || s.spp > 4096) {
    throw std::invalid_argument("rays per pixel must be a square in [1, 4096], got " + std::to_string(s.spp));
  }
  if (s.lens_parts > 8) throw std::invalid_argument("lens parts must be in [0, 8], got " + std::to_string(s.lens_parts));
  // Raymarch: spp rays per pixel, root a side; cones: the lens's parts a
  // side (1 without a lens). lens.z, lens.w: the first row and the rows of
  // them to trace, all of them unless a host splits them (gpu_renderer).
  const uint32_t parts = lens_parts(tree, s);
  p.lens = s.mode == Mode::RayMarch ? glm::vec4(c.focus, float(s.spp), 0, float(root))
                                    : glm::vec4(c.focus, float(parts), 0, float(parts));
  p.domain = glm::vec4(tree.origin, tree.size);
  const float finest = tree.voxel_size(tree.depth_count - 1);
  if (const octree::Detail& d = tree.detail; d.octaves > 0) {
    p.detail = glm::vec4(d.amplitude, d.wavelength, d.gain, 0);
    p.detail_colour = glm::vec4(d.colour_slope, finest / svo::math::SVO_SQRT2);
    p.detail_u = glm::uvec4(d.octaves, d.seed, 0, 0);
  }
  if (!(s.footprint_spread >= 0 && s.footprint_spread <= 4)) {
    throw std::invalid_argument("footprint spread must be in [0, 4], got " + std::to_string(s.footprint_spread));
  }
  p.material = glm::vec4(tree.sigma_rho2, s.specular, finest, s.footprint_spread);
  if (!(s.shading_voxel >= 0.25f && s.shading_voxel <= 4.0f)) {
    throw std::invalid_argument("shading voxel must be in [0.25, 4] cone radii, got " + std::to_string(s.shading_voxel));
  }
  p.shading = glm::vec4(s.shading_voxel, two_sided(tree) ? 1.0f : 0.0f, 0, 0);
  p.constant_colour = glm::vec4(tree.constant_colour, 0);
  p.ambient = glm::vec4(s.ambient, 0);
  p.background = glm::vec4(s.background, 0);
  p.image = glm::uvec4(s.width, s.height, uint32_t(s.mode),
                       (s.shadows ? svo::math::SVO_FLAG_SHADOWS : 0u) | (s.gbuffer ? svo::math::SVO_FLAG_GBUFFER : 0u) |
                       (s.curved_masks ? svo::math::SVO_FLAG_CURVED_MASKS : 0u) |
                       (s.front_facing ? svo::math::SVO_FLAG_FRONT_FACING : 0u) |
                       (s.element_normals ? svo::math::SVO_FLAG_ELEMENT_NORMALS : 0u) |
                       (s.covered_part ? svo::math::SVO_FLAG_COVERED_PART : 0u) |
                       (s.crease_split ? svo::math::SVO_FLAG_CREASE_SPLIT : 0u));
  p.tree = glm::uvec4(tree.brick_size, tree.depth_count, s.max_steps, uint32_t(s.lights.size()));
  p.pool = glm::uvec4(packed.brick_bytes, 0, 0, 0);
  p.offsets_a = packed.offsets_a;
  p.offsets_b = packed.offsets_b;
  p.offsets_c = packed.offsets_c;
  p.encodings = packed.encodings;
  for (size_t i = 0; i < s.lights.size(); ++i) {
    const Light& l = s.lights[i];
    if (!finite(l.vector) || !finite(l.radiance) || !std::isfinite(l.size) || l.size < 0) {
      throw std::invalid_argument("light " + std::to_string(i + 1) + " is not finite or has a negative size");
    }
    glm::vec3 vec = l.vector;
    if (!l.point) {
      if (!(glm::length(vec) > 0)) throw std::invalid_argument("light " + std::to_string(i + 1) + " has no direction");
      vec = glm::normalize(vec);
    }
    p.light_vector[i] = glm::vec4(vec, l.point ? 1.0f : 0.0f);
    p.light_radiance[i] = glm::vec4(l.radiance, l.size);
  }
  return p;
}

const MaskTable& tracer_mask_table() {
  static const MaskTable table = build_mask_table(poisson_disk(kMaskBits), int(svo::math::SVO_MASK_BINS),
                                                  int(svo::math::SVO_MASK_BINS));
  return table;
}

const std::vector<Mask>& tracer_mask_buffer() {
  static const std::vector<Mask> buffer = tracer_buffer(tracer_mask_table());
  return buffer;
}

void finish_frame_stats(Frame& frame) {
  frame.covered_pixels = 0;
  uint64_t steps = 0;
  for (const auto& c : frame.colour) frame.covered_pixels += c.a > 0 ? 1 : 0;
  for (uint32_t s : frame.steps) steps += s;
  frame.steps_per_pixel = frame.steps.empty() ? 0.0 : double(steps) / double(frame.steps.size());
}

}  // namespace svo::render
