// Mesh files to TriangleMesh through OpenMesh, textures through
// OpenImageIO. No OpenVDB here: the reference ray tracer reads meshes too.
#include <OpenImageIO/imagebuf.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <sstream>
#include <stdexcept>

#include "common/shared_math.h"
#include "svo/voxelizer/mesh.h"

namespace svo::voxelizer {

namespace {

struct MeshTraits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Color);
  HalfedgeAttributes(OpenMesh::Attributes::TexCoord2D | OpenMesh::Attributes::PrevHalfedge);
  FaceAttributes(OpenMesh::Attributes::TextureIndex);
  using Color = OpenMesh::Vec3uc;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

Texture load_texture(const std::string& file, const std::string& mesh_path) {
  OIIO::ImageBuf image(file);
  if (!image.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    throw std::runtime_error(mesh_path + ": texture " + file + ": " + image.geterror());
  }
  const OIIO::ImageSpec& spec = image.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels < 1) {
    throw std::runtime_error(mesh_path + ": texture " + file + ": no pixels");
  }
  // 8- and 16-bit images hold sRGB-encoded values; float images are linear.
  bool srgb = spec.format.basetype != OIIO::TypeDesc::FLOAT && spec.format.basetype != OIIO::TypeDesc::HALF;
  Texture t;
  t.width = spec.width, t.height = spec.height;
  t.texels.resize(size_t(t.width) * size_t(t.height));
  std::vector<float> pixel(size_t(spec.nchannels));
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      image.getpixel(x + spec.x, y + spec.y, pixel.data(), spec.nchannels);
      glm::vec3 c(pixel[0], pixel[std::min(1, spec.nchannels - 1)], pixel[std::min(2, spec.nchannels - 1)]);
      if (srgb) {
        c = glm::vec3(svo::math::svo_srgb_to_linear(c.x), svo::math::svo_srgb_to_linear(c.y),
                      svo::math::svo_srgb_to_linear(c.z));
      }
      t.texels[size_t(y) * size_t(t.width) + size_t(x)] = glm::clamp(c, glm::vec3(0), glm::vec3(1e4f));
    }
  return t;
}

// Slope variance of the OBJ's materials (the mean over the materials of its
// mtllib files): PBR roughness "Pr" alpha gives sigma^2 = alpha^2 / 2, a
// Phong exponent "Ns" the Beckmann equivalent sigma^2 = 1 / (Ns + 2).
// Returns a negative value when the file names no such material.
float obj_material_slope_variance(const std::string& path) {
  namespace fs = std::filesystem;
  std::ifstream obj(path);
  std::string line;
  double sum = 0;
  int count = 0;
  while (std::getline(obj, line)) {
    if (line.rfind("mtllib", 0) != 0) continue;
    std::istringstream names(line.substr(6));
    std::string name;
    while (names >> name) {
      std::ifstream mtl(fs::path(path).parent_path() / name);
      std::string m;
      double pr = -1, ns = -1;
      bool in_material = false;
      auto flush = [&] {
        if (!in_material) return;
        if (pr >= 0)
          sum += pr * pr / 2, ++count;
        else if (ns >= 0)
          sum += 1.0 / (ns + 2.0), ++count;
        pr = ns = -1;
      };
      while (std::getline(mtl, m)) {
        std::istringstream in(m);
        std::string key;
        in >> key;
        if (key == "newmtl") flush(), in_material = true;
        if (key == "Pr") in >> pr;
        if (key == "Ns") in >> ns;
      }
      flush();
    }
  }
  return count ? float(sum / count) : -1.0f;
}

}  // namespace

glm::vec3 Texture::sample(glm::vec2 uv) const {
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
  if (!OpenMesh::IO::read_mesh(mesh, path, opt)) {
    throw std::runtime_error(path + ": cannot read it as a mesh (OBJ, PLY, OFF or STL)");
  }
  if (mesh.n_faces() == 0) throw std::runtime_error(path + ": the mesh has no faces");
  TriangleMesh out;
  bool colours = opt.check(OpenMesh::IO::Options::VertexColor);
  glm::vec3 constant = options.colour.value_or(glm::vec3(0.8f));
  float material = std::filesystem::path(path).extension() == ".obj" ? obj_material_slope_variance(path) : -1.0f;
  out.sigma_rho2 = options.sigma_rho >= 0 ? options.sigma_rho * options.sigma_rho : material >= 0 ? material : 0.01f;
  for (auto v : mesh.vertices()) {
    auto p = mesh.point(v);
    glm::dvec3 q(p[0], p[1], p[2]);
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
      throw std::runtime_error(path + ": vertex " + std::to_string(v.idx()) + " has a non-finite coordinate");
    }
    out.positions.push_back(q);
    if (colours) {
      auto c = mesh.color(v);
      out.colours.push_back(glm::vec3(svo::math::svo_srgb_to_linear(c[0] / 255.0f),
                                      svo::math::svo_srgb_to_linear(c[1] / 255.0f),
                                      svo::math::svo_srgb_to_linear(c[2] / 255.0f)));
    } else {
      out.colours.push_back(constant);
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
      texture_of_id[id] = int(out.textures.size());
      out.textures.push_back(load_texture(file, path));
    }
  }
  for (auto f : mesh.faces()) {
    glm::ivec3 t;
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
    if (k != 3) continue;
    glm::dvec3 a = out.positions[size_t(t.x)], b = out.positions[size_t(t.y)], c = out.positions[size_t(t.z)];
    glm::dvec3 cross = glm::cross(b - a, c - a);
    double twice_area = glm::length(cross);
    if (!(twice_area > 0)) {
      ++out.degenerate;  // zero area: no normal, no surface; skipped
      continue;
    }
    out.triangles.push_back(t);
    out.face_normals.push_back(glm::vec3(cross / twice_area));
    int texture = -1;
    if (textured) {
      auto it = texture_of_id.find(mesh.texture_index(f));
      if (it != texture_of_id.end()) texture = it->second;
    }
    out.face_texture.push_back(texture);
    out.face_uv.push_back(uv);
    out.area += 0.5 * twice_area;
  }
  if (out.triangles.empty()) {
    throw std::runtime_error(path + ": the mesh has no triangle of non-zero area (" + std::to_string(out.degenerate) +
                             " degenerate)");
  }
  glm::dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : out.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (!(glm::length(hi - lo) > 0)) throw std::runtime_error(path + ": the mesh has zero extent");
  out.bounds = {glm::vec3(lo), glm::vec3(hi)};
  return out;
}

}  // namespace svo::voxelizer
