// The only translation unit that includes OpenVDB (slow to compile).
#include <OpenImageIO/imagebuf.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <mutex>
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

// Closest point to p on triangle (a, b, c), with its barycentric coordinates
// (Ericson, Real-Time Collision Detection, 5.1.5).
glm::dvec3 closest_on_triangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3& bary) {
  glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return bary = {1, 0, 0}, a;
  glm::dvec3 bp = p - b;
  double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return bary = {0, 1, 0}, b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    double v = d1 / (d1 - d3);
    return bary = {1 - v, v, 0}, a + v * ab;
  }
  glm::dvec3 cp = p - c;
  double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return bary = {0, 0, 1}, c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    double w = d2 / (d2 - d6);
    return bary = {1 - w, 0, w}, a + w * ac;
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return bary = {0, 1 - w, w}, b + w * (c - b);
  }
  double denom = 1 / (va + vb + vc);
  double v = vb * denom, w = vc * denom;
  bary = {1 - v - w, v, w};
  return a + ab * v + ac * w;
}

// A texture in linear RGB, sampled bilinearly with wrap-around (OBJ: v up).
struct Texture {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;

  static Texture load(const std::string& file, const std::string& mesh_path) {
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

  glm::vec3 sample(glm::vec2 uv) const {
    float fx = (uv.x - std::floor(uv.x)) * width - 0.5f, fy = (1.0f - (uv.y - std::floor(uv.y))) * height - 0.5f;
    int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
    float ax = fx - float(x0), ay = fy - float(y0);
    auto at = [&](int x, int y) {
      x = ((x % width) + width) % width, y = ((y % height) + height) % height;
      return texels[size_t(y) * size_t(width) + size_t(x)];
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), ax), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax), ay);
  }
};

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

class MeshSource : public SurfaceSource {
 public:
  MeshSource(const std::string& path, const MeshOptions& options) : path_(path) {
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
    bool colours = opt.check(OpenMesh::IO::Options::VertexColor);
    glm::vec3 constant = options.colour.value_or(glm::vec3(0.8f));
    float material = std::filesystem::path(path).extension() == ".obj" ? obj_material_slope_variance(path) : -1.0f;
    sigma_rho2_ = options.sigma_rho >= 0 ? options.sigma_rho * options.sigma_rho : material >= 0 ? material : 0.01f;
    for (auto v : mesh.vertices()) {
      auto p = mesh.point(v);
      glm::dvec3 q(p[0], p[1], p[2]);
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
        throw std::runtime_error(path + ": vertex " + std::to_string(v.idx()) + " has a non-finite coordinate");
      }
      positions_.push_back(q);
      if (colours) {
        auto c = mesh.color(v);
        colours_.push_back(glm::vec3(svo::math::svo_srgb_to_linear(c[0] / 255.0f),
                                     svo::math::svo_srgb_to_linear(c[1] / 255.0f),
                                     svo::math::svo_srgb_to_linear(c[2] / 255.0f)));
      } else {
        colours_.push_back(constant);
      }
    }
    // Textures named by the OBJ's materials (map_Kd), relative to the mesh.
    std::map<int, int> texture_of_id;
    OpenMesh::MPropHandleT<std::map<int, std::string>> mapping;
    bool textured =
        opt.check(OpenMesh::IO::Options::FaceTexCoord) && mesh.get_property_handle(mapping, "TextureMapping");
    if (textured) {
      std::filesystem::path dir = std::filesystem::path(path).parent_path();
      for (const auto& [id, name] : mesh.property(mapping)) {
        std::string file = (dir / name).string();
        if (!std::filesystem::exists(file)) throw std::runtime_error(path + ": texture " + file + " does not exist");
        texture_of_id[id] = int(textures_.size());
        textures_.push_back(Texture::load(file, path));
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
      glm::dvec3 a = positions_[size_t(t.x)], b = positions_[size_t(t.y)], c = positions_[size_t(t.z)];
      glm::dvec3 cross = glm::cross(b - a, c - a);
      double twice_area = glm::length(cross);
      if (!(twice_area > 0)) {
        ++degenerate_;  // zero area: no normal, no surface; skipped
        continue;
      }
      triangles_.push_back(t);
      face_normals_.push_back(glm::vec3(cross / twice_area));
      int texture = -1;
      if (textured) {
        auto it = texture_of_id.find(mesh.texture_index(f));
        if (it != texture_of_id.end()) texture = it->second;
      }
      face_texture_.push_back(texture);
      face_uv_.push_back(uv);
      area_ += 0.5 * twice_area;
    }
    if (triangles_.empty()) {
      throw std::runtime_error(path + ": the mesh has no triangle of non-zero area (" + std::to_string(degenerate_) +
                               " degenerate)");
    }
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& p : positions_) lo = glm::min(lo, p), hi = glm::max(hi, p);
    if (!(glm::length(hi - lo) > 0)) throw std::runtime_error(path + ": the mesh has zero extent");
    bounds_ = {glm::vec3(lo), glm::vec3(hi)};
  }

  Box bounds() const override { return bounds_; }
  float sigma_rho2() const override { return sigma_rho2_; }
  double surface_area() const override { return area_; }
  // Narrow band of 3 voxels each side, float distance + int32 polygon index, tree overhead.
  double bytes_per_sample() const override { return 6 * (4 + 4) * 1.5; }

  void prepare(const Lattice& lattice) override {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    lattice_ = lattice;
    transform_ = openvdb::math::Transform::createLinearTransform(lattice.voxel);
    transform_->postTranslate(openvdb::Vec3d(lattice.origin.x, lattice.origin.y, lattice.origin.z));
    std::vector<openvdb::Vec3s> points;
    points.reserve(positions_.size());
    for (const auto& p : positions_) {
      glm::dvec3 i = (p - lattice.origin) / lattice.voxel;
      points.emplace_back(float(i.x), float(i.y), float(i.z));
    }
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(triangles_.size());
    for (const auto& t : triangles_) tris.emplace_back(uint32_t(t.x), uint32_t(t.y), uint32_t(t.z));
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points, tris);
    index_ = openvdb::Int32Grid::create(-1);
    distance_ = openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform_, kBandVoxels, kBandVoxels, 0,
                                                                 index_.get());
  }

  std::vector<glm::ivec3> candidate_bricks(uint32_t brick_size) const override {
    std::vector<glm::ivec3> out;
    const float h = float(lattice_.voxel);
    const int B = int(brick_size), limit = int(lattice_.resolution / brick_size);
    for (auto leaf = distance_->tree().cbeginLeaf(); leaf; ++leaf) {
      bool surface = false;
      for (auto v = leaf->cbeginValueOn(); v && !surface; ++v) surface = std::abs(*v) <= 0.5f * h;
      if (!surface) continue;
      openvdb::CoordBBox box = leaf->getNodeBoundingBox();
      glm::ivec3 lo(box.min().x(), box.min().y(), box.min().z()), hi(box.max().x(), box.max().y(), box.max().z());
      glm::ivec3 blo = glm::max(glm::ivec3(0), glm::ivec3(glm::floor(glm::vec3(lo) / float(B))));
      glm::ivec3 bhi = glm::min(glm::ivec3(limit - 1), glm::ivec3(glm::floor(glm::vec3(hi) / float(B))));
      for (int z = blo.z; z <= bhi.z; ++z)
        for (int y = blo.y; y <= bhi.y; ++y)
          for (int x = blo.x; x <= bhi.x; ++x) out.emplace_back(x, y, z);
    }
    std::sort(out.begin(), out.end(),
              [](glm::ivec3 a, glm::ivec3 b) { return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x); });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  using SurfaceSource::evaluate;
  void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const override {
    out.clear();
    auto dist = distance_->getConstAccessor();
    auto index = index_->getConstAccessor();
    const float band = std::min(kBandVoxels * float(lattice_.voxel), near_within);
    const float background = distance_->background();
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          openvdb::Coord ijk(x, y, z);
          FinePoint point;
          float d = dist.getValue(ijk);
          int32_t tri = index.getValue(ijk);
          if (std::abs(d) < band && tri >= 0 && size_t(tri) < triangles_.size()) {
            glm::dvec3 p = lattice_.position({x, y, z});
            const glm::ivec3& t = triangles_[size_t(tri)];
            glm::dvec3 bary;
            glm::dvec3 c =
                closest_on_triangle(p, positions_[size_t(t.x)], positions_[size_t(t.y)], positions_[size_t(t.z)], bary);
            double exact = glm::length(p - c);
            point.near = exact < band;
            point.distance = float(d < 0 ? -exact : exact);
            point.closest = glm::vec3(c);
            // The closest triangle's own normal (DESIGN section 6): interpolated
            // vertex normals would bend flat faces next to sharp edges.
            point.normal = face_normals_[size_t(tri)];
            int texture = face_texture_[size_t(tri)];
            if (texture >= 0) {
              const auto& uv = face_uv_[size_t(tri)];
              glm::vec2 at = float(bary.x) * uv[0] + float(bary.y) * uv[1] + float(bary.z) * uv[2];
              point.colour = textures_[size_t(texture)].sample(at);
            } else {
              point.colour = float(bary.x) * colours_[size_t(t.x)] + float(bary.y) * colours_[size_t(t.y)] +
                             float(bary.z) * colours_[size_t(t.z)];
            }
            if (!point.near) point.distance = d < 0 ? -band : band;
          } else {
            float magnitude = std::max(std::abs(d), band);
            point.distance = (d < 0 || (d == -background)) ? -magnitude : magnitude;
          }
          out.push_back(point);
        }
  }

 private:
  std::string path_;
  std::vector<glm::dvec3> positions_;
  std::vector<glm::vec3> face_normals_, colours_;
  std::vector<int> face_texture_;  // index into textures_, or -1
  std::vector<std::array<glm::vec2, 3>> face_uv_;
  std::vector<Texture> textures_;
  size_t degenerate_ = 0;
  std::vector<glm::ivec3> triangles_;
  double area_ = 0;
  float sigma_rho2_ = 0.01f;
  Box bounds_;
  Lattice lattice_;
  openvdb::math::Transform::Ptr transform_;
  openvdb::FloatGrid::Ptr distance_;
  openvdb::Int32Grid::Ptr index_;
};

}  // namespace

std::unique_ptr<SurfaceSource> load_mesh(const std::string& path, const MeshOptions& options) {
  return std::make_unique<MeshSource>(path, options);
}

}  // namespace svo::voxelizer
