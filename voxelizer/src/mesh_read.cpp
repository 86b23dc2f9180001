// Mesh files to TriangleMesh through OpenMesh, textures through
// OpenImageIO. No OpenVDB here: the reference ray tracer reads meshes too.
#include <OpenImageIO/imageio.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/shared_math.h"
#include "svo/octree/image_header.h"
#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/winding.h"

namespace svo::voxelizer {

namespace {

struct MeshTraits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Color);
  HalfedgeAttributes(OpenMesh::Attributes::TexCoord2D | OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::TextureIndex);
  // Float colours: OpenMesh converts an OBJ's float colours to the mesh's
  // type, and a value outside [0, 1] cast to unsigned char is undefined
  // behaviour (found by the mesh_file fuzz target). As floats they arrive
  // unchanged (PLY bytes divided by 255) and are clamped below.
  using Color = OpenMesh::Vec3f;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// ---- Screening of the headers OpenMesh trusts. OpenMesh 9.0's PLY reader
// writes through a wild pointer on a property type it does not know (found
// by the mesh_file fuzz target), and its readers reserve memory for the
// element counts of a header: both are checked here first, strictly.

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// "" when the PLY header is one OpenMesh can be given, else the problem.
// Every element needs at least one byte: a count above the file's size is
// refused before any reader reserves memory for it.
// The body of an ASCII PLY, one line per element: OpenMesh loops over a
// list's count as read, so a count of garbage made it push gigabytes of
// handles (found by the mesh_file fuzz target). Each line: one number per
// scalar property, for a list a count from 0 to 1000 then that many
// numbers; nothing else.
template <typename Element>
std::string screen_ply_ascii_body(std::istream& in, const std::vector<Element>& declared, int header_lines) {
  std::string line;
  size_t number = size_t(header_lines);
  auto is_number = [](const std::string& t) {
    char* end = nullptr;
    std::strtod(t.c_str(), &end);
    return !t.empty() && end == t.c_str() + t.size();
  };
  for (const Element& e : declared) {
    for (int64_t i = 0; i < e.count; ++i) {
      if (!std::getline(in, line)) return "PLY file ends before its elements";
      ++number;
      std::istringstream words(line);
      std::vector<std::string> w;
      for (std::string word; words >> word;) w.push_back(word);
      const std::string where = "PLY line " + std::to_string(number) + ": ";
      size_t at = 0;
      for (bool list : e.lists) {
        if (at >= w.size()) return where + "fewer values than the element's properties";
        if (list) {
          const std::string& c = w[at];
          if (c.empty() || c.size() > 4 || c.find_first_not_of("0123456789") != std::string::npos ||
              std::stoi(c) > 1000) {
            return where + "a list count '" + c.substr(0, 40) + "' is not an integer from 0 to 1000";
          }
          at += 1 + size_t(std::stoi(c));
          if (at > w.size()) return where + "fewer list values than its count";
          for (size_t k = at - size_t(std::stoi(c)); k < at; ++k) {
            if (!is_number(w[k])) return where + "'" + w[k].substr(0, 40) + "' is not a number";
          }
        } else {
          if (!is_number(w[at])) return where + "'" + w[at].substr(0, 40) + "' is not a number";
          ++at;
        }
      }
      if (at != w.size()) return where + "more values than the element's properties";
    }
  }
  return "";
}

std::string screen_ply(std::istream& in, uintmax_t file_bytes) {
  static const std::set<std::string> kTypes = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                               "float", "double", "int8",    "uint8",  "int16", "uint16",
                                               "int32", "uint32", "float32", "float64"};
  std::string line;
  bool elements = false, ascii = false;
  struct Element {
    int64_t count = 0;
    std::vector<bool> lists;  // per property: a list?
  };
  std::vector<Element> declared;
  for (int number = 1; number <= 1000 && std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = "PLY header line " + std::to_string(number) + ": ";
    for (char c : line) {
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t') return where + "a control character";
    }
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word;) w.push_back(word);
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") return "not a PLY file (no 'ply' line)";
      continue;
    }
    if (number == 2) {
      if (w.size() != 3 || w[0] != "format" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian") || w[2] != "1.0") {
        return where + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'";
      }
      ascii = w[1] == "ascii";
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (!elements) return where + "no element";
      return ascii ? screen_ply_ascii_body(in, declared, number) : "";
    }
    if (w[0] == "element") {
      if (w.size() != 3 || w[2].empty() || w[2].size() > 12 ||
          w[2].find_first_not_of("0123456789") != std::string::npos) {
        return where + "expected 'element NAME COUNT'";
      }
      if (std::stod(w[2]) > double(file_bytes)) {
        return where + "element " + w[1] + " claims " + w[2] + " entries, more than the file's " +
               std::to_string(file_bytes) + " bytes can hold";
      }
      elements = true;
      declared.push_back({int64_t(std::stod(w[2])), {}});
      continue;
    }
    if (w[0] == "property") {
      if (!elements) return where + "a property before any element";
      const bool scalar = w.size() == 3 && kTypes.count(w[1]);
      const bool list = w.size() == 5 && w[1] == "list" && kTypes.count(w[2]) && kTypes.count(w[3]);
      if (!scalar && !list) return where + "expected 'property TYPE NAME' or 'property list TYPE TYPE NAME'";
      declared.back().lists.push_back(list);
      continue;
    }
    return where + "unknown keyword '" + w[0].substr(0, 40) + "'";
  }
  return "PLY header without end_header in its first 1000 lines";
}

// OFF: a first line OpenMesh reads as it means it ([ST][C][N][4][n]OFF and
// nothing else), and counts that are plain non-negative integers no larger
// than the file: OpenMesh reads "-5" into an unsigned count and reserves
// memory for it (16 GiB, found by the mesh_file fuzz target). Binary OFF is
// refused (its counts' byte order is OpenMesh's guess).
std::string screen_off(std::istream& in, uintmax_t file_bytes) {
  std::string first;
  std::getline(in, first);
  if (!first.empty() && first.back() == '\r') first.pop_back();
  size_t at = 0;
  for (const char* prefix : {"ST", "C", "N", "4", "n"}) {
    if (first.compare(at, std::strlen(prefix), prefix) == 0) at += std::strlen(prefix);
  }
  if (first.compare(at, 3, "OFF") != 0) return "";  // not OFF: OpenMesh's OFF reader will not take it
  const std::string rest = first.substr(at + 3);
  if (rest.find("BINARY") != std::string::npos) return "binary OFF is not supported (use ASCII OFF, PLY or OBJ)";
  if (rest.find_first_not_of(" \t") != std::string::npos) return "OFF header: unexpected text after the keyword";
  double counts[3] = {0, 0, 0};
  for (double& c : counts) {
    std::string word;
    // Comments may sit between the keyword and the counts.
    while (in >> word && word[0] == '#') in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    if (word.empty() || word.size() > 12 || word.find_first_not_of("0123456789") != std::string::npos) {
      return "OFF header: expected the vertex, face and edge counts as non-negative integers";
    }
    c = std::stod(word);
  }
  if (counts[0] + counts[1] > double(file_bytes)) {
    return "OFF header claims " + std::to_string(int64_t(counts[0])) + " vertices and " +
           std::to_string(int64_t(counts[1])) + " faces, more than the file's " + std::to_string(file_bytes) +
           " bytes can hold";
  }
  // The body, line by line: OpenMesh loops over a face's corner count as
  // read, so "111...1" (an overflow: 2^32 - 1) made it push 4 GiB of
  // handles (found by the mesh_file fuzz target). Vertex lines: 3 or more
  // numbers; face lines: a count K in [1, 1000], then K indices in
  // [0, vertices), then at most 4 colour numbers; blank and # lines skipped.
  in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  const int64_t vertices = int64_t(counts[0]), faces = int64_t(counts[1]);
  std::string line;
  int64_t seen_vertices = 0, seen_faces = 0;
  for (size_t number = 3; seen_faces < faces && std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word && word[0] != '#';) w.push_back(word);
    if (w.empty()) continue;
    const std::string where = "OFF line " + std::to_string(number) + ": ";
    auto is_number = [](const std::string& t) {
      char* end = nullptr;
      std::strtod(t.c_str(), &end);
      return end == t.c_str() + t.size();
    };
    auto is_index = [](const std::string& t, int64_t below) {
      return !t.empty() && t.size() <= 10 && t.find_first_not_of("0123456789") == std::string::npos &&
             std::stoll(t) < below;
    };
    if (seen_vertices < vertices) {
      if (w.size() < 3) return where + "a vertex needs 3 coordinates";
      for (const auto& t : w) {
        if (!is_number(t)) return where + "'" + t.substr(0, 40) + "' is not a number";
      }
      ++seen_vertices;
      continue;
    }
    if (!is_index(w[0], 1001) || w[0] == "0") return where + "a face starts with its corner count, 1 to 1000";
    const size_t k = size_t(std::stoll(w[0]));
    if (w.size() < 1 + k || w.size() > 1 + k + 4)
      return where + "expected " + w[0] + " corners (and up to 4 colour numbers)";
    for (size_t i = 1; i <= k; ++i) {
      if (!is_index(w[i], vertices)) return where + "corner '" + w[i].substr(0, 40) + "' is not a vertex index";
    }
    for (size_t i = k + 1; i < w.size(); ++i) {
      if (!is_number(w[i])) return where + "'" + w[i].substr(0, 40) + "' is not a number";
    }
    ++seen_faces;
  }
  if (seen_vertices < vertices || seen_faces < faces) return "OFF file ends before its vertices and faces";
  return "";
}

// OBJ faces: OpenMesh 9.0 asserts (aborts) on a face line whose corners it
// cannot parse (found by the mesh_file fuzz target). Each corner must be
// V, V/T, V//N or V/T/N with V and T non-zero integers, and a face needs 3.
// "vc" lines are refused (below).
std::string screen_obj(std::istream& in) {
  // [-]DIGITS at t[at]: false when absent (unless optional), zero or longer than 9 digits.
  auto index = [](const std::string& t, size_t& at, bool optional) {
    const size_t start = at;
    if (at < t.size() && t[at] == '-') ++at;
    const size_t digits = at;
    while (at < t.size() && std::isdigit(static_cast<unsigned char>(t[at]))) ++at;
    const size_t n = at - digits;
    if (n == 0) return optional && at == start;
    return n <= 9 && std::stol(t.substr(digits, n)) != 0;
  };
  std::string line;
  for (size_t number = 1; std::getline(in, line); ++number) {
    // OpenMesh reads the keyword as the first word, whatever space precedes it.
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    // OpenMesh's non-standard "vc" line colours the last vertex it read,
    // whether or not there is one (a null reference, found by the
    // mesh_file fuzz target): refused.
    if (keyword == "vc") {
      return "OBJ line " + std::to_string(number) +
             ": 'vc' vertex colour lines are not supported (give colours as 'v X Y Z R G B')";
    }
    if (keyword != "f") continue;
    int corners = 0;
    for (std::string t; words >> t; ++corners) {
      if (t[0] == '#') break;  // a comment ends the line
      size_t at = 0;
      bool ok = index(t, at, false);
      if (ok && at < t.size() && t[at] == '/') {
        ++at;
        ok = index(t, at, true);
        if (ok && at < t.size() && t[at] == '/') ++at, ok = index(t, at, true);
      }
      if (!ok || at != t.size()) {
        return "OBJ line " + std::to_string(number) + ": face corner '" + t.substr(0, 40) +
               "' is not V, V/T, V//N or V/T/N";
      }
    }
    if (corners < 3) return "OBJ line " + std::to_string(number) + ": a face needs 3 corners";
  }
  return "";
}

std::string screen_mesh_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";  // OpenMesh reports it
  std::error_code error;
  const uintmax_t bytes = std::filesystem::file_size(path, error);
  if (error) return "";
  if (ext == ".ply") return screen_ply(in, bytes);
  if (ext == ".off") return screen_off(in, bytes);
  if (ext == ".obj") return screen_obj(in);
  return "";
}

// An OBJ material as its MTL file gives it (the keys we read; < 0: absent).
struct MtlMaterial {
  glm::vec3 kd{-1}, ks{-1};
  double ns = -1, pr = -1;
};

// The lines of a small regular file, or none: mtllib names what a hostile
// OBJ wants (a FIFO or /dev/zero would hang or eat memory).
std::vector<std::string> small_file_lines(const std::filesystem::path& file, uintmax_t limit) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error) || std::filesystem::file_size(file, error) > limit || error) {
    return {};
  }
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The materials of the OBJ's mtllib files (regular files of at most 16 MiB,
// relative to the OBJ), by name.
std::map<std::string, MtlMaterial> read_mtl_materials(const std::string& path) {
  namespace fs = std::filesystem;
  constexpr uintmax_t kMaxMtlBytes = 16u << 20;
  std::map<std::string, MtlMaterial> out;
  for (const std::string& line : small_file_lines(path, std::numeric_limits<uintmax_t>::max())) {
    if (line.rfind("mtllib", 0) != 0) continue;
    std::istringstream names(line.substr(6));
    for (std::string name; names >> name;) {
      MtlMaterial* m = nullptr;
      for (const std::string& entry : small_file_lines(fs::path(path).parent_path() / name, kMaxMtlBytes)) {
        std::istringstream in(entry);
        std::string key;
        in >> key;
        if (key == "newmtl") {
          std::string material;
          in >> material;
          m = &out[material];
        }
        if (!m) continue;
        auto rgb = [&](glm::vec3& c) {
          glm::vec3 v;
          if (in >> v.x >> v.y >> v.z && std::isfinite(v.x + v.y + v.z)) c = glm::clamp(v, 0.0f, 1.0f);
        };
        auto number = [&](double& x) {
          double v;
          if (in >> v && std::isfinite(v) && v >= 0) x = v;
        };
        if (key == "Kd") rgb(m->kd);
        if (key == "Ks") rgb(m->ks);
        if (key == "Ns") number(m->ns);
        if (key == "Pr") number(m->pr);
      }
    }
  }
  return out;
}

// Slope variance of the OBJ's materials (the mean over its materials):
// PBR roughness "Pr" alpha gives sigma^2 = alpha^2 / 2, a Phong exponent
// "Ns" the Beckmann equivalent sigma^2 = 1 / (Ns + 2). Returns a negative
// value when the file names no such material.
float obj_material_slope_variance(const std::map<std::string, MtlMaterial>& materials) {
  double sum = 0;
  int count = 0;
  for (const auto& [name, m] : materials) {
    if (m.pr >= 0) {
      sum += m.pr * m.pr / 2, ++count;
    } else if (m.ns >= 0) {
      sum += 1.0 / (m.ns + 2.0), ++count;
    }
  }
  return count ? float(sum / count) : -1.0f;
}

// An MTL material as our material JSON (docs/materials.md): GGX of
// roughness Pr where it has one, the Phong NDF of exponent Ns where it has
// a specular colour Ks, else Lambert; Kd the diffuse albedo (default 1: the
// mesh's colour or texture tints it already).
std::string mtl_material_json(const std::string& name, const MtlMaterial& m) {
  std::ostringstream j;
  auto rgb = [](glm::vec3 c) {
    std::ostringstream s;
    s << "[" << c.x << ", " << c.y << ", " << c.z << "]";
    return s.str();
  };
  std::string escaped;
  for (char c : name) {
    if (c == '"' || c == '\\') escaped += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) escaped += c;
  }
  j << "{\"name\": \"" << escaped << "\", ";
  const glm::vec3 diffuse = m.kd.x >= 0 ? m.kd : glm::vec3(1);
  const glm::vec3 f0 = m.ks.x >= 0 ? m.ks : glm::vec3(0.04f);
  if (m.pr >= 0) {
    j << "\"brdf\": \"ggx\", \"roughness\": " << std::clamp(m.pr, 0.002, 4.0) << ", \"f0\": " << rgb(f0) << ", ";
  } else if (m.ks.x >= 0 && m.ks != glm::vec3(0) && m.ns >= 0) {
    j << "\"brdf\": \"phong\", \"exponent\": " << std::min(m.ns, 1e6) << ", \"f0\": " << rgb(f0) << ", ";
  } else {
    j << "\"brdf\": \"lambert\", ";
  }
  j << "\"diffuse\": " << rgb(diffuse) << "}";
  return j.str();
}

// The OBJ's usemtl name of each triangle OpenMesh makes (a face of n corners
// becomes n - 2 triangles, in file order): names in order of first use ("default" before
// any usemtl), and per triangle an index into them.
struct ObjGroups {
  std::vector<std::string> names;
  std::vector<uint32_t> triangle_group;
};
ObjGroups obj_groups(const std::string& path) {
  ObjGroups g;
  uint32_t current = 0;
  bool named = false;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    if (keyword == "usemtl") {
      std::string name;
      words >> name;
      auto it = std::find(g.names.begin(), g.names.end(), name);
      current = uint32_t(it - g.names.begin());
      if (it == g.names.end()) g.names.push_back(name);
      named = true;
      continue;
    }
    if (keyword != "f") continue;
    int corners = 0;
    for (std::string t; words >> t && t[0] != '#';) ++corners;
    if (!named) {
      g.names.insert(g.names.begin(), "default");
      for (auto& t : g.triangle_group) ++t;
      current = 0;
      named = true;
    }
    for (int k = 2; k < corners; ++k) g.triangle_group.push_back(current);
  }
  return g;
}

}  // namespace

Texture read_texture(const std::string& file, const std::string& mesh_path) {
  const std::string where = mesh_path + ": texture " + file;
  auto fail = [&](std::string why) {
    if (auto nl = why.find('\n'); nl != std::string::npos) why.resize(nl);
    throw std::runtime_error(where + ": " + (why.empty() ? "cannot read it as an image" : why));
  };
  // Checks in front of the format libraries, which trust their headers.
  if (std::string why = octree::check_exr_header(file, kMaxTextureTexels); !why.empty()) fail(why);
  if (std::string why = octree::check_png_chunks(file); !why.empty()) fail(why);
  // The reader of the file's extension only: OpenImageIO's open() would
  // otherwise try every format it knows on a file its extension's rejects.
  auto input = OIIO::ImageInput::create(file, false);
  if (!input) fail("unsupported image format: " + OIIO::geterror());
  OIIO::ImageSpec spec;
  if (!input->open(file, spec)) fail(input->geterror());
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels < 1) fail("no pixels");
  // From the header, before the pixels are allocated.
  const double texels = double(spec.width) * double(spec.height);
  if (texels > kMaxTextureTexels || texels * spec.nchannels > 4 * kMaxTextureTexels || spec.width > 16384 ||
      spec.height > 16384) {
    fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" + std::to_string(spec.nchannels) +
         " samples, more than the limit of 8192x8192x4 (16384 a side)");
  }
  std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) fail(input->geterror());
  // 8- and 16-bit images hold sRGB-encoded values; float images are linear.
  bool srgb = spec.format.basetype != OIIO::TypeDesc::FLOAT && spec.format.basetype != OIIO::TypeDesc::HALF;
  Texture t;
  t.width = spec.width, t.height = spec.height;
  t.texels.resize(size_t(t.width) * size_t(t.height));
  const size_t n = size_t(spec.nchannels);
  for (size_t i = 0; i < t.texels.size(); ++i) {
    const float* p = &pixels[i * n];
    glm::vec3 c(p[0], p[std::min<size_t>(1, n - 1)], p[std::min<size_t>(2, n - 1)]);
    for (int k = 0; k < 3; ++k) c[k] = std::isnan(c[k]) ? 0.0f : std::clamp(c[k], 0.0f, 1e4f);
    if (srgb) {
      c = glm::vec3(svo::math::svo_srgb_to_linear(c.x), svo::math::svo_srgb_to_linear(c.y),
                    svo::math::svo_srgb_to_linear(c.z));
    }
    t.texels[i] = glm::clamp(c, glm::vec3(0), glm::vec3(1e4f));
  }
  return t;
}

glm::vec3 Texture::sample(glm::vec2 uv) const {
  if (width <= 0 || height <= 0 || texels.size() != size_t(width) * size_t(height)) return glm::vec3(0);
  // Only the fractional part matters; a non-finite coordinate reads as 0.
  if (!std::isfinite(uv.x)) uv.x = 0;
  if (!std::isfinite(uv.y)) uv.y = 0;
  float fx = (uv.x - std::floor(uv.x)) * width - 0.5f, fy = (1.0f - (uv.y - std::floor(uv.y))) * height - 0.5f;
  int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
  float ax = fx - float(x0), ay = fy - float(y0);
  auto at = [&](int x, int y) {
    x = ((x % width) + width) % width, y = ((y % height) + height) % height;
    return texels[size_t(y) * size_t(width) + size_t(x)];
  };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), ax), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax), ay);
}

glm::vec3 TriangleMesh::colour(size_t triangle, glm::dvec3 bary) const {
  const int texture = face_texture[triangle];
  if (texture >= 0) {
    const auto& uv = face_uv[triangle];
    glm::vec2 at = float(bary.x) * uv[0] + float(bary.y) * uv[1] + float(bary.z) * uv[2];
    return textures[size_t(texture)].sample(at);
  }
  const glm::ivec3& t = triangles[triangle];
  return float(bary.x) * colours[size_t(t.x)] + float(bary.y) * colours[size_t(t.y)] +
         float(bary.z) * colours[size_t(t.z)];
}

TriangleMesh read_mesh(const std::string& path, const MeshOptions& options) {
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file");
  if (std::filesystem::is_directory(path)) throw std::runtime_error(path + ": is a directory, not a mesh");
  // A FIFO or a device would hang the reader or never end.
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": not a regular file");
  // OpenMesh reports problems on its own streams, several lines each: we
  // report one line ourselves.
  omerr().disable();
  omlog().disable();
  omout().disable();
  TriMesh mesh;
  mesh.request_vertex_colors();
  mesh.request_halfedge_texcoords2D();
  mesh.request_face_texture_index();
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::VertexColor | OpenMesh::IO::Options::FaceTexCoord;
  if (std::string why = screen_mesh_file(path); !why.empty()) throw std::runtime_error(path + ": " + why);
  if (!OpenMesh::IO::read_mesh(mesh, path, opt)) {
    throw std::runtime_error(path + ": cannot read it as a mesh (OBJ, PLY, OFF or STL)");
  }
  if (mesh.n_faces() == 0) throw std::runtime_error(path + ": the mesh has no faces");
  bool colours = opt.check(OpenMesh::IO::Options::VertexColor);
  MeshArrays arrays;
  arrays.positions.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    auto p = mesh.point(v);
    arrays.positions.emplace_back(p[0], p[1], p[2]);
    if (colours) {
      auto c = mesh.color(v);
      glm::vec3 encoded;
      for (int k = 0; k < 3; ++k) encoded[k] = std::isnan(c[k]) ? 0.0f : std::clamp(float(c[k]), 0.0f, 1.0f);
      arrays.colours.push_back(glm::vec3(svo::math::svo_srgb_to_linear(encoded.x),
                                         svo::math::svo_srgb_to_linear(encoded.y),
                                         svo::math::svo_srgb_to_linear(encoded.z)));
    }
  }
  // Textures named by the OBJ's materials (map_Kd), relative to the mesh.
  std::map<int, int> texture_of_id;
  OpenMesh::MPropHandleT<std::map<int, std::string>> mapping;
  bool textured = opt.check(OpenMesh::IO::Options::FaceTexCoord) && mesh.get_property_handle(mapping, "TextureMapping");
  if (textured) {
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    for (const auto& [id, name] : mesh.property(mapping)) {
      std::string file = (dir / name).string();
      if (!std::filesystem::exists(file)) throw std::runtime_error(path + ": texture " + file + " does not exist");
      texture_of_id[id] = int(arrays.textures.size());
      arrays.textures.push_back(read_texture(file, path));
    }
  }
  for (auto f : mesh.faces()) {
    glm::ivec3 t(-1);
    std::array<glm::vec2, 3> uv{};
    int k = 0;
    for (auto h : mesh.fh_range(f)) {
      if (k < 3) {
        t[k] = mesh.to_vertex_handle(h).idx();
        auto tc = mesh.texcoord2D(h);
        uv[size_t(k)] = glm::vec2(tc[0], tc[1]);
      }
      ++k;
    }
    if (k != 3) continue;  // a TriMesh has triangles only
    int texture = -1;
    if (textured) {
      auto it = texture_of_id.find(mesh.texture_index(f));
      if (it != texture_of_id.end()) texture = it->second;
    }
    arrays.triangles.push_back(t);
    arrays.face_uv.push_back(uv);
    arrays.face_texture.push_back(texture);
  }
  // OBJ usemtl groups: a material per group, from its MTL entry, when there
  // are two or more and OpenMesh kept every triangle in file order.
  const bool obj = lower_extension(path) == ".obj";
  const std::map<std::string, MtlMaterial> mtl = obj ? read_mtl_materials(path) : std::map<std::string, MtlMaterial>{};
  if (obj) {
    const ObjGroups groups = obj_groups(path);
    if (groups.names.size() > 1 && groups.triangle_group.size() == mesh.n_faces() &&
        arrays.triangles.size() == mesh.n_faces()) {
      arrays.face_material = groups.triangle_group;
      for (const std::string& name : groups.names) {
        auto it = mtl.find(name);
        arrays.materials.push_back(mtl_material_json(name, it != mtl.end() ? it->second : MtlMaterial{}));
      }
    } else if (groups.names.size() > 1 && options.warning) {
      options.warning(path + ": " + std::to_string(groups.names.size()) +
                      " usemtl groups not used as materials (OpenMesh kept " + std::to_string(mesh.n_faces()) + " of " +
                      std::to_string(groups.triangle_group.size()) + " triangles)");
    }
  }
  TriangleMesh out = make_triangle_mesh(path, std::move(arrays), options);
  const float material = obj_material_slope_variance(mtl);
  if (options.sigma_rho < 0 && material >= 0) out.sigma_rho2 = material;
  return out;
}

namespace {

// What the generalized winding number says of a surface, from at most 2048
// triangles spread over it (area-weighted): the share of its area whose
// winding number crosses 1/2 through it (it bounds a volume; the rest is a
// sheet, both sides inside or both outside), and the share where it goes
// from within 0.05 of 0 to within 0.05 of 1 (a closed surface gives 0 and 1
// everywhere; from there, the holes take up less than 5% of the sphere).
struct WindingShares {
  double bounds_volume = 0;
  double closed = 0;
};

WindingShares winding_shares(const TriangleMesh& mesh) {
  const WindingNumber winding(mesh.positions, mesh.triangles);
  const glm::dvec3 extent = glm::dvec3(mesh.bounds.hi) - glm::dvec3(mesh.bounds.lo);
  const double probe = 1e-6 * glm::length(extent);
  const size_t stride = std::max<size_t>(1, mesh.triangles.size() / 2048);
  double total = 0;
  WindingShares shares;
  for (size_t t = 0; t < mesh.triangles.size(); t += stride) {
    const glm::ivec3 i = mesh.triangles[t];
    const glm::dvec3 a = mesh.positions[size_t(i.x)], b = mesh.positions[size_t(i.y)], c = mesh.positions[size_t(i.z)];
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    const glm::dvec3 centre = (a + b + c) / 3.0, n(mesh.face_normals[t]);
    // The jump through the triangle is 1: its middle says it all.
    const double middle = 0.5 * (winding(centre + probe * n) + winding(centre - probe * n));
    total += area;
    if (std::abs(middle - 0.5) < 0.25) shares.bounds_volume += area;
    if (std::abs(middle - 0.5) < 0.05) shares.closed += area;
  }
  if (total > 0) shares.bounds_volume /= total, shares.closed /= total;
  return shares;
}

}  // namespace

TriangleMesh make_triangle_mesh(const std::string& path, MeshArrays in, const MeshOptions& options) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(path + ": " + why); };
  const size_t n = in.positions.size(), m = in.triangles.size();
  if (m == 0) fail("the mesh has no faces");
  auto check_count = [&](size_t count, size_t expected, const char* what, const char* per) {
    if (count != 0 && count != expected) {
      fail(std::to_string(count) + " " + what + " for " + std::to_string(expected) + " " + per);
    }
  };
  check_count(in.colours.size(), n, "vertex colours", "vertices");
  check_count(in.face_uv.size(), m, "face texture coordinates", "triangles");
  check_count(in.face_texture.size(), m, "face texture indices", "triangles");
  check_count(in.face_material.size(), m, "face materials", "triangles");
  if (in.materials.size() > 255) fail(std::to_string(in.materials.size()) + " materials (at most 255)");
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3& q = in.positions[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(q[k])) fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
      if (std::abs(q[k]) > kMaxCoordinate) {
        fail("vertex " + std::to_string(i) + " has a coordinate beyond +-1e15 (" + std::to_string(q[k]) + ")");
      }
    }
  }
  for (size_t i = 0; i < in.colours.size(); ++i) {
    glm::vec3& c = in.colours[i];
    for (int k = 0; k < 3; ++k) c[k] = std::isnan(c[k]) ? 0.0f : std::clamp(c[k], 0.0f, 1e4f);
  }
  for (size_t i = 0; i < in.textures.size(); ++i) {
    const Texture& t = in.textures[i];
    if (t.width <= 0 || t.height <= 0 || t.texels.size() != size_t(t.width) * size_t(t.height)) {
      fail("texture " + std::to_string(i) + " has no texels");
    }
  }
  TriangleMesh out;
  out.positions = std::move(in.positions);
  out.colours = std::move(in.colours);
  if (out.colours.empty()) out.colours.assign(n, options.colour.value_or(glm::vec3(0.8f)));
  out.textures = std::move(in.textures);
  out.materials = std::move(in.materials);
  out.sigma_rho2 = options.sigma_rho >= 0 ? options.sigma_rho * options.sigma_rho : 0.01f;
  std::vector<std::pair<int, int>> edges;  // (low, high) corner pairs of the kept triangles
  edges.reserve(3 * m);
  for (size_t f = 0; f < m; ++f) {
    const glm::ivec3 t = in.triangles[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] < 0 || size_t(t[k]) >= n) {
        fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(t[k]) + ", but the mesh has " +
             std::to_string(n) + " vertices");
      }
    }
    int texture = in.face_texture.empty() ? -1 : in.face_texture[f];
    if (texture < -1 || (texture >= 0 && size_t(texture) >= out.textures.size())) {
      fail("face " + std::to_string(f) + " refers to texture " + std::to_string(texture) + ", but the mesh has " +
           std::to_string(out.textures.size()) + " textures");
    }
    // Texture coordinates matter on textured faces only (OpenMesh leaves
    // them undefined on the others: zeros there).
    std::array<glm::vec2, 3> uv{};
    if (texture >= 0 && !in.face_uv.empty()) uv = in.face_uv[f];
    for (const glm::vec2& c : uv) {
      if (!std::isfinite(c.x) || !std::isfinite(c.y)) {
        fail("face " + std::to_string(f) + " has a non-finite texture coordinate");
      }
    }
    glm::dvec3 a = out.positions[size_t(t.x)], b = out.positions[size_t(t.y)], c = out.positions[size_t(t.z)];
    // The normal from the cross product scaled to its largest component
    // first: a length of tiny components would underflow into denormals
    // and leave a normal that is not unit (found by the mesh_arrays fuzz target).
    glm::dvec3 cross = glm::cross(b - a, c - a);
    const double scale = std::max({std::abs(cross.x), std::abs(cross.y), std::abs(cross.z)});
    const glm::dvec3 direction = cross / scale;
    const double twice_area = glm::length(direction) * scale;
    // Zero area, or an area that underflows to zero (found by the
    // mesh_arrays fuzz target): no normal, no surface; dropped.
    if (!(scale > 0) || !std::isfinite(scale) || !(0.5 * twice_area > 0)) {
      ++out.degenerate;
      continue;
    }
    out.triangles.push_back(t);
    out.face_normals.push_back(glm::vec3(direction / glm::length(direction)));
    out.face_texture.push_back(texture);
    out.face_uv.push_back(uv);
    if (!in.face_material.empty()) {
      if (in.face_material[f] >= out.materials.size()) {
        fail("face " + std::to_string(f) + " has material " + std::to_string(in.face_material[f]) +
             ", but the mesh has " + std::to_string(out.materials.size()) + " materials");
      }
      out.face_material.push_back(in.face_material[f]);
    }
    out.area += 0.5 * twice_area;
    for (int k = 0; k < 3; ++k) {
      int u = t[k], v = t[(k + 1) % 3];
      edges.emplace_back(std::min(u, v), std::max(u, v));
    }
  }
  if (out.triangles.empty()) {
    fail("the mesh has no triangle of non-zero area (" + std::to_string(out.degenerate) + " degenerate)");
  }
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : out.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (!(glm::length(hi - lo) > 0)) fail("the mesh has zero extent");
  out.bounds = {glm::vec3(lo), glm::vec3(hi)};
  // Topology of the kept triangles, by vertex index: an edge used once is
  // open, three or more times non-manifold.
  std::sort(edges.begin(), edges.end());
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) ++out.open_edges;
    if (j - i >= 3) ++out.nonmanifold_edges;
    i = j;
  }
  // A surface with holes or non-manifold edges is drawn as a solid when the
  // winding number says its holes are small (OpenVDB's flood fill does not
  // leak through them), else two-sided (mesh_source.cpp).
  WindingShares shares;
  if (out.open_edges || out.nonmanifold_edges) {
    shares = winding_shares(out);
    out.two_sided = shares.closed < kClosedShare;
  }
  if (options.warning) {
    if (out.degenerate) {
      options.warning(path + ": " + std::to_string(out.degenerate) + " triangles of zero area dropped");
    }
    if (out.open_edges || out.nonmanifold_edges) {
      char why[200];
      std::snprintf(why, sizeof why,
                    "by the winding number, %.1f%% of its area is closed (%.0f%% bounds a volume, %.0f%% is a sheet)",
                    100 * shares.closed, 100 * shares.bounds_volume, 100 * (1 - shares.bounds_volume));
      options.warning(path + ": not a closed manifold surface (" + std::to_string(out.open_edges) + " open edges, " +
                      std::to_string(out.nonmanifold_edges) + " non-manifold edges): " +
                      (out.two_sided
                           ? "drawn two-sided, as a thin shell around every triangle; "
                           : "its holes are small: drawn as a solid, inside and outside from OpenVDB's flood fill; ") +
                      why);
    }
  }
  return out;
}

}  // namespace svo::voxelizer
