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
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "common/shared_math.h"
#include "gltf_read.h"
#include "mesh_screen.h"
#include "svo/octree/files.h"
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
using screen::lower_extension;

// An OBJ material as its MTL file gives it (the keys we read; < 0: absent).
struct MtlMaterial {
  glm::vec3 kd{-1}, ks{-1};
  double ns = -1, pr = -1;
};

// The materials of the OBJ's mtllib files (relative to the OBJ, checked by
// screen::check_obj_material_files: regular files of at most 16 MiB; those
// that do not exist are skipped), by name.
std::map<std::string, MtlMaterial> read_mtl_materials(const std::string& path) {
  namespace fs = std::filesystem;
  std::map<std::string, MtlMaterial> out;
  std::ifstream obj(path, std::ios::binary);
  for (std::string line; std::getline(obj, line);) {
    std::istringstream names(line);
    std::string keyword;
    if (!(names >> keyword) || keyword != "mtllib") continue;
    for (std::string name; names >> name;) {
      const fs::path file = fs::path(path).parent_path() / name;
      std::error_code error;
      if (fs::status(file, error).type() == fs::file_type::not_found) continue;
      std::string text;
      try {
        text = files::read_bounded(file.string(), screen::kMaxMtlBytes, "an MTL material file");
      } catch (const files::FileError& e) {
        throw std::runtime_error(path + ": mtllib " + e.what());
      }
      std::istringstream entries(text);
      MtlMaterial* m = nullptr;
      for (std::string entry; std::getline(entries, entry);) {
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
// any usemtl), and per triangle an index into them. Also the faces'
// polygons (an index counted back from the vertices or texture coordinates
// read so far when negative).
struct ObjGroups {
  std::vector<std::string> names;
  std::vector<uint32_t> triangle_group;
  screen::FilePolygons polygons;
};
ObjGroups obj_groups(const std::string& path) {
  ObjGroups g;
  uint32_t current = 0;
  bool named = false;
  int vertices = 0;
  std::vector<glm::vec2> texcoords;
  // A 1-based OBJ index, or a negative one counted back from `count`, to 0-based; -1 if out of range.
  auto resolve = [](long i, int count) {
    return i > 0 && i <= count ? int(i - 1) : i < 0 && -i <= count ? int(count + i) : -1;
  };
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string keyword;
    if (!(words >> keyword)) continue;
    if (keyword == "v") {
      ++vertices;
      continue;
    }
    if (keyword == "vt") {
      glm::vec2 t(0.0f);
      words >> t.x >> t.y;
      texcoords.push_back(t);
      continue;
    }
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
    std::vector<int> face;
    std::vector<glm::vec2> uv;
    bool all_uv = true;
    for (std::string t; words >> t && t[0] != '#';) {
      // "v", "v/vt", "v//vn", "v/vt/vn"
      face.push_back(resolve(std::strtol(t.c_str(), nullptr, 10), vertices));
      const size_t slash = t.find('/');
      const int vt = slash == std::string::npos || slash + 1 >= t.size() || t[slash + 1] == '/'
                         ? -1
                         : resolve(std::strtol(t.c_str() + slash + 1, nullptr, 10), int(texcoords.size()));
      all_uv = all_uv && vt >= 0;
      if (all_uv) uv.push_back(texcoords[size_t(vt)]);
    }
    if (!all_uv) uv.clear();
    const int corners = int(face.size());
    g.polygons.add(std::move(face), std::move(uv));
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

namespace {

// A texture's image opened by the reader of its extension, its header read
// and checked against `max_pixels`, nothing decoded. Throws what
// read_texture throws.
std::unique_ptr<OIIO::ImageInput> open_texture(const std::string& file, const std::string& mesh_path, double max_pixels,
                                               OIIO::ImageSpec& spec) {
  const std::string where = mesh_path + ": texture " + file;
  auto fail = [&](std::string why) {
    if (auto nl = why.find('\n'); nl != std::string::npos) why.resize(nl);
    throw std::runtime_error(where + ": " + (why.empty() ? "cannot read it as an image" : why));
  };
  // A FIFO or a device (a link to /dev/zero) would hang the format
  // libraries: OpenImageIO tries every format it knows on a file without
  // an extension.
  try {
    files::require_regular_file(file, "an image");
  } catch (const files::FileError& e) {
    std::string why = e.what();
    if (why.rfind(file + ": ", 0) == 0) why.erase(0, file.size() + 2);
    fail(why);
  }
  // Checks in front of the format libraries, which trust their headers.
  if (std::string why = octree::check_exr_header(file, max_pixels); !why.empty()) fail(why);
  if (std::string why = octree::check_png_chunks(file); !why.empty()) fail(why);
  // The reader of the file's extension only: OpenImageIO's open() would
  // otherwise try every format it knows on a file its extension's rejects.
  auto input = OIIO::ImageInput::create(file, false);
  if (!input) fail("unsupported image format: " + OIIO::geterror());
  if (!input->open(file, spec)) fail(input->geterror());
  if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels < 1) fail("no pixels");
  // From the header, before the pixels are allocated: at most max_pixels
  // texels of 4 samples, twice the budget's square root a side.
  const double texels = double(spec.width) * double(spec.height);
  const double side = std::floor(std::sqrt(max_pixels));
  if (texels > max_pixels || texels * spec.nchannels > 4 * max_pixels || spec.width > 2 * side ||
      spec.height > 2 * side) {
    const std::string limit = side * side == max_pixels
                                  ? std::to_string(int64_t(side)) + "x" + std::to_string(int64_t(side))
                                  : std::to_string(int64_t(max_pixels)) + " pixels ";
    fail(std::to_string(spec.width) + "x" + std::to_string(spec.height) + "x" + std::to_string(spec.nchannels) +
         " samples, more than the limit of " + limit + "x4 (" + std::to_string(int64_t(2 * side)) +
         " a side); --max-texture-mpix raises it");
  }
  return input;
}

}  // namespace

double texture_header_pixels(const std::string& file, const std::string& mesh_path, double max_pixels) {
  OIIO::ImageSpec spec;
  open_texture(file, mesh_path, max_pixels, spec);
  return double(spec.width) * double(spec.height);
}

Texture read_texture(const std::string& file, const std::string& mesh_path, double max_pixels) {
  const std::string where = mesh_path + ": texture " + file;
  auto fail = [&](std::string why) {
    if (auto nl = why.find('\n'); nl != std::string::npos) why.resize(nl);
    throw std::runtime_error(where + ": " + (why.empty() ? "cannot read it as an image" : why));
  };
  OIIO::ImageSpec spec;
  auto input = open_texture(file, mesh_path, max_pixels, spec);
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

namespace {

// The positions and faces (fanned from their first corner; the polygons
// into `polygons`) of an ASCII OFF file the screen accepted (screen_off:
// vertex lines of 3 or more numbers, face lines of a count, that many indices below the vertex count and at
// most 4 colour numbers), colours not read; nullopt for the 4OFF and nOFF
// forms, whose vertices are not 3 numbers. For when OpenMesh's reader loses
// faces: it misreads face colours in a plain OFF file (libcgal-demo's
// quint_tris.off: 1 of 20 triangles kept).
std::optional<MeshArrays> read_off_plainly(const std::string& path, screen::FilePolygons* polygons) {
  std::ifstream in(path);
  std::string first;
  // Comment and blank lines before the keyword, as the screen skips them.
  while (std::getline(in, first)) {
    const size_t text = first.find_first_not_of(" \t\r");
    if (text != std::string::npos && first[text] != '#') break;
    first.clear();
  }
  const size_t keyword = first.find("OFF");
  if (keyword == std::string::npos || first.find_first_of("4n") < keyword) return std::nullopt;
  // Vertex, face and edge counts, comment lines between them skipped, as
  // the screen reads them.
  int64_t counts[3] = {0, 0, 0};
  for (int64_t& c : counts) {
    std::string word;
    while (in >> word && word[0] == '#') in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    c = std::strtoll(word.c_str(), nullptr, 10);
  }
  in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  MeshArrays arrays;
  arrays.positions.reserve(size_t(counts[0]));
  int64_t faces = 0;
  for (std::string line; faces < counts[1] && std::getline(in, line);) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);  // a comment
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string word; words >> word && word[0] != '#';) w.push_back(word);
    if (w.empty()) continue;
    if (int64_t(arrays.positions.size()) < counts[0]) {
      if (w.size() < 3) return std::nullopt;
      arrays.positions.emplace_back(std::strtod(w[0].c_str(), nullptr), std::strtod(w[1].c_str(), nullptr),
                                    std::strtod(w[2].c_str(), nullptr));
      continue;
    }
    ++faces;
    const size_t k = size_t(std::strtoll(w[0].c_str(), nullptr, 10));
    if (k > size_t(kMaxPolygonCorners) || w.size() < k + 1) return std::nullopt;
    std::vector<int> polygon;
    for (size_t i = 1; i <= k; ++i) polygon.push_back(int(std::strtol(w[i].c_str(), nullptr, 10)));
    for (size_t i = 2; i < k; ++i) arrays.triangles.emplace_back(polygon[0], polygon[i - 1], polygon[i]);
    polygons->add(std::move(polygon), {});
  }
  return arrays;
}

// Each polygon's run of triangles, made as fans (OpenMesh's reader, the OFF
// reader above), split again by triangulate_polygon where the fan leaves a
// non-convex polygon; face_uv follows the corners. The file's texture
// coordinates, where it gives them, are its polygons' corners': OpenMesh
// leaves those of its fan's triangles undefined (a textured OBJ quad was
// refused for "a non-finite texture coordinate"). Nothing changes unless
// the triangles are exactly the polygons' fans, in order (a reader that
// dropped or reordered faces). Returns the polygons split again.
size_t resplit_polygons(MeshArrays& arrays, const screen::FilePolygons& file) {
  if (file.triangles != arrays.triangles.size()) return 0;
  for (const screen::FilePolygon& polygon : file.polygons) {
    const std::vector<int>& c = polygon.corners;
    for (size_t i = 2; i < c.size(); ++i) {
      if (arrays.triangles[polygon.first_triangle + i - 2] != glm::ivec3(c[0], c[i - 1], c[i])) return 0;
    }
  }
  const int n = int(arrays.positions.size());
  const bool uv = arrays.face_uv.size() == arrays.triangles.size();
  size_t split = 0;
  std::vector<glm::dvec3> corners;
  std::vector<glm::vec2> corner_uv;
  for (const screen::FilePolygon& polygon : file.polygons) {
    const std::vector<int>& c = polygon.corners;
    const size_t k = c.size(), first = polygon.first_triangle;
    if (std::any_of(c.begin(), c.end(), [n](int i) { return i < 0 || i >= n; })) continue;
    corners.clear();
    for (int i : c) corners.push_back(arrays.positions[size_t(i)]);
    const std::vector<glm::ivec3> local = triangulate_polygon(corners);
    bool same = true;
    for (size_t j = 0; j < local.size(); ++j) same = same && local[j] == glm::ivec3(0, int(j) + 1, int(j) + 2);
    const bool file_uv = uv && polygon.uv.size() == k;
    if (same && !file_uv) continue;
    // Each corner's texture coordinates: the file's, else from the fan's triangles.
    corner_uv.assign(k, glm::vec2(0.0f));
    if (file_uv) {
      corner_uv = polygon.uv;
    } else if (uv) {
      for (size_t j = 0; j + 2 < k; ++j) {
        const auto& t = arrays.face_uv[first + j];
        corner_uv[0] = t[0];
        corner_uv[j + 1] = t[1];
        corner_uv[j + 2] = t[2];
      }
    }
    for (size_t j = 0; j < local.size(); ++j) {
      const glm::ivec3 l = local[j];
      arrays.triangles[first + j] = glm::ivec3(c[size_t(l.x)], c[size_t(l.y)], c[size_t(l.z)]);
      if (uv) arrays.face_uv[first + j] = {corner_uv[size_t(l.x)], corner_uv[size_t(l.y)], corner_uv[size_t(l.z)]};
    }
    split += same ? 0 : 1;
  }
  return split;
}

void report_resplit(const std::string& path, size_t split, const MeshOptions& options) {
  if (split > 0 && options.warning) {
    options.warning(path + ": " + std::to_string(split) + " non-convex polygon" + (split == 1 ? "" : "s") +
                    " split by ear clipping (a fan from the first corner would leave the polygon)");
  }
}

}  // namespace

TriangleMesh read_mesh(const std::string& path, const MeshOptions& options) {
  if (!std::filesystem::exists(path)) throw std::runtime_error(path + ": no such file");
  if (std::filesystem::is_directory(path)) throw std::runtime_error(path + ": is a directory, not a mesh");
  // A FIFO or a device would hang the reader or never end.
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(path + ": not a regular file");
  if (gltf::is_gltf_path(path)) return make_triangle_mesh(path, gltf::read_gltf(path, options), options);
  if (lower_extension(path) == ".vdb") {
    throw std::runtime_error(path + ": an OpenVDB level set is read by svo voxelize only, not as a mesh");
  }
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
  double file_triangles = -1;
  std::string own_reader;
  bool file_polygons = false;
  screen::FilePolygons ply_polygons;
  if (std::string why = screen::screen_mesh_file(path, &file_triangles, &own_reader, &file_polygons, &ply_polygons);
      !why.empty()) {
    throw std::runtime_error(path + ": " + why);
  }
  // An OFF file OpenMesh's reader cannot be trusted with is read by svo's
  // own reader: one whose face lines carry colours (OpenMesh took a colour
  // of -2 for the next face's corner count and pushed 4 GiB of handles,
  // found by the mesh_file fuzz target; it kept 1 of the 20 triangles of
  // libcgal-demo's quint_tris.off), or one with comment lines before its
  // keyword (OpenMesh refuses it: libcgal-demo's cube-shuffled.off). The
  // 4OFF and nOFF forms, which that reader does not read, are refused
  // rather than handed to OpenMesh.
  if (!own_reader.empty()) {
    screen::FilePolygons polygons;
    std::optional<MeshArrays> plain = read_off_plainly(path, &polygons);
    if (!plain) {
      throw std::runtime_error(path + ": a 4OFF or nOFF file with " + own_reader + ": not read (OpenMesh's " +
                               "reader cannot be trusted with it; write it as plain OFF)");
    }
    if (options.warning) {
      options.warning(path + ": " + own_reader + ": read by svo's own OFF reader (positions and faces; colours " +
                      "not read)");
    }
    report_resplit(path, resplit_polygons(*plain, polygons), options);
    return make_triangle_mesh(path, std::move(*plain), options);
  }
  // OpenMesh opens the OBJ's material files itself.
  if (lower_extension(path) == ".obj") screen::check_obj_material_files(path, options.warning);
  if (!OpenMesh::IO::read_mesh(mesh, path, opt)) {
    throw std::runtime_error(path + ": cannot read it as a mesh (OBJ, PLY, OFF or STL)");
  }
  // OpenMesh drops a face it cannot add (a corner repeated, a third face on
  // an edge) without a word: an OFF file is then read by our own reader,
  // others are said to have lost triangles, against the screen's count.
  // (It kept none of libcgal-demo's cube_poly.off, triangles and quads.)
  if (file_triangles > double(mesh.n_faces())) {
    const auto file = uint64_t(file_triangles);
    const std::string kept = std::to_string(mesh.n_faces()) + " of " + std::to_string(file) + " triangles";
    if (lower_extension(path) == ".off") {
      screen::FilePolygons polygons;
      if (std::optional<MeshArrays> plain = read_off_plainly(path, &polygons)) {
        if (options.warning) {
          options.warning(path + ": OpenMesh's reader kept " + kept + ": read by svo's own (positions and faces; " +
                          "colours not read)");
        }
        report_resplit(path, resplit_polygons(*plain, polygons), options);
        return make_triangle_mesh(path, std::move(*plain), options);
      }
    }
    if (options.warning) {
      options.warning(path + ": " + std::to_string(file - mesh.n_faces()) + " of " + std::to_string(file) +
                      " triangles dropped by the reader (a corner repeated, or a face it could not join to the "
                      "others)");
    }
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
    // Every texture's header first, against the budgets: nothing is
    // decoded unless all of them fit.
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::vector<std::string> files;
    double total = 0;
    for (const auto& [id, name] : mesh.property(mapping)) {
      std::string file = (dir / name).string();
      if (!std::filesystem::exists(file)) throw std::runtime_error(path + ": texture " + file + " does not exist");
      OIIO::ImageSpec spec;
      open_texture(file, path, options.max_texture_pixels, spec);
      total += double(spec.width) * double(spec.height);
      if (total > options.max_total_texture_pixels) {
        char why[160];
        std::snprintf(why, sizeof why,
                      ": %dx%d pixels bring the mesh's textures to %.0f Mi pixels, more than the limit of %.0f Mi "
                      "pixels for all of them (--max-texture-mpix-total raises it)",
                      spec.width, spec.height, std::ceil(total / 1048576.0),
                      std::floor(options.max_total_texture_pixels / 1048576.0));
        throw std::runtime_error(path + ": texture " + file + why);
      }
      texture_of_id[id] = int(files.size());
      files.push_back(file);
    }
    for (const std::string& file : files)
      arrays.textures.push_back(read_texture(file, path, options.max_texture_pixels));
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
  // OpenMesh fans every polygon: non-convex ones of an OFF, OBJ or PLY file
  // are split again from the file's own corner lists.
  const bool obj = lower_extension(path) == ".obj";
  const ObjGroups groups = obj ? obj_groups(path) : ObjGroups{};
  if (obj) {
    report_resplit(path, resplit_polygons(arrays, groups.polygons), options);
  } else if (!ply_polygons.polygons.empty()) {
    report_resplit(path, resplit_polygons(arrays, ply_polygons), options);
  } else if (lower_extension(path) == ".off" && file_polygons) {
    screen::FilePolygons polygons;
    if (read_off_plainly(path, &polygons)) report_resplit(path, resplit_polygons(arrays, polygons), options);
  }
  // OBJ usemtl groups: a material per group, from its MTL entry, when there
  // are two or more and OpenMesh kept every triangle in file order.
  const std::map<std::string, MtlMaterial> mtl = obj ? read_mtl_materials(path) : std::map<std::string, MtlMaterial>{};
  if (obj) {
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
// triangles spread over it (area-weighted): the share of its area that
// bounds a volume (bounds_volume: the winding number goes from near 0 to
// near 1 or -1 through it; the rest is a sheet, both sides outside; the
// shell of a surface drawn two-sided lies inside that volume), and the
// share where it goes from within 0.05 of 0 to within 0.05 of 1 (a closed
// surface gives 0 and 1 everywhere; from there, the holes take up less
// than 5% of the sphere).
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
    shares.bounds_volume += area * bounds_volume(middle);
    if (std::abs(middle - 0.5) < 0.05) shares.closed += area;
  }
  if (total > 0) shares.bounds_volume /= total, shares.closed /= total;
  return shares;
}

}  // namespace

namespace {

// Turns the faces of `mesh` that are wound against their neighbours: across
// every edge two triangles share (by position, TriangleMesh::welded; not
// across open or non-manifold edges), the second follows the first, breadth first from
// the first face of each connected piece; then each closed piece whose
// volume is negative (wound inside out) is turned whole. Returns the
// number of faces turned. Shading reads the faces' normals: libcgal-demo's
// cube-shuffled.off, whose faces are wound at random, drew half its
// triangles dark.
size_t orient_consistently(TriangleMesh& mesh) {
  const size_t m = mesh.triangles.size();
  auto key = [&](int a, int b) { return mesh.edge_key(a, b); };
  // (edge, face) for every edge of every face, sorted: a face's neighbours
  // across an edge by binary search (a hash map of vectors cost 2 s and
  // 120 MB more on a million triangles).
  std::vector<std::pair<uint64_t, uint32_t>> edge_faces;
  edge_faces.reserve(3 * m);
  for (size_t f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) edge_faces.emplace_back(key(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3]), f);
  std::sort(edge_faces.begin(), edge_faces.end());
  // Whether face f, as stored, runs from a to b (by position) along one of its edges.
  auto runs = [&](size_t f, int a, int b) {
    const glm::ivec3& t = mesh.triangles[f];
    const uint32_t wa = mesh.welded[size_t(a)], wb = mesh.welded[size_t(b)];
    for (int k = 0; k < 3; ++k)
      if (mesh.welded[size_t(t[k])] == wa && mesh.welded[size_t(t[(k + 1) % 3])] == wb) return true;
    return false;
  };
  std::vector<int8_t> flip(m, -1);  // -1: not reached yet
  std::vector<uint32_t> queue, piece;
  size_t turned = 0;
  for (size_t seed = 0; seed < m; ++seed) {
    if (flip[seed] >= 0) continue;
    flip[seed] = 0;
    queue.assign(1, uint32_t(seed));
    piece.clear();
    bool closed = true;
    for (size_t q = 0; q < queue.size(); ++q) {
      const uint32_t f = queue[q];
      piece.push_back(f);
      const glm::ivec3& t = mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const int a = t[k], b = t[(k + 1) % 3];
        const uint64_t edge = key(a, b);
        const auto shared = std::lower_bound(edge_faces.begin(), edge_faces.end(), std::make_pair(edge, 0u));
        if (shared + 1 >= edge_faces.end() || (shared + 1)->first != edge ||
            (shared + 2 < edge_faces.end() && (shared + 2)->first == edge)) {
          closed = false;  // an open or non-manifold edge
          continue;
        }
        const uint32_t g = shared->second == f ? (shared + 1)->second : shared->second;
        if (flip[g] >= 0) continue;
        // f runs a -> b as it will be (after its own turn); g must run b -> a.
        const bool f_ab = flip[f] == 0;
        const bool g_ab = runs(g, a, b);
        flip[g] = int8_t(g_ab == f_ab ? 1 : 0);
        queue.push_back(g);
      }
    }
    if (!closed) continue;
    // A closed piece: its volume as it will be wound says whether to turn it whole.
    double volume = 0;
    for (uint32_t f : piece) {
      glm::ivec3 t = mesh.triangles[f];
      if (flip[f]) std::swap(t.y, t.z);
      volume +=
          glm::dot(mesh.positions[size_t(t.x)], glm::cross(mesh.positions[size_t(t.y)], mesh.positions[size_t(t.z)]));
    }
    if (volume < 0)
      for (uint32_t f : piece) flip[f] = int8_t(1 - flip[f]);
  }
  for (size_t f = 0; f < m; ++f) {
    if (!flip[f]) continue;
    ++turned;
    std::swap(mesh.triangles[f].y, mesh.triangles[f].z);
    std::swap(mesh.face_uv[f][1], mesh.face_uv[f][2]);
    mesh.face_normals[f] = -mesh.face_normals[f];
  }
  return turned;
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
  {
    struct Hash {
      size_t operator()(const glm::dvec3& p) const {
        uint64_t h = 0;
        for (int k = 0; k < 3; ++k) {
          uint64_t bits;
          const double v = p[k] == 0 ? 0.0 : p[k];  // -0 and 0 alike
          std::memcpy(&bits, &v, sizeof bits);
          h = (h ^ bits) * 0x100000001b3ull;
        }
        return size_t(h ^ (h >> 29));
      }
    };
    std::unordered_map<glm::dvec3, uint32_t, Hash> first;
    first.reserve(n);
    out.welded.resize(n);
    for (size_t i = 0; i < n; ++i) out.welded[i] = first.emplace(out.positions[i], uint32_t(i)).first->second;
  }
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
      const int u = int(out.welded[size_t(t[k])]), v = int(out.welded[size_t(t[(k + 1) % 3])]);
      edges.emplace_back(std::min(u, v), std::max(u, v));
    }
  }
  if (out.triangles.empty()) {
    fail("the mesh has no triangle of non-zero area (" + std::to_string(out.degenerate) + " degenerate)");
  }
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : out.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (!(glm::length(hi - lo) > 0)) fail("the mesh has zero extent");
  if (const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}); !(extent >= kMinExtent)) {
    char why[160];
    std::snprintf(why, sizeof why, "the mesh's bounding box is too small: extent %.3g, below %.0e (scale it up)",
                  extent, kMinExtent);
    fail(why);
  }
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
  // Faces wound against their neighbours turned first: the winding number
  // below, and shading, read the winding.
  size_t turned = orient_consistently(out);
  // A surface with holes or non-manifold edges is drawn as a solid when the
  // winding number says its holes are small (OpenVDB's flood fill does not
  // leak through them), else two-sided (mesh_source.cpp).
  WindingShares shares;
  if (out.open_edges || out.nonmanifold_edges) {
    shares = winding_shares(out);
    out.two_sided = shares.closed < kClosedShare;
  }
  // A solid wound inside out (its faces clockwise seen from outside, so a
  // negative volume: libcgal-demo's tetrahedron, beam and ellipsoid) has
  // its faces turned: their normals, which shading reads, pointed inwards
  // and drew it dark. (Inside and outside come from the distance, not the
  // winding, so only the normals were wrong.) orient_consistently turned
  // closed pieces already; this covers a solid with small holes.
  if (!out.two_sided) {
    const glm::dvec3 centre = 0.5 * (lo + hi);
    double volume = 0;
    for (const glm::ivec3& t : out.triangles) {
      const glm::dvec3 a = out.positions[size_t(t.x)] - centre, b = out.positions[size_t(t.y)] - centre,
                       c = out.positions[size_t(t.z)] - centre;
      volume += glm::dot(a, glm::cross(b, c));
    }
    if (volume < 0) {
      turned = out.triangles.size() - turned;
      for (size_t f = 0; f < out.triangles.size(); ++f) {
        std::swap(out.triangles[f].y, out.triangles[f].z);
        std::swap(out.face_uv[f][1], out.face_uv[f][2]);
        out.face_normals[f] = -out.face_normals[f];
      }
    }
  }
  std::string decided = "a closed manifold surface: drawn as a solid";
  if (out.open_edges || out.nonmanifold_edges) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "by the winding number, %.1f%% of its area is closed (%.0f%% bounds a volume, %.0f%% is a sheet)",
                  100 * shares.closed, 100 * shares.bounds_volume, 100 * (1 - shares.bounds_volume));
    decided =
        "not a closed manifold surface (" + std::to_string(out.open_edges) + " open edges, " +
        std::to_string(out.nonmanifold_edges) + " non-manifold edges): " +
        (out.two_sided ? "drawn two-sided, as a thin shell around every triangle (inside the volume where it "
                         "bounds one); "
                       : "its holes are small: drawn as a solid, inside and outside from OpenVDB's flood fill; ") +
        why;
  }
  const std::string turned_text = turned == out.triangles.size()
                                      ? "its faces were wound inside out (clockwise seen from outside): turned"
                                      : std::to_string(turned) + " of its " + std::to_string(out.triangles.size()) +
                                            " faces were wound against the others or inside out: turned";
  if (turned) decided += "; " + turned_text;
  out.surface = decided;
  if (options.warning) {
    if (out.degenerate) {
      options.warning(path + ": " + std::to_string(out.degenerate) + " triangles of zero area dropped");
    }
    if (out.open_edges || out.nonmanifold_edges) {
      options.warning(path + ": " + decided);
    } else if (turned) {
      options.warning(path + ": " + turned_text);
    }
  }
  return out;
}

}  // namespace svo::voxelizer
