// Scene files (--scene-file): several meshes, each placed by a transform and
// given a material, merged into one TriangleMesh with a material per face.
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "svo/voxelizer/mesh.h"

namespace svo::voxelizer {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

constexpr uintmax_t kMaxJsonBytes = 1 << 20;
constexpr size_t kMaxObjects = 1024;
constexpr size_t kMaxSceneMaterials = 255;  // octree::kMaxMaterials

// The text of a regular file of at most kMaxJsonBytes; `where` starts messages.
std::string read_small_file(const fs::path& path, const std::string& where) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error(where + ": cannot open " + path.string());
  if (!S_ISREG(st.st_mode)) throw std::runtime_error(where + ": " + path.string() + " is not a regular file");
  if (uintmax_t(st.st_size) > kMaxJsonBytes) {
    throw std::runtime_error(where + ": " + path.string() + " is larger than 1 MiB");
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw std::runtime_error(where + ": cannot read " + path.string());
  return text.str();
}

// Text from the file in a message: control bytes as \xNN, at most 60 bytes,
// so that the message stays one line whatever the file holds.
std::string shown(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < 60; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7F) {
      static const char* hex = "0123456789ABCDEF";
      out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
    } else {
      out += char(c);
    }
  }
  return text.size() > 60 ? out + "..." : out;
}

// A path named by the file; one with a control byte is refused (every
// message naming it would break its line).
fs::path path_of(const json& value, const fs::path& folder, const std::string& at, const std::string& key) {
  const std::string text = value.get<std::string>();
  for (char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      throw std::runtime_error(at + ": key '" + key + "': the path '" + shown(text) + "' holds a control character");
    }
  }
  const fs::path p = text;
  return p.is_relative() ? folder / p : p;
}

json parse_json(const std::string& text, const std::string& where) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number beyond double (found by fuzzing)
    std::string why = e.what();
    for (char& c : why) c = c == '\n' ? ' ' : c;
    throw std::runtime_error(where + ": not JSON: " + why);
  }
}

// A material object with its "file" made absolute against `base` (so that
// the octree's copy is found from anywhere).
std::string material_text(json m, const fs::path& base, const std::string& where) {
  if (!m.is_object()) throw std::runtime_error(where + ": a material is a JSON object or the path of one");
  if (auto it = m.find("file"); it != m.end() && it->is_string()) {
    fs::path file = it->get<std::string>();
    if (file.is_relative()) *it = fs::absolute(base / file).lexically_normal().string();
  }
  return m.dump(-1, ' ', false, json::error_handler_t::replace);
}

glm::dvec3 vec3_of(const json& v, const std::string& where, const std::string& key) {
  if (v.is_number()) return glm::dvec3(v.get<double>());
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number()) {
    throw std::runtime_error(where + ": key '" + key + "': expected [x, y, z]" +
                             (key == "scale" ? " or a number" : ""));
  }
  glm::dvec3 r(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z)) {
    throw std::runtime_error(where + ": key '" + key + "': not finite");
  }
  return r;
}

// Appends `part`, its positions moved by `m` (its faces turned over when m
// mirrors), each face given `material`, or its own (appended to out's
// materials) when `material` is kOwn.
constexpr uint32_t kOwn = 0xFFFFFFFFu;
void append(TriangleMesh& out, TriangleMesh part, const glm::dmat4& m, uint32_t material) {
  const uint32_t own = uint32_t(out.materials.size());
  if (material == kOwn) {
    out.materials.insert(out.materials.end(), part.materials.begin(), part.materials.end());
    if (part.face_material.empty()) part.face_material.assign(part.triangles.size(), 0);
  }
  const bool mirror = glm::determinant(glm::dmat3(m)) < 0;
  const int base = int(out.positions.size());
  const int textures = int(out.textures.size());
  for (auto& p : part.positions) out.positions.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
  for (uint32_t w : part.welded) out.welded.push_back(w + uint32_t(base));  // within the part only
  out.colours.insert(out.colours.end(), part.colours.begin(), part.colours.end());
  for (size_t f = 0; f < part.triangles.size(); ++f) {
    glm::ivec3 t = part.triangles[f] + glm::ivec3(base);
    std::array<glm::vec2, 3> uv = part.face_uv[f];
    if (mirror) std::swap(t.y, t.z), std::swap(uv[1], uv[2]);
    const glm::dvec3 a = out.positions[size_t(t.x)], b = out.positions[size_t(t.y)], c = out.positions[size_t(t.z)];
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double twice_area = glm::length(cross);
    if (!(twice_area > 0) || !std::isfinite(twice_area)) {
      ++out.degenerate;
      continue;
    }
    out.triangles.push_back(t);
    out.face_normals.push_back(glm::vec3(cross / twice_area));
    out.face_texture.push_back(part.face_texture[f] >= 0 ? part.face_texture[f] + textures : -1);
    out.face_uv.push_back(uv);
    out.face_material.push_back(material == kOwn ? own + part.face_material[f] : material);
    out.area += 0.5 * twice_area;
  }
  for (auto& t : part.textures) out.textures.push_back(std::move(t));
  out.degenerate += part.degenerate;
  out.open_edges += part.open_edges;
  out.nonmanifold_edges += part.nonmanifold_edges;
  // One object with large holes makes the scene two-sided (its closed
  // objects then too: a shell around each of their triangles).
  out.two_sided = out.two_sided || part.two_sided;
  out.sigma_rho2 = std::max(out.sigma_rho2, part.sigma_rho2);
}

}  // namespace

TriangleMesh read_scene_file(const std::string& path, const MeshOptions& options) {
  const std::string where = "scene file " + path;
  const json scene = parse_json(read_small_file(path, where), where);
  if (!scene.is_object()) throw std::runtime_error(where + ": expected a JSON object");
  for (auto it = scene.begin(); it != scene.end(); ++it) {
    if (it.key() != "materials" && it.key() != "objects") {
      throw std::runtime_error(where + ": unknown key '" + shown(it.key()) + "' (keys: materials, objects)");
    }
  }
  const fs::path folder = fs::absolute(path).parent_path();
  // Materials by name (in the order of their names).
  std::vector<std::string> names;
  TriangleMesh out;
  if (auto it = scene.find("materials"); it != scene.end()) {
    if (!it->is_object()) throw std::runtime_error(where + ": key 'materials': expected an object of name: material");
    if (it->size() > kMaxSceneMaterials) {
      throw std::runtime_error(where + ": key 'materials': " + std::to_string(it->size()) + " materials (at most " +
                               std::to_string(kMaxSceneMaterials) + ")");
    }
    for (auto m = it->begin(); m != it->end(); ++m) {
      const std::string at = where + ": material '" + shown(m.key()) + "'";
      names.push_back(m.key());
      if (m->is_string()) {
        const fs::path file = path_of(*m, folder, where, "materials");
        out.materials.push_back(material_text(parse_json(read_small_file(file, at), at + " (" + file.string() + ")"),
                                              fs::absolute(file).parent_path(), at));
      } else {
        out.materials.push_back(material_text(*m, folder, at));
      }
    }
  }
  auto objects = scene.find("objects");
  if (objects == scene.end() || !objects->is_array() || objects->empty()) {
    throw std::runtime_error(where + ": key 'objects': expected a non-empty array of objects");
  }
  if (objects->size() > kMaxObjects) {
    throw std::runtime_error(where + ": key 'objects': " + std::to_string(objects->size()) + " objects (at most " +
                             std::to_string(kMaxObjects) + ")");
  }
  int without = -1;           // an object with no material at all (the renderer's default)
  double texture_pixels = 0;  // of the meshes read so far
  for (size_t i = 0; i < objects->size(); ++i) {
    const json& o = (*objects)[i];
    const std::string at = where + ": object " + std::to_string(i);
    if (!o.is_object()) throw std::runtime_error(at + ": expected a JSON object");
    for (auto k = o.begin(); k != o.end(); ++k) {
      static const char* keys[] = {"mesh", "material", "scale", "rotate", "translate", "colour"};
      if (std::find(std::begin(keys), std::end(keys), k.key()) == std::end(keys)) {
        throw std::runtime_error(at + ": unknown key '" + shown(k.key()) +
                                 "' (keys: mesh, material, scale, rotate, translate, colour)");
      }
    }
    if (!o.contains("mesh") || !o["mesh"].is_string()) throw std::runtime_error(at + ": key 'mesh': expected a path");
    uint32_t material = 0;
    const fs::path mesh_path = path_of(o["mesh"], folder, at, "mesh");
    TriangleMesh part;
    if (o.contains("material")) {
      if (!o["material"].is_string()) throw std::runtime_error(at + ": key 'material': expected a material's name");
      const std::string name = o["material"].get<std::string>();
      auto found = std::find(names.begin(), names.end(), name);
      if (found == names.end()) {
        throw std::runtime_error(at + ": key 'material': no material named '" + shown(name) + "' in 'materials'");
      }
      material = uint32_t(found - names.begin());
    }
    MeshOptions mesh_options = options;
    const glm::dvec3 scale = o.contains("scale") ? vec3_of(o["scale"], at, "scale") : glm::dvec3(1);
    if (!(scale.x > 0 && scale.y > 0 && scale.z > 0)) {
      throw std::runtime_error(at + ": key 'scale': must be > 0 (a mirror is a rotation away)");
    }
    const glm::dvec3 rotate = o.contains("rotate") ? vec3_of(o["rotate"], at, "rotate") : glm::dvec3(0);
    const glm::dvec3 translate = o.contains("translate") ? vec3_of(o["translate"], at, "translate") : glm::dvec3(0);
    if (o.contains("colour")) {
      const glm::dvec3 c = vec3_of(o["colour"], at, "colour");
      if (!(c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x <= 1 && c.y <= 1 && c.z <= 1)) {
        throw std::runtime_error(at + ": key 'colour': components must be in [0, 1]");
      }
      mesh_options.colour = glm::vec3(c);
    }
    // p' = translate + Rz Ry Rx (scale p), angles in degrees.
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
    m = glm::rotate(m, glm::radians(rotate.z), glm::dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(rotate.y), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(rotate.x), glm::dvec3(1, 0, 0));
    m = glm::scale(m, scale);
    // The texture budget is the scene's: what earlier meshes used is spent.
    mesh_options.max_total_texture_pixels = options.max_total_texture_pixels - texture_pixels;
    part = read_mesh(mesh_path.string(), mesh_options);
    for (const Texture& t : part.textures) texture_pixels += double(t.width) * double(t.height);
    if (!o.contains("material")) {
      // The mesh's own materials (OBJ usemtl groups), else the scene's only one.
      if (!part.materials.empty()) {
        material = kOwn;
      } else if (names.size() > 1) {
        throw std::runtime_error(at + ": key 'material': missing (the scene has " + std::to_string(names.size()) +
                                 " materials and " + mesh_path.string() + " has none of its own)");
      } else if (names.empty()) {
        without = int(i);
      }
    }
    if (part.two_sided && !out.two_sided) {
      out.surface = "object " + std::to_string(i) + " (" + mesh_path.string() + ") is " + part.surface +
                    "; the whole scene with it";
    }
    append(out, std::move(part), m, material);
  }
  if (!out.two_sided) out.surface = "every object closed, or its holes small: drawn as a solid";
  if (out.triangles.empty()) throw std::runtime_error(where + ": no triangle of non-zero area");
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : out.positions) {
    if (!(std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate && std::abs(p.z) <= kMaxCoordinate)) {
      throw std::runtime_error(where + ": a placed vertex lies beyond +-1e15 (or is not finite)");
    }
    lo = glm::min(lo, p), hi = glm::max(hi, p);
  }
  out.bounds = {glm::vec3(lo), glm::vec3(hi)};
  if (const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}); !(extent >= kMinExtent)) {
    std::ostringstream why;
    why << where << ": the placed meshes' bounding box is too small: extent " << extent << ", below " << kMinExtent
        << " (scale it up)";
    throw std::runtime_error(why.str());
  }
  if (out.materials.size() > kMaxSceneMaterials) {
    throw std::runtime_error(where + ": " + std::to_string(out.materials.size()) +
                             " materials with the meshes' own (at most " + std::to_string(kMaxSceneMaterials) + ")");
  }
  if (without >= 0 && !out.materials.empty()) {
    throw std::runtime_error(where + ": object " + std::to_string(without) +
                             ": key 'material': missing (other objects' meshes have materials: name one in "
                             "'materials' for this one)");
  }
  if (out.materials.size() < 2) out.face_material.clear();
  return out;
}

}  // namespace svo::voxelizer
