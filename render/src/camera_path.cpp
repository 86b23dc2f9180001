#include "svo/render/camera_path.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "svo/octree/files.h"
#include "svo/render/camera.h"

namespace svo::render {

namespace {

using dvec3 = glm::dvec3;

// Spherical linear interpolation of unit vectors a and b (double precision).
dvec3 slerp(dvec3 a, dvec3 b, double s) {
  const double c = std::clamp(glm::dot(a, b), -1.0, 1.0);
  if (c > 1.0 - 1e-12) return glm::normalize(a + s * (b - a));
  const double angle = std::acos(c);
  if (c < -1.0 + 1e-12) {
    // Opposite: turn about any axis perpendicular to a.
    dvec3 axis = glm::cross(a, std::abs(a.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0));
    axis = glm::normalize(axis);
    dvec3 perp = glm::cross(axis, a);
    return glm::normalize(std::cos(s * angle) * a + std::sin(s * angle) * perp);
  }
  const double sin_angle = std::sin(angle);
  return glm::normalize((std::sin((1 - s) * angle) * a + std::sin(s * angle) * b) / sin_angle);
}

double json_number(float v) {
  char text[32];
  auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

// One line from nlohmann's message: drops its "[json.exception.parse_error.101] " prefix.
std::string json_reason(const nlohmann::json::exception& e) {
  std::string what = e.what();
  if (auto close = what.find("] "); close != std::string::npos) what = what.substr(close + 2);
  return what;
}

}  // namespace

float view_width(const Camera& c) {
  return float(2.0 * glm::length(dvec3(c.target) - dvec3(c.eye)) * std::tan(glm::radians(0.5 * double(c.fov_deg))));
}

Camera sample_path(const std::vector<Camera>& keys, double u) {
  if (keys.empty()) throw std::invalid_argument("camera path: no keys");
  if (keys.size() == 1 || !(u > 0)) return keys.front();
  const double last = double(keys.size() - 1);
  if (u >= last) return keys.back();
  const size_t i = size_t(std::floor(u));
  const double s = u - double(i);
  const Camera& a = keys[i];
  const Camera& b = keys[i + 1];
  if (s == 0) return a;
  const dvec3 ta(a.target), tb(b.target), ea(a.eye), eb(b.eye);
  const double da = glm::length(ea - ta), db = glm::length(eb - tb);
  const dvec3 target = (1 - s) * ta + s * tb;
  const double distance = da * std::pow(db / da, s);  // d_a^(1-s) d_b^s
  const dvec3 dir = slerp((ea - ta) / da, (eb - tb) / db, s);
  Camera c;
  c.target = glm::vec3(target);
  c.eye = glm::vec3(target + distance * dir);
  c.up = glm::vec3(slerp(glm::normalize(dvec3(a.up)), glm::normalize(dvec3(b.up)), s));
  c.fov_deg = float((1 - s) * double(a.fov_deg) + s * double(b.fov_deg));
  return c;
}

std::vector<Camera> path_cameras(const CameraPath& path) {
  if (path.keys.size() < 2) throw std::invalid_argument("camera path: needs at least 2 keys");
  if (path.frames < 2) throw std::invalid_argument("camera path: needs at least 2 frames");
  if (path.frames > kMaxPathFrames) {
    throw std::invalid_argument("camera path: " + std::to_string(path.frames) + " frames, above the limit of " +
                                std::to_string(kMaxPathFrames));
  }
  std::vector<Camera> out;
  out.reserve(path.frames);
  const double span = double(path.keys.size() - 1);
  for (uint32_t f = 0; f < path.frames; ++f) {
    // Integer arithmetic first, so that key frames land exactly on a key.
    const uint64_t num = uint64_t(f) * (path.keys.size() - 1);
    const uint64_t den = path.frames - 1;
    const double u = num % den == 0 ? double(num / den) : double(f) * span / double(den);
    out.push_back(sample_path(path.keys, u));
  }
  return out;
}

CameraPath deep_zoom_path(const Camera& start, glm::vec3 target, float zoom, uint32_t frames) {
  if (!std::isfinite(zoom) || !(zoom >= 1)) {
    std::ostringstream s;
    s << "deep-zoom: zoom " << zoom << " must be a finite number >= 1";
    throw std::invalid_argument(s.str());
  }
  if (frames < 2) throw std::invalid_argument("deep-zoom: needs at least 2 frames, got " + std::to_string(frames));
  if (frames > kMaxPathFrames) {
    throw std::invalid_argument("deep-zoom: " + std::to_string(frames) + " frames, above the limit of " +
                                std::to_string(kMaxPathFrames));
  }
  Camera first = start;
  first.target = target;
  first.aperture = 0;
  first.focus = 0;
  validate_camera(first, "deep-zoom: start camera looking at the target");
  Camera last = first;
  const dvec3 t(target), e(first.eye);
  last.eye = glm::vec3(t + (e - t) / double(zoom));
  validate_camera(last, "deep-zoom: last camera (zoom too large for float precision at the target)");
  CameraPath path;
  path.keys = {first, last};
  path.frames = frames;
  return path;
}

std::optional<glm::vec3> surface_target(const octree::Octree& tree, const Camera& camera, float aspect) {
  const glm::vec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tv = std::tan(glm::radians(0.5f * camera.fov_deg)), th = tv * aspect;
  if (auto hit = march_to_surface(tree, camera.eye, forward)) return hit;
  for (int ring = 1; ring <= 6; ++ring) {
    const int count = 8 * ring;
    for (int k = 0; k < count; ++k) {
      const float angle = 2 * float(M_PI) * float(k) / float(count);
      const glm::vec2 o = float(ring) / 6.0f * 0.95f * glm::vec2(std::cos(angle), std::sin(angle));
      if (auto hit = march_to_surface(tree, camera.eye, forward + o.x * th * right + o.y * tv * up)) return hit;
    }
  }
  return std::nullopt;
}

std::optional<glm::vec3> silhouette_target(const octree::Octree& tree, const Camera& camera, float aspect) {
  const glm::dvec3 forward = glm::normalize(glm::dvec3(camera.target) - glm::dvec3(camera.eye));
  const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(camera.up)));
  const double th = std::tan(glm::radians(0.5 * double(camera.fov_deg))) * double(aspect);
  auto ray = [&](double x) { return march_to_surface(tree, camera.eye, glm::vec3(forward + x * th * right)); };
  std::optional<glm::vec3> hit = ray(0);
  if (!hit) return std::nullopt;
  // The first miss to the right, in steps of 1/128 of the half width.
  double lo = 0, hi = -1;
  for (int i = 1; i <= 128; ++i) {
    const double x = double(i) / 128.0;
    if (auto h = ray(x)) {
      lo = x, hit = h;
    } else {
      hi = x;
      break;
    }
  }
  if (hi < 0) return std::nullopt;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (auto h = ray(mid)) {
      lo = mid, hit = h;
    } else {
      hi = mid;
    }
  }
  return hit;
}

CameraPath parse_camera_path(std::string_view text, const std::string& source_name, uint32_t default_frames) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(source_name + ": not a JSON camera path: " + json_reason(e));
  }
  auto fail = [&](const std::string& why) { throw std::invalid_argument(source_name + ": " + why); };
  const nlohmann::json* keys = &j;
  CameraPath path;
  path.frames = default_frames;
  if (j.is_object()) {
    if (!j.contains("keys")) fail("missing key \"keys\" (a list of cameras)");
    keys = &j["keys"];
    if (j.contains("frames")) {
      const auto& f = j["frames"];
      const std::string range = "\"frames\" must be an integer from 2 to " + std::to_string(kMaxPathFrames);
      if (!f.is_number_integer()) fail(range);
      if (f.is_number_unsigned() ? f.get<uint64_t>() > kMaxPathFrames : f.get<int64_t>() > int64_t(kMaxPathFrames)) {
        fail("\"frames\" is " + f.dump() + ", above the limit of " + std::to_string(kMaxPathFrames) + " frames");
      }
      if (f.get<int64_t>() < 2) fail(range);
      path.frames = uint32_t(f.get<int64_t>());
    }
  } else if (!j.is_array()) {
    fail("expected a list of cameras or {\"keys\": [...]}");
  }
  if (!keys->is_array()) fail("\"keys\" must be a list of cameras");
  if (keys->size() < 2) fail("a camera path needs at least 2 keys, got " + std::to_string(keys->size()));
  for (size_t i = 0; i < keys->size(); ++i) {
    const auto& k = (*keys)[i];
    const std::string where = "key " + std::to_string(i + 1);
    if (!k.is_object()) fail(where + ": expected an object with eye, target, up and fov");
    auto number = [&](const nlohmann::json& v, const std::string& what) {
      if (!v.is_number()) fail(where + ": " + what + " must be a number");
      const double d = v.get<double>();
      if (!std::isfinite(d) || std::abs(d) > 3.0e38) fail(where + ": " + what + " is not a finite float");
      return float(d);
    };
    auto vec3 = [&](const char* name) {
      if (!k.contains(name)) fail(where + ": missing \"" + name + "\"");
      const auto& a = k[name];
      if (!a.is_array() || a.size() != 3) fail(where + ": \"" + name + "\" must be an array of 3 numbers");
      const std::string what = std::string("\"") + name + "\"";
      return glm::vec3(number(a[0], what), number(a[1], what), number(a[2], what));
    };
    Camera c;
    c.eye = vec3("eye");
    c.target = vec3("target");
    c.up = vec3("up");
    if (!k.contains("fov")) fail(where + ": missing \"fov\"");
    c.fov_deg = number(k["fov"], "\"fov\"");
    validate_camera(c, source_name + ": " + where);
    path.keys.push_back(c);
  }
  if (path.frames < 2) fail("a camera path needs at least 2 frames, got " + std::to_string(path.frames));
  return path;
}

CameraPath load_camera_path(const std::string& file, uint32_t default_frames) {
  // A regular file of at most 64 MiB (tens of thousands of keys fit).
  return parse_camera_path(files::read_bounded(file, 64 << 20, "a camera path file (JSON)"), file, default_frames);
}

std::string camera_path_json(const CameraPath& path) {
  auto arr = [](glm::vec3 v) { return nlohmann::json::array({json_number(v.x), json_number(v.y), json_number(v.z)}); };
  nlohmann::json keys = nlohmann::json::array();
  for (const Camera& c : path.keys) {
    keys.push_back(
        {{"eye", arr(c.eye)}, {"target", arr(c.target)}, {"up", arr(c.up)}, {"fov", json_number(c.fov_deg)}});
  }
  nlohmann::json j{{"frames", path.frames}, {"keys", keys}};
  return j.dump(2) + "\n";
}

void save_camera_path(const std::string& file, const CameraPath& path) {
  const std::string text = camera_path_json(path);
  files::write_file(file, text);
}

}  // namespace svo::render
