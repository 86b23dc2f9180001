// glTF 2.0 through tinygltf (Debian's libtinygltf, a shared library). What
// tinygltf would trust is checked first or after: the GLB container, the
// JSON's nesting (its parser recurses), the files it opens (our bounded
// readers replace its own), and every index and byte range of the model
// before a byte is read. Images never reach tinygltf (its stb_image has no
// budget, and 2.7 reads an image's buffer view unchecked): we take them out
// of the JSON, find their bytes ourselves and decode them by read_texture.
#include "gltf_read.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "mesh_screen.h"
#include "svo/octree/files.h"

namespace svo::voxelizer::gltf {

namespace {

[[noreturn]] void fail(const std::string& path, std::string why) {
  if (auto nl = why.find('\n'); nl != std::string::npos) why.resize(nl);
  throw std::runtime_error(path + ": " + why);
}

uint32_t le32(const std::string& s, size_t at) {
  uint32_t v = 0;
  std::memcpy(&v, s.data() + at, 4);  // x86-64 and the GLB are little-endian
  return v;
}

// The GLB container (glTF 2.0 section 4.4): returns "" or the problem; sets
// the JSON chunk and the BIN chunk (empty when there is none).
std::string screen_glb(const std::string& bytes, std::string& json, std::string& bin) {
  if (bytes.size() < 20) return "GLB file of " + std::to_string(bytes.size()) + " bytes, shorter than its header";
  if (bytes.compare(0, 4, "glTF") != 0) return "GLB magic is not \"glTF\"";
  if (le32(bytes, 4) != 2) return "GLB version " + std::to_string(le32(bytes, 4)) + ", expected 2";
  const uint64_t length = le32(bytes, 8);
  if (length > bytes.size() || length < 20) {
    return "GLB header states " + std::to_string(length) + " bytes, the file has " + std::to_string(bytes.size());
  }
  const uint64_t json_length = le32(bytes, 12);
  if (le32(bytes, 16) != 0x4E4F534Au) return "GLB first chunk is not JSON";
  if (json_length == 0 || 20 + json_length > length) {
    return "GLB JSON chunk of " + std::to_string(json_length) + " bytes runs past the file's " + std::to_string(length);
  }
  json = bytes.substr(20, json_length);
  uint64_t at = 20 + json_length;
  if (at == length) return "";
  if (at + 8 > length) return "GLB ends inside a chunk header";
  const uint64_t bin_length = le32(bytes, at);
  if (le32(bytes, at + 4) != 0x004E4942u) return "GLB second chunk is not BIN";
  if (at + 8 + bin_length > length) {
    return "GLB BIN chunk of " + std::to_string(bin_length) + " bytes runs past the file's " + std::to_string(length);
  }
  bin = bytes.substr(at + 8, bin_length);
  return "";
}

// Nesting depth of the JSON text's arrays and objects (strings skipped).
int json_depth(const std::string& text) {
  int depth = 0, deepest = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    if (c == '[' || c == '{') deepest = std::max(deepest, ++depth);
    if (c == ']' || c == '}') --depth;
  }
  return deepest;
}

// The JSON checked before tinygltf parses it: nesting, syntax, version and
// required extensions.
nlohmann::json screen_json(const std::string& path, const std::string& text) {
  if (int d = json_depth(text); d > kMaxJsonDepth) {
    fail(path, "JSON nested " + std::to_string(d) + " deep, more than " + std::to_string(kMaxJsonDepth));
  }
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) fail(path, "not valid JSON (glTF 2.0 expected)");
  if (!j.is_object()) fail(path, "the JSON is not an object (glTF 2.0 expected)");
  auto asset = j.find("asset");
  if (asset == j.end() || !asset->is_object() || !asset->contains("version") || !(*asset)["version"].is_string()) {
    fail(path, "no asset.version (glTF 2.0 expected)");
  }
  const std::string version = (*asset)["version"];
  if (version.rfind("2.", 0) != 0) fail(path, "glTF version " + version + ", only 2.x is read");
  if (auto req = j.find("extensionsRequired"); req != j.end() && req->is_array()) {
    for (const auto& e : *req) {
      if (e.is_string() && e.get<std::string>() == "KHR_mesh_quantization") continue;
      fail(path, "requires extension " + (e.is_string() ? e.get<std::string>() : e.dump()) +
                     ", which is not supported (Draco and other compressed or extended files: decompress them first, "
                     "e.g. gltf-transform)");
    }
  }
  return j;
}

// What tinygltf may read besides the file: external buffers and images,
// regular files only, bounded all together.
struct ReadBudget {
  uint64_t left = kMaxGltfBytes;
};

bool file_exists(const std::string& file, void*) {
  std::error_code error;
  return std::filesystem::exists(file, error);
}
std::string expand_path(const std::string& file, void*) { return file; }  // no wordexp
bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& file, void* user) {
  auto* budget = static_cast<ReadBudget*>(user);
  try {
    const std::string text = files::read_bounded(file, budget->left, "a glTF buffer or image");
    budget->left -= text.size();
    out->assign(text.begin(), text.end());
    return true;
  } catch (const std::exception& e) {
    if (err) *err += e.what();
    return false;
  }
}
bool write_whole(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not allowed";
  return false;
}
// The bytes of a base64 text (RFC 4648, padding optional); false on any
// other character.
bool decode_base64(const std::string& text, size_t from, std::string& out) {
  uint32_t acc = 0;
  int bits = 0;
  for (size_t i = from; i < text.size(); ++i) {
    const char c = text[i];
    int v = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
            : c == '='             ? -2
                                   : -1;
    if (v == -2) break;
    if (v < 0) return false;
    acc = (acc << 6) | uint32_t(v), bits += 6;
    if (bits >= 8) bits -= 8, out += char((acc >> bits) & 0xFF);
  }
  return true;
}

// "%20" and the like decoded (glTF URIs are RFC 3986).
std::string percent_decode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
        std::isxdigit(uint8_t(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// One accessor, every range checked: element i, component c as a double
// (normalized integers mapped to [0, 1] or [-1, 1]).
class AccessorView {
 public:
  AccessorView(const std::string& path, const tinygltf::Model& m, int index, const char* what,
               std::initializer_list<int> types) {
    auto bad = [&](const std::string& why) {
      fail(path, std::string(what) + " accessor " + std::to_string(index) + ": " + why);
    };
    if (index < 0 || size_t(index) >= m.accessors.size()) {
      fail(path, std::string(what) + " names accessor " + std::to_string(index) + ", but the file has " +
                     std::to_string(m.accessors.size()));
    }
    const tinygltf::Accessor& a = m.accessors[size_t(index)];
    if (a.sparse.isSparse) bad("sparse accessors are not supported");
    if (std::find(types.begin(), types.end(), a.type) == types.end()) bad("unexpected type " + std::to_string(a.type));
    components_ = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    component_type_ = a.componentType;
    const int bytes = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (bytes <= 0 || components_ <= 0 || component_type_ == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
      bad("unexpected component type " + std::to_string(a.componentType));
    }
    component_bytes_ = size_t(bytes);
    normalized_ = a.normalized;
    count_ = a.count;
    if (count_ == 0) bad("count 0");
    if (count_ > uint64_t(3 * kMaxMeshTriangles)) bad(std::to_string(count_) + " elements, more than the budget");
    const size_t element = component_bytes_ * size_t(components_);
    if (a.bufferView < 0) return;  // all zeros (glTF 2.0 5.1.1)
    if (size_t(a.bufferView) >= m.bufferViews.size()) {
      bad("names buffer view " + std::to_string(a.bufferView) + ", but the file has " +
          std::to_string(m.bufferViews.size()));
    }
    const tinygltf::BufferView& v = m.bufferViews[size_t(a.bufferView)];
    if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size()) {
      bad("its view names buffer " + std::to_string(v.buffer) + ", but the file has " +
          std::to_string(m.buffers.size()));
    }
    const std::vector<unsigned char>& data = m.buffers[size_t(v.buffer)].data;
    if (v.byteLength > data.size() || v.byteOffset > data.size() - v.byteLength) {
      bad("its view's bytes " + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) +
          " run past its buffer's " + std::to_string(data.size()));
    }
    stride_ = v.byteStride ? v.byteStride : element;
    if (v.byteStride && (v.byteStride < element || v.byteStride > 252 || v.byteStride % component_bytes_)) {
      bad("byte stride " + std::to_string(v.byteStride) + " for elements of " + std::to_string(element) + " bytes");
    }
    if (a.byteOffset > v.byteLength || element > v.byteLength - a.byteOffset ||
        (count_ - 1) > (v.byteLength - a.byteOffset - element) / stride_) {
      bad(std::to_string(count_) + " elements of stride " + std::to_string(stride_) + " from byte " +
          std::to_string(a.byteOffset) + " run past its view's " + std::to_string(v.byteLength) + " bytes");
    }
    base_ = data.data() + v.byteOffset + a.byteOffset;
  }

  size_t count() const { return count_; }
  int components() const { return components_; }
  bool is_float() const { return component_type_ == TINYGLTF_COMPONENT_TYPE_FLOAT; }
  bool is_unsigned_int() const {
    return component_type_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
           component_type_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           component_type_ == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }

  double get(size_t i, int c) const {
    if (!base_) return 0;
    const unsigned char* p = base_ + i * stride_ + size_t(c) * component_bytes_;
    auto load = [p](auto v) {
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    switch (component_type_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return load(float(0));
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        return scale(load(int8_t(0)), 127.0, true);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return scale(load(uint8_t(0)), 255.0, false);
      case TINYGLTF_COMPONENT_TYPE_SHORT:
        return scale(load(int16_t(0)), 32767.0, true);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return scale(load(uint16_t(0)), 65535.0, false);
      case TINYGLTF_COMPONENT_TYPE_INT:
        return load(int32_t(0));
      default:
        return load(uint32_t(0));
    }
  }

 private:
  double scale(double v, double max, bool is_signed) const {
    if (!normalized_) return v;
    return is_signed ? std::max(v / max, -1.0) : v / max;
  }
  const unsigned char* base_ = nullptr;
  size_t stride_ = 0, component_bytes_ = 0, count_ = 0;
  int components_ = 0, component_type_ = 0;
  bool normalized_ = false;
};

glm::dmat4 node_matrix(const std::string& path, const tinygltf::Node& n, int index) {
  auto finite = [&](const std::vector<double>& v, size_t size, const char* what) {
    if (v.empty()) return false;
    if (v.size() != size) {
      fail(path, "node " + std::to_string(index) + ": " + what + " of " + std::to_string(v.size()) + " numbers");
    }
    for (double x : v) {
      if (!std::isfinite(x)) fail(path, "node " + std::to_string(index) + ": a non-finite " + what);
    }
    return true;
  };
  glm::dmat4 m(1.0);
  if (finite(n.matrix, 16, "matrix")) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[size_t(4 * c + r)];  // column-major
    return m;
  }
  if (finite(n.translation, 3, "translation"))
    m[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1);
  if (finite(n.rotation, 4, "rotation")) {
    glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);  // glTF: x, y, z, w
    const double length = glm::length(q);
    if (length > 0) m = m * glm::mat4_cast(q / length);
  }
  if (finite(n.scale, 3, "scale"))
    m = m * glm::dmat4(glm::dvec4(n.scale[0], 0, 0, 0), glm::dvec4(0, n.scale[1], 0, 0),
                       glm::dvec4(0, 0, n.scale[2], 0), glm::dvec4(0, 0, 0, 1));
  return m;
}

struct Reader {
  std::string path;
  const MeshOptions& options;
  const tinygltf::Model& model;
  const nlohmann::json& images;  // the file's "images", kept from tinygltf (see read_gltf)
  MeshArrays out;
  // (image, baseColorFactor) -> texture slot; the factor is baked in.
  std::map<std::pair<int, std::array<float, 3>>, int> texture_slots;
  std::vector<std::pair<int, glm::vec3>> texture_sources;
  uint64_t visits = 0, skipped = 0;
  bool count_only = false;  // the hierarchy walked first, nothing read: cycles and fan-outs refused fast

  void node(int index, const glm::dmat4& parent, int depth) {
    if (index < 0 || size_t(index) >= model.nodes.size()) {
      fail(path, "names node " + std::to_string(index) + ", but the file has " + std::to_string(model.nodes.size()));
    }
    if (depth > kMaxNodeDepth)
      fail(path, "node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " (a cycle?)");
    if (++visits > kMaxNodeVisits) fail(path, "more than " + std::to_string(kMaxNodeVisits) + " node instances");
    const tinygltf::Node& n = model.nodes[size_t(index)];
    const glm::dmat4 m = parent * node_matrix(path, n, index);
    if ((n.mesh >= 0 || n.mesh < -1) && !count_only) mesh(n.mesh, m);
    for (int child : n.children) node(child, m, depth + 1);
  }

  void mesh(int index, const glm::dmat4& m) {
    if (index < 0 || size_t(index) >= model.meshes.size()) {
      fail(path, "names mesh " + std::to_string(index) + ", but the file has " + std::to_string(model.meshes.size()));
    }
    for (const tinygltf::Primitive& p : model.meshes[size_t(index)].primitives) primitive(p, m);
  }

  int texture_slot(int texture, glm::vec3 factor) {
    if (texture < 0 || size_t(texture) >= model.textures.size()) {
      fail(path,
           "names texture " + std::to_string(texture) + ", but the file has " + std::to_string(model.textures.size()));
    }
    const int image = model.textures[size_t(texture)].source;
    if (image < 0 || size_t(image) >= images.size()) {
      fail(path, "texture " + std::to_string(texture) + " names image " + std::to_string(image) +
                     ", but the file has " + std::to_string(images.size()) +
                     " (KHR_texture_basisu and WebP images are not supported)");
    }
    auto key = std::make_pair(image, std::array<float, 3>{factor.x, factor.y, factor.z});
    auto [it, added] = texture_slots.emplace(key, int(texture_sources.size()));
    if (added) texture_sources.emplace_back(image, factor);
    return it->second;
  }

  void primitive(const tinygltf::Primitive& p, const glm::dmat4& m) {
    if (p.extensions.count("KHR_draco_mesh_compression")) {
      fail(path, "a Draco-compressed primitive (KHR_draco_mesh_compression) is not supported: decompress it first");
    }
    if (p.mode >= 0 && p.mode <= 3) {  // points, lines
      ++skipped;
      return;
    }
    if (p.mode < 4 || p.mode > 6) fail(path, "primitive mode " + std::to_string(p.mode) + " is not a glTF mode");
    auto attribute = [&](const char* name) {
      auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    if (attribute("POSITION") < 0) fail(path, "a primitive has no POSITION");
    const AccessorView pos(path, model, attribute("POSITION"), "POSITION", {TINYGLTF_TYPE_VEC3});
    // Material: base colour factor, texture on TEXCOORD_0.
    glm::vec3 factor = options.colour.value_or(glm::vec3(0.8f));
    int texture = -1;
    if (p.material >= 0) {
      if (size_t(p.material) >= model.materials.size()) {
        fail(path, "names material " + std::to_string(p.material) + ", but the file has " +
                       std::to_string(model.materials.size()));
      }
      const tinygltf::PbrMetallicRoughness& pbr = model.materials[size_t(p.material)].pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() >= 3) {
        factor = glm::vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2]));
        for (int k = 0; k < 3; ++k) factor[k] = std::isfinite(factor[k]) ? std::clamp(factor[k], 0.0f, 1.0f) : 0.0f;
      }
      if (pbr.baseColorTexture.index >= 0) {
        if (pbr.baseColorTexture.texCoord != 0) {
          fail(path, "material " + std::to_string(p.material) + ": baseColorTexture on TEXCOORD_" +
                         std::to_string(pbr.baseColorTexture.texCoord) + " (only TEXCOORD_0 is supported)");
        }
        if (attribute("TEXCOORD_0") < 0) {
          fail(path, "material " + std::to_string(p.material) + " has a baseColorTexture, the primitive no TEXCOORD_0");
        }
        texture = texture_slot(pbr.baseColorTexture.index, factor);
      }
    }
    const size_t n = pos.count();
    if (double(out.positions.size()) + double(n) > kMaxMeshTriangles) {
      fail(path, "more than 100 million vertices (mesh instances included)");
    }
    const size_t first = out.positions.size();
    for (size_t i = 0; i < n; ++i) {
      const glm::dvec4 q = m * glm::dvec4(pos.get(i, 0), pos.get(i, 1), pos.get(i, 2), 1.0);
      out.positions.emplace_back(q);
    }
    // Per-vertex colours for every vertex, once any primitive has them.
    const int colour_index = attribute("COLOR_0");
    if (out.colours.size() < first) out.colours.resize(first, options.colour.value_or(glm::vec3(0.8f)));
    if (colour_index >= 0 && texture < 0) {
      const AccessorView col(path, model, colour_index, "COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
      if (col.count() != n)
        fail(path, "COLOR_0 has " + std::to_string(col.count()) + " elements for " + std::to_string(n) + " positions");
      for (size_t i = 0; i < n; ++i)
        out.colours.push_back(factor * glm::vec3(col.get(i, 0), col.get(i, 1), col.get(i, 2)));
    } else {
      out.colours.resize(first + n, factor);
    }
    std::optional<AccessorView> uv;
    if (texture >= 0) {
      uv.emplace(path, model, attribute("TEXCOORD_0"), "TEXCOORD_0", std::initializer_list<int>{TINYGLTF_TYPE_VEC2});
      if (uv->count() != n)
        fail(path,
             "TEXCOORD_0 has " + std::to_string(uv->count()) + " elements for " + std::to_string(n) + " positions");
    }
    // Corner indices: the indices accessor, or 0 .. n - 1.
    std::optional<AccessorView> idx;
    if (p.indices >= 0) {
      idx.emplace(path, model, p.indices, "indices", std::initializer_list<int>{TINYGLTF_TYPE_SCALAR});
      if (!idx->is_unsigned_int())
        fail(path, "indices accessor " + std::to_string(p.indices) + " is not unsigned integers");
    }
    const size_t corners = idx ? idx->count() : n;
    auto corner = [&](size_t k) -> int {
      const double v = idx ? idx->get(k, 0) : double(k);
      if (!(v < double(n))) {
        fail(path, "index " + std::to_string(uint64_t(v)) + " names no vertex of a primitive of " + std::to_string(n));
      }
      return int(first + size_t(v));
    };
    const bool mirrored = glm::determinant(glm::dmat3(m)) < 0;
    auto add = [&](size_t a, size_t b, size_t c) {
      glm::ivec3 t(corner(a), corner(b), corner(c));
      if (mirrored) std::swap(t.y, t.z);
      out.triangles.push_back(t);
      std::array<glm::vec2, 3> face{};
      if (uv) {
        const size_t k[3] = {size_t(t.x) - first, size_t(t.y) - first, size_t(t.z) - first};
        for (int j = 0; j < 3; ++j)
          face[size_t(j)] = glm::vec2(uv->get(k[j], 0), 1.0 - uv->get(k[j], 1));  // v down -> up
      }
      out.face_uv.push_back(face);
      out.face_texture.push_back(texture);
    };
    const size_t triangles = p.mode == 4 ? corners / 3 : corners >= 3 ? corners - 2 : 0;
    if (double(out.triangles.size()) + double(triangles) > kMaxMeshTriangles) {
      fail(path, "more than 100 million triangles (mesh instances included)");
    }
    for (size_t t = 0; t < triangles; ++t) {
      if (p.mode == 4)
        add(3 * t, 3 * t + 1, 3 * t + 2);
      else if (p.mode == 5)
        t % 2 ? add(t + 1, t, t + 2) : add(t, t + 1, t + 2);
      else
        add(0, t + 1, t + 2);
    }
  }
};

// The encoded bytes of image `im` (a JSON object of the file's "images"):
// its buffer view's, every range checked; a data URI's, base64-decoded; or
// a file's beside the glTF (a regular file, within the read budget).
std::string image_bytes(const std::string& path, const tinygltf::Model& model, const nlohmann::json& im,
                        const std::string& uri, const std::string& name, const std::string& dir, ReadBudget& budget) {
  if (!im.is_object()) fail(path, name + " is not a JSON object");
  if (auto v = im.find("bufferView"); v != im.end()) {
    if (!v->is_number_unsigned() || v->get<uint64_t>() >= model.bufferViews.size()) {
      fail(path,
           name + " names buffer view " + v->dump() + ", but the file has " + std::to_string(model.bufferViews.size()));
    }
    const tinygltf::BufferView& view = model.bufferViews[v->get<size_t>()];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
      fail(path, name + ": its view names buffer " + std::to_string(view.buffer) + ", but the file has " +
                     std::to_string(model.buffers.size()));
    }
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    if (view.byteLength > data.size() || view.byteOffset > data.size() - view.byteLength) {
      fail(path, name + ": its view's bytes " + std::to_string(view.byteOffset) + " + " +
                     std::to_string(view.byteLength) + " run past its buffer's " + std::to_string(data.size()));
    }
    return std::string(reinterpret_cast<const char*>(data.data()) + view.byteOffset, view.byteLength);
  }
  if (uri.rfind("data:", 0) == 0) {
    const size_t comma = uri.find(',');
    std::string out;
    if (comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos ||
        !decode_base64(uri, comma + 1, out)) {
      fail(path, name + ": a data URI that is not base64");
    }
    return out;
  }
  if (uri.empty()) fail(path, name + " has neither a bufferView nor a uri");
  const std::string file = (std::filesystem::path(dir) / percent_decode(uri)).string();
  try {
    std::string out = files::read_bounded(file, budget.left, "an image");
    budget.left -= out.size();
    return out;
  } catch (const files::FileError& e) {
    fail(path, name + ": " + e.what());
  }
}

}  // namespace

bool is_gltf_path(const std::string& path) {
  const std::string ext = screen::lower_extension(path);
  return ext == ".gltf" || ext == ".glb";
}

MeshArrays read_gltf(const std::string& path, const MeshOptions& options) {
  std::string bytes;
  try {
    bytes = files::read_bounded(path, kMaxGltfBytes, "a glTF 2.0 file");
  } catch (const files::FileError& e) {
    throw std::runtime_error(e.what());
  }
  const bool binary = bytes.compare(0, 4, "glTF") == 0;
  std::string json = bytes, bin;
  if (binary) {
    if (std::string why = screen_glb(bytes, json, bin); !why.empty()) fail(path, why);
  } else if (screen::lower_extension(path) == ".glb") {
    fail(path, "not a GLB file (no \"glTF\" magic)");
  }
  nlohmann::json doc = screen_json(path, json);
  // The images are not given to tinygltf: 2.7 hands its image loader a
  // buffer view's bytes without checking the view against its buffer (a
  // heap overread found by the gltf fuzz target). We read them below.
  nlohmann::json images = nlohmann::json::array();
  if (auto it = doc.find("images"); it != doc.end()) {
    if (it->is_array()) images = *it;
    doc.erase(it);
  }
  json = doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (binary) {
    // The GLB again around the new JSON. tinygltf 2.7 takes the BIN chunk
    // to run to the file's end, its 8-byte header included: 8 zero bytes
    // after the end keep its reads of a buffer that long inside our memory.
    if (!bin.empty()) {
      for (auto& b : doc.value("buffers", nlohmann::json::array())) {
        if (b.is_object() && !b.contains("uri") && b.contains("byteLength") && b["byteLength"].is_number_unsigned() &&
            b["byteLength"].get<uint64_t>() > bin.size()) {
          fail(path, "the GLB buffer's byteLength " + b["byteLength"].dump() + " exceeds its BIN chunk of " +
                         std::to_string(bin.size()) + " bytes");
        }
        break;  // only the first buffer may be the BIN chunk
      }
    }
    while (json.size() % 4) json += ' ';
    auto u32 = [](uint64_t v) {
      const uint32_t w = uint32_t(v);
      return std::string(reinterpret_cast<const char*>(&w), 4);
    };
    const uint64_t length = 20 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
    bytes = "glTF" + u32(2) + u32(length) + u32(json.size()) + "JSON" + json;
    if (!bin.empty()) bytes += u32(bin.size()) + std::string("BIN\0", 4) + bin;
    bytes.append(8, '\0');
  }

  ReadBudget budget;
  budget.left -= std::min<uint64_t>(budget.left, bytes.size());
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&file_exists, &expand_path, &read_whole, &write_whole, &budget});
  tinygltf::Model model;
  std::string err, warn;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                              unsigned(bytes.size() - 8), dir)
                : loader.LoadASCIIFromString(&model, &err, &warn, json.data(), unsigned(json.size()), dir);
  } catch (const std::exception& e) {
    fail(path, std::string("glTF: ") + e.what());
  }
  if (!ok || !err.empty()) fail(path, "glTF: " + (err.empty() ? std::string("cannot read it") : err));

  Reader r{path, options, model, images, {}, {}, {}, 0, 0, true};
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(scene) >= model.scenes.size()) {
      fail(path,
           "default scene " + std::to_string(scene) + ", but the file has " + std::to_string(model.scenes.size()));
    }
    roots = model.scenes[size_t(scene)].nodes;
  } else {
    std::vector<bool> child(model.nodes.size());
    for (const auto& n : model.nodes)
      for (int c : n.children)
        if (c >= 0 && size_t(c) < child.size()) child[size_t(c)] = true;
    for (size_t i = 0; i < child.size(); ++i)
      if (!child[i]) roots.push_back(int(i));
  }
  for (int root : roots) r.node(root, glm::dmat4(1.0), 0);
  r.count_only = false, r.visits = 0;
  for (int root : roots) r.node(root, glm::dmat4(1.0), 0);
  if (r.skipped && options.warning) {
    options.warning(path + ": " + std::to_string(r.skipped) + " primitives of points or lines skipped");
  }
  if (r.out.triangles.empty()) fail(path, "the scene has no triangles");

  // Textures: every image's header against the budgets first, then decoded
  // from a private temporary file by read_texture (PNG or JPEG only).
  if (!r.texture_sources.empty()) {
    files::StagingDirectory staging(std::filesystem::temp_directory_path(), "svo-gltf-");
    std::vector<std::string> files(r.texture_sources.size());
    std::map<int, std::string> written;
    double total = 0;
    for (size_t i = 0; i < r.texture_sources.size(); ++i) {
      const int image = r.texture_sources[i].first;
      const nlohmann::json& im = images[size_t(image)];
      const std::string uri =
          im.is_object() && im.contains("uri") && im["uri"].is_string() ? im["uri"].get<std::string>() : "";
      const std::string name =
          "image " + std::to_string(image) + (uri.empty() || uri.rfind("data:", 0) == 0 ? "" : " (" + uri + ")");
      if (!written.count(image)) {
        const std::string data = image_bytes(path, model, im, uri, name, dir, budget);
        const char* ext = data.size() >= 8 && std::memcmp(data.data(), "\x89PNG\r\n\x1a\n", 8) == 0 ? ".png"
                          : data.size() >= 3 && std::memcmp(data.data(), "\xFF\xD8\xFF", 3) == 0    ? ".jpg"
                                                                                                    : nullptr;
        if (!ext) fail(path, name + ": not a PNG or JPEG image" + (data.empty() ? " (no bytes)" : ""));
        const std::string file = (staging.path() / ("image" + std::to_string(image) + ext)).string();
        files::write_file(file, data.data(), data.size());
        written[image] = file;
        try {
          total += texture_header_pixels(file, path, options.max_texture_pixels);
        } catch (const std::exception& e) {
          std::string why = e.what();
          if (auto at = why.find(file); at != std::string::npos) why.replace(at, file.size(), name);
          throw std::runtime_error(why);
        }
        if (total > options.max_total_texture_pixels) {
          fail(path, name + ": brings the textures to more than the limit of " +
                         std::to_string(int64_t(options.max_total_texture_pixels / 1048576.0)) +
                         " Mi pixels for all of them (--max-texture-mpix-total raises it)");
        }
      }
      files[i] = written[image];
    }
    for (size_t i = 0; i < files.size(); ++i) {
      Texture t;
      try {
        t = read_texture(files[i], path, options.max_texture_pixels);
      } catch (const std::exception& e) {
        std::string why = e.what();
        if (auto at = why.find(files[i]); at != std::string::npos)
          why.replace(at, files[i].size(), "image " + std::to_string(r.texture_sources[i].first));
        throw std::runtime_error(why);
      }
      for (glm::vec3& c : t.texels) c *= r.texture_sources[i].second;
      r.out.textures.push_back(std::move(t));
    }
  }
  return std::move(r.out);
}

}  // namespace svo::voxelizer::gltf
