#include "svo/render/camera.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "svo/octree/files.h"
#include "svo/octree/sampler.h"

namespace svo::render {

namespace {

constexpr float kPresetFov = 40.0f;
// mid: 2x closer than the framed far view, about as close as 3x closer than
// the whole domain's far view (PresetOptions::whole_domain).
constexpr float kMidCloser = 2.0f, kDomainMidCloser = 3.0f;
constexpr float kFrameFill = 0.9f;       // the far view's object spans at most 90% of the narrower field
constexpr float kFillIrradiance = 0.6f;  // the default fill light: a fifth of the key's 3
// close: the finest voxel spans 1/64 of the narrower field (8 pixels at 512),
// magnified enough to see each voxel's shading, not so far that the image is
// a blur of interpolated voxels. With procedural detail octaves (finer than
// any voxel) the surface holds detail at any zoom: 8 voxels away, or 2% of
// the domain, the deep-zoom view.
// Never farther than half the mid view's distance (a coarse octree's 64
// voxels can be wider than the object).
constexpr float kCloseVoxelsAcross = 64.0f, kCloseCloser = 2.0f;
constexpr float kDetailCloseVoxels = 8.0f, kDetailCloseFraction = 0.02f;
const glm::vec3 kWorldUp(0, 1, 0);
// validate_camera: eye and target coordinates within +-1e18, so that the
// tracer's squared distances (up to 3 (2e18)^2) stay finite in float.
constexpr float kMaxCameraCoordinate = 1e18f;

std::string vec_text(glm::vec3 v) {
  std::ostringstream s;
  s << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

// Untrusted text as it may appear inside a one-line message: control bytes
// (a newline among them) as \xNN, at most 80 bytes then "...".
std::string printable(std::string_view text) {
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (size_t i = 0; i < text.size() && i < 80; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += char(c);
    }
  }
  if (text.size() > 80) out += "...";
  return out;
}

// Splits on commas; each piece must be a finite number (spaces around it allowed).
// Returns the numbers, or throws "<where>: <problem>".
std::vector<float> parse_numbers(std::string_view text, const std::string& where) {
  std::vector<float> out;
  size_t start = 0;
  for (int index = 1;; ++index) {
    size_t comma = text.find(',', start);
    std::string_view piece = text.substr(start, comma == std::string_view::npos ? text.npos : comma - start);
    while (!piece.empty() && std::isspace(static_cast<unsigned char>(piece.front()))) piece.remove_prefix(1);
    while (!piece.empty() && std::isspace(static_cast<unsigned char>(piece.back()))) piece.remove_suffix(1);
    std::string_view digits = piece;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    float v = 0;
    auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size() || !std::isfinite(v)) {
      throw std::invalid_argument(where + ": value " + std::to_string(index) + " '" + printable(piece) +
                                  "' is not a finite number");
    }
    out.push_back(v);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// ---- Surface search through the finest level's hbar.

struct SurfaceHit {
  glm::vec3 point;
  glm::vec3 normal;  // unit, facing the ray's origin
};

class DistanceSampler {
 public:
  explicit DistanceSampler(const octree::Octree& tree)
      : tree_(tree), depth_(tree.depth_count - 1), voxel_(tree.voxel_size(depth_)) {}

  float voxel() const { return voxel_; }

  // Trilinear hbar and nbar at p; nullopt unless all 8 lattice corners lie in bricks.
  std::optional<std::pair<float, glm::vec3>> at(glm::vec3 p) const {
    glm::vec3 q = (p - tree_.origin) / voxel_;
    glm::vec3 fl = glm::floor(q);
    glm::ivec3 base(fl);
    glm::vec3 f = q - fl;
    float h = 0;
    glm::vec3 n(0);
    for (int i = 0; i < 8; ++i) {
      glm::ivec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1);
      auto v = octree::lattice_voxel(tree_, depth_, base + o);
      if (!v) return std::nullopt;
      float w = (o.x ? f.x : 1 - f.x) * (o.y ? f.y : 1 - f.y) * (o.z ? f.z : 1 - f.z);
      h += w * v->hbar;
      n += w * v->nbar;
    }
    return std::make_pair(h, n);
  }

  // First crossing of hbar from positive to negative along eye + t dir
  // (dir unit) inside the domain cube, in half-voxel steps, refined by bisection.
  std::optional<SurfaceHit> march(glm::vec3 eye, glm::vec3 dir) const {
    glm::vec3 lo = tree_.origin, hi = tree_.origin + glm::vec3(tree_.size);
    float t0 = 0, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir[a]) < 1e-12f) {
        if (eye[a] < lo[a] || eye[a] > hi[a]) return std::nullopt;
        continue;
      }
      float ta = (lo[a] - eye[a]) / dir[a], tb = (hi[a] - eye[a]) / dir[a];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    if (t0 >= t1) return std::nullopt;
    const float step = 0.5f * voxel_;
    std::optional<float> previous;  // hbar at t - step, when known
    const int64_t steps = int64_t((t1 - t0) / step) + 1;
    for (int64_t i = 0; i <= steps; ++i) {
      const float t = t0 + float(i) * step;
      auto s = at(eye + t * dir);
      if (s && previous && *previous > 0 && s->first <= 0) {
        float a = t - step, b = t;
        for (int k = 0; k < 24; ++k) {
          float m = 0.5f * (a + b);
          auto sm = at(eye + m * dir);
          if (!sm) break;
          (sm->first > 0 ? a : b) = m;
        }
        glm::vec3 p = eye + 0.5f * (a + b) * dir;
        auto sp = at(p);
        glm::vec3 n = sp && glm::length(sp->second) > 1e-6f ? glm::normalize(sp->second) : -dir;
        if (glm::dot(n, dir) > 0) n = -n;
        return SurfaceHit{p, n};
      }
      previous = s ? std::optional<float>(s->first) : std::nullopt;
    }
    return std::nullopt;
  }

  // Whether the segment point + t dir, 2 voxels <= t <= length, keeps its
  // distance from the surface: hbar >= rise * t wherever the finest level
  // stores it (rise: half the cosine between dir and the normal at point).
  bool clear(glm::vec3 point, glm::vec3 dir, float length, float rise) const {
    for (int i = 4; float(i) * 0.5f * voxel_ <= length; ++i) {
      const float t = float(i) * 0.5f * voxel_;
      auto s = at(point + t * dir);
      if (s && s->first < rise * t) return false;
    }
    return true;
  }

 private:
  const octree::Octree& tree_;
  uint32_t depth_;
  float voxel_;
};

// What the presets frame: the finest level's bricks (where the surface is),
// or the domain cube standing in as one brick when there are none.
struct Framed {
  std::vector<glm::vec3> corners;  // lower corners of the bricks
  float size = 0;                  // their edge
  glm::vec3 lo{0}, hi{0};          // their bounds
  bool surface = false;            // whether the octree has a finest brick
};

Framed framed(const octree::Octree& tree) {
  Framed out;
  if (!tree.nodes.empty() && tree.depth_count > 0) {
    const uint32_t finest = tree.depth_count - 1;
    out.size = tree.size / float(1u << finest);
    struct Item {
      uint32_t node, depth;
      glm::ivec3 coords;
    };
    std::vector<Item> stack{{0, 0, glm::ivec3(0)}};
    while (!stack.empty()) {
      Item item = stack.back();
      stack.pop_back();
      if (item.node >= tree.nodes.size()) continue;
      const octree::Node& node = tree.nodes[item.node];
      if (item.depth == finest) {
        if (node.brick != octree::kNone) out.corners.push_back(tree.origin + glm::vec3(item.coords) * out.size);
        continue;
      }
      if (node.children == octree::kNone) continue;
      for (uint32_t i = 0; i < 8; ++i) {
        glm::ivec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1);
        stack.push_back({node.children + i, item.depth + 1, item.coords * 2 + o});
      }
    }
  }
  out.surface = !out.corners.empty();
  if (!out.surface) out.corners = {tree.origin}, out.size = tree.size;
  out.lo = glm::vec3(1e30f), out.hi = glm::vec3(-1e30f);
  for (glm::vec3 a : out.corners) out.lo = glm::min(out.lo, a), out.hi = glm::max(out.hi, a + glm::vec3(out.size));
  return out;
}

glm::vec3 preset_direction(const PresetOptions& p) {
  float az = glm::radians(p.azimuth_deg), el = glm::radians(p.elevation_deg);
  return glm::vec3(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
}

// An up vector not parallel to `forward`.
glm::vec3 up_for(glm::vec3 forward) {
  if (std::abs(glm::dot(glm::normalize(forward), kWorldUp)) < 0.98f) return kWorldUp;
  return glm::vec3(0, 0, -1);
}

// The least distance from `centre` along `dir` at which every corner of the
// framed bricks lies inside kFrameFill of the field of view: a corner q
// (from the centre) at lateral offsets x, y and depth D - q.dir needs
// D >= |x| / tan_h + q.dir (and the same with y, tan_v).
float framing_distance(const Framed& f, glm::vec3 centre, glm::vec3 dir, glm::vec3 up, float aspect) {
  const glm::vec3 forward = -dir;
  const glm::vec3 right = glm::normalize(glm::cross(forward, up)), true_up = glm::cross(right, forward);
  const float tv = std::tan(glm::radians(0.5f * kPresetFov)) * kFrameFill, th = tv * aspect;
  float distance = 0, reach = 0;
  for (glm::vec3 a : f.corners) {
    for (int i = 0; i < 8; ++i) {
      const glm::vec3 q = a + f.size * glm::vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1) - centre;
      const float need = std::max(std::abs(glm::dot(q, right)) / th, std::abs(glm::dot(q, true_up)) / tv);
      distance = std::max(distance, need + glm::dot(q, dir));
      reach = std::max(reach, glm::length(q));
    }
  }
  // Never inside the object: beyond its farthest point from the centre.
  return std::max(distance, 1.05f * reach);
}

// The whole domain cube in frame (PresetOptions::whole_domain).
Camera domain_view(const octree::Octree& tree, float aspect, const PresetOptions& p) {
  Camera c;
  c.fov_deg = kPresetFov;
  c.target = tree.origin + glm::vec3(0.5f * tree.size);
  const float half_v = glm::radians(0.5f * kPresetFov), half_h = std::atan(std::tan(half_v) * aspect);
  const float radius = 0.5f * std::sqrt(3.0f) * tree.size;  // the cube's bounding sphere
  const glm::vec3 dir = preset_direction(p);
  c.up = up_for(-dir);
  c.eye = c.target + dir * (radius / std::sin(std::min(half_v, half_h)));
  return c;
}

Camera far_view(const octree::Octree& tree, const Framed& f, float aspect, const PresetOptions& p) {
  if (p.whole_domain) return domain_view(tree, aspect, p);
  const glm::vec3 dir = preset_direction(p);
  Camera c;
  c.fov_deg = kPresetFov;
  c.target = 0.5f * (f.lo + f.hi);
  c.up = up_for(-dir);
  const float distance =
      p.distance > 0 ? p.distance * glm::length(f.hi - f.lo) : framing_distance(f, c.target, dir, c.up, aspect);
  c.eye = c.target + dir * distance;
  return c;
}

Camera mid_view(const octree::Octree& tree, const Framed& f, float aspect, const PresetOptions& p) {
  if (!f.surface) throw std::runtime_error("view mid: the octree holds no surface (no brick at the finest level)");
  PresetOptions framing = p;
  framing.distance = 0;
  Camera c = far_view(tree, f, aspect, framing);
  const float far_distance = glm::length(c.eye - c.target);
  const float closer = p.whole_domain ? kDomainMidCloser : kMidCloser;
  c.target = 0.5f * (f.lo + f.hi);
  c.eye =
      c.target + preset_direction(p) * (p.distance > 0 ? p.distance * glm::length(f.hi - f.lo) : far_distance / closer);
  return c;
}

// close_distance given the mid view's distance from its target.
float close_distance_from(const octree::Octree& tree, float aspect, float mid_distance) {
  const float voxel = tree.voxel_size(tree.depth_count - 1);
  if (tree.detail.octaves > 0) return std::max(kDetailCloseVoxels * voxel, kDetailCloseFraction * tree.size);
  const float narrower_half_field = std::tan(glm::radians(0.5f * kPresetFov)) * std::min(1.0f, aspect);
  return std::min(kCloseVoxelsAcross * voxel / (2 * narrower_half_field), mid_distance / kCloseCloser);
}

Camera mid_preset(const octree::Octree& tree, const Framed& f, float aspect, const PresetOptions& p) {
  PresetOptions framing = p;
  framing.distance = 0;
  return mid_view(tree, f, aspect, framing);
}

Camera close_view(const octree::Octree& tree, const Framed& f, float aspect, const PresetOptions& p) {
  Camera mid = mid_preset(tree, f, aspect, p);
  DistanceSampler sampler(tree);
  glm::vec3 forward = glm::normalize(mid.target - mid.eye);
  glm::vec3 right = glm::normalize(glm::cross(forward, mid.up));
  glm::vec3 up = glm::cross(right, forward);
  float tv = std::tan(glm::radians(0.5f * mid.fov_deg)), th = tv * aspect;
  // The centre ray first, then rings of rays further out in the mid view's image.
  std::vector<glm::vec2> offsets{{0, 0}};
  for (int ring = 1; ring <= 6; ++ring) {
    int count = 8 * ring;
    for (int k = 0; k < count; ++k) {
      float angle = 2 * float(M_PI) * float(k) / float(count);
      offsets.push_back(float(ring) / 6.0f * 0.95f * glm::vec2(std::cos(angle), std::sin(angle)));
    }
  }
  std::optional<SurfaceHit> hit;
  glm::vec3 ray;
  for (glm::vec2 o : offsets) {
    ray = glm::normalize(forward + o.x * th * right + o.y * tv * up);
    if ((hit = sampler.march(mid.eye, ray))) break;
  }
  if (!hit) throw std::runtime_error("view close: no ray of the mid view meets the surface");

  const float distance = p.distance > 0 ? p.distance * glm::length(f.hi - f.lo)
                                        : close_distance_from(tree, aspect, glm::length(mid.eye - mid.target));
  glm::vec3 n = hit->normal, towards_viewer = -ray;
  glm::vec3 tangent = towards_viewer - n * glm::dot(n, towards_viewer);
  if (glm::length(tangent) < 1e-4f) {  // looking along the normal: any tangent
    tangent = glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
  }
  tangent = glm::normalize(tangent);
  Camera c;
  c.fov_deg = kPresetFov;
  c.target = hit->point;
  for (float degrees : {60.0f, 45.0f, 30.0f, 15.0f, 0.0f}) {
    float a = glm::radians(degrees);
    glm::vec3 dir = n * std::cos(a) + tangent * std::sin(a);
    c.eye = hit->point + distance * dir;
    if (sampler.clear(hit->point, dir, distance, 0.5f * std::cos(a))) break;
  }
  c.up = up_for(c.target - c.eye);
  return c;
}

}  // namespace

float close_distance(const octree::Octree& tree, float aspect, const PresetOptions& options) {
  const Framed f = framed(tree);
  const Camera mid = mid_preset(tree, f, aspect, options);
  return close_distance_from(tree, aspect, glm::length(mid.eye - mid.target));
}

std::optional<glm::vec3> march_to_surface(const octree::Octree& tree, glm::vec3 origin, glm::vec3 dir) {
  if (tree.depth_count == 0 || !(tree.size > 0) || !finite(origin) || !finite(dir) || !(glm::length(dir) > 0)) {
    return std::nullopt;
  }
  auto hit = DistanceSampler(tree).march(origin, glm::normalize(dir));
  if (!hit) return std::nullopt;
  return hit->point;
}

std::vector<std::string> view_preset_names() { return {"far", "mid", "close"}; }

std::pair<glm::vec3, glm::vec3> object_bounds(const octree::Octree& tree) {
  const Framed f = framed(tree);
  return {f.lo, f.hi};
}

float object_size(const octree::Octree& tree) {
  const auto [lo, hi] = object_bounds(tree);
  return glm::length(hi - lo);
}

std::vector<Light> default_lights(const Camera& camera) {
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up)), up = glm::cross(right, forward);
  Light key, fill;
  key.vector = glm::normalize(-0.5f * right + 0.75f * up - 0.45f * forward);
  fill.vector = glm::normalize(0.7f * right - 0.1f * up - 0.7f * forward);
  fill.radiance = glm::vec3(kFillIrradiance);
  return {key, fill};
}

Camera view_preset(const octree::Octree& tree, std::string_view name, float aspect, const PresetOptions& options) {
  if (!(aspect > 0) || !std::isfinite(aspect)) throw std::invalid_argument("view preset: aspect must be positive");
  if (tree.depth_count == 0 || !(tree.size > 0))
    throw std::invalid_argument("view preset: octree without levels or size");
  if (!(std::isfinite(options.azimuth_deg) && std::abs(options.elevation_deg) < 90.0f) ||
      !(options.distance >= 0 && std::isfinite(options.distance))) {
    throw std::invalid_argument(
        "view preset: azimuth must be finite, elevation within (-90, 90) degrees and distance >= 0");
  }
  if (name == "far") return far_view(tree, framed(tree), aspect, options);
  if (name == "mid") return mid_view(tree, framed(tree), aspect, options);
  if (name == "close") return close_view(tree, framed(tree), aspect, options);
  throw std::invalid_argument("unknown view '" + printable(name) + "' (views: far, mid, close)");
}

void validate_camera(const Camera& c, const std::string& where) {
  auto fail = [&](const std::string& why) { throw std::invalid_argument(where + ": " + why); };
  if (!finite(c.eye) || !finite(c.target) || !finite(c.up) || !std::isfinite(c.fov_deg) || !std::isfinite(c.aperture) ||
      !std::isfinite(c.focus)) {
    fail("values must be finite numbers");
  }
  // In double: the squares of float coordinates beyond ~1e19 overflow a float.
  const glm::dvec3 eye(c.eye), target(c.target), up(c.up);
  const glm::dvec3 view = target - eye;
  const double length = glm::length(view);
  for (const auto& [name, p] : {std::pair{"eye", c.eye}, std::pair{"target", c.target}}) {
    if (std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) > kMaxCameraCoordinate) {
      std::ostringstream s;
      s << name << " " << vec_text(p) << " is too far out (" << length << " from the "
        << (std::string(name) == "eye" ? "target" : "eye") << "): coordinates must be within +-" << kMaxCameraCoordinate
        << ", beyond which float arithmetic overflows";
      fail(s.str());
    }
  }
  if (length == 0) fail("eye and target are the same point " + vec_text(c.eye));
  if (!(length > 1e-6 * std::max(1.0, glm::length(eye)))) {
    std::ostringstream s;
    s << "eye " << vec_text(c.eye) << " and target " << vec_text(c.target) << " are too close for float precision ("
      << length << " apart; at least 1e-6 x max(1, |eye|) = " << 1e-6 * std::max(1.0, glm::length(eye)) << ")";
    fail(s.str());
  }
  if (!(glm::length(up) > 0)) fail("up is the zero vector");
  if (glm::length(glm::cross(view / length, glm::normalize(up))) < 1e-3) {
    fail("up " + vec_text(c.up) + " is parallel to the view direction " + vec_text(glm::vec3(view / length)));
  }
  if (!(c.fov_deg > 0 && c.fov_deg < 180)) {
    std::ostringstream s;
    s << "fov " << c.fov_deg << " is outside (0, 180) degrees";
    fail(s.str());
  }
  if (c.aperture < 0) fail("aperture must be >= 0");
  if (c.aperture > 0 && !(c.focus > 0)) fail("focus must be > 0 with an aperture");
}

Camera parse_camera(std::string_view text) {
  const std::string where = "--camera '" + printable(text) + "'";
  std::vector<float> v = parse_numbers(text, where);
  if (v.size() != 10) {
    throw std::invalid_argument(where + ": expected 10 numbers ex,ey,ez,tx,ty,tz,ux,uy,uz,fov, got " +
                                std::to_string(v.size()));
  }
  Camera c;
  c.eye = {v[0], v[1], v[2]};
  c.target = {v[3], v[4], v[5]};
  c.up = {v[6], v[7], v[8]};
  c.fov_deg = v[9];
  validate_camera(c, where);
  return c;
}

Camera load_camera_json(const std::string& path) {
  // A regular file of at most 1 MiB: a FIFO or /dev/zero named here would
  // hang or eat memory.
  return parse_camera_json(files::read_bounded(path, 1 << 20, "a camera file (JSON)"), path);
}

Camera parse_camera_json(std::string_view text, const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    std::string what = e.what();
    if (auto close = what.find("] "); close != std::string::npos) what = what.substr(close + 2);
    throw std::runtime_error(path + ": not a JSON camera file: " + what);
  }
  auto fail = [&](const std::string& why) { throw std::invalid_argument(path + ": " + why); };
  if (!j.is_object()) fail("expected a JSON object with eye, target, up and fov");
  auto vec3 = [&](const char* key) {
    if (!j.contains(key)) fail(std::string("missing key \"") + key + "\"");
    const auto& a = j[key];
    if (!a.is_array() || a.size() != 3 || !a[0].is_number() || !a[1].is_number() || !a[2].is_number()) {
      fail(std::string("\"") + key + "\" must be an array of 3 numbers");
    }
    return glm::vec3(a[0].get<float>(), a[1].get<float>(), a[2].get<float>());
  };
  auto number = [&](const char* key, std::optional<float> fallback) {
    if (!j.contains(key)) {
      if (!fallback) fail(std::string("missing key \"") + key + "\"");
      return *fallback;
    }
    if (!j[key].is_number()) fail(std::string("\"") + key + "\" must be a number");
    return j[key].get<float>();
  };
  Camera c;
  c.eye = vec3("eye");
  c.target = vec3("target");
  c.up = vec3("up");
  c.fov_deg = number("fov", std::nullopt);
  c.aperture = number("aperture", 0.0f);
  c.focus = number("focus", 0.0f);
  validate_camera(c, path);
  return c;
}

void save_camera_json(const std::string& path, const Camera& c) {
  // Each float as the shortest decimal that reads back as the same float.
  auto num = [](float v) {
    char text[32];
    auto end = std::to_chars(text, text + sizeof text, v).ptr;
    return std::strtod(std::string(text, end).c_str(), nullptr);
  };
  auto arr = [&](glm::vec3 v) { return nlohmann::json::array({num(v.x), num(v.y), num(v.z)}); };
  nlohmann::json j{{"eye", arr(c.eye)}, {"target", arr(c.target)}, {"up", arr(c.up)}, {"fov", num(c.fov_deg)}};
  if (c.aperture > 0) j["aperture"] = num(c.aperture), j["focus"] = num(c.focus);
  std::string text = j.dump(2) + "\n";
  files::write_file(path, text);
}

Light parse_light(std::string_view text, glm::vec3 scene_centre) {
  const std::string where = "--light '" + printable(text) + "'";
  Light light;
  std::string_view rest;
  if (text.starts_with("dir:")) {
    light.point = false;
    rest = text.substr(4);
  } else if (text.starts_with("point:")) {
    light.point = true;
    rest = text.substr(6);
  } else {
    throw std::invalid_argument(where +
                                ": expected dir:X,Y,Z[,IRRADIANCE[,ANGLE]] or point:X,Y,Z[,INTENSITY[,RADIUS]]");
  }
  std::vector<float> v = parse_numbers(rest, where);
  if (v.size() < 3 || v.size() > 5) {
    throw std::invalid_argument(where + ": expected 3 to 5 numbers after '" +
                                std::string(light.point ? "point:" : "dir:") + "', got " + std::to_string(v.size()));
  }
  light.vector = {v[0], v[1], v[2]};
  if (!light.point && !(glm::length(light.vector) > 0)) throw std::invalid_argument(where + ": direction is zero");
  float distance = glm::length(light.vector - scene_centre);
  float strength = light.point ? 3.0f * distance * distance : 3.0f;
  if (v.size() >= 4) {
    if (v[3] < 0) throw std::invalid_argument(where + ": intensity must be >= 0");
    strength = v[3];
  }
  light.radiance = glm::vec3(strength);
  light.size = light.point ? 0.01f * distance : 0.02f;
  if (v.size() == 5) {
    if (v[4] < 0) throw std::invalid_argument(where + ": size must be >= 0");
    if (!light.point && v[4] >= 0.5f * float(M_PI)) throw std::invalid_argument(where + ": angle must be below pi/2");
    light.size = v[4];
  }
  return light;
}

}  // namespace svo::render
