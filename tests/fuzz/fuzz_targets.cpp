#include "fuzz_targets.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>
#include <xxhash.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <stdexcept>

#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/camera_path.h"
#include "svo/render/image_io.h"
#include "svo/render/luminaire.h"
#include "svo/render/merl.h"
#include "svo/render/shading.h"
#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/vdb.h"
#include "svo_format.h"

namespace svo::math {
struct FuzzLighting : render::NativeShadingReader {
#include "common/environment.glsl"
};
}  // namespace svo::math

namespace svo::fuzz {

namespace {

// A fatal finding: the contract itself is broken (not a sanitizer report).
[[noreturn]] void broken(const std::string& what) {
  std::fprintf(stderr, "fuzz: contract broken: %s\n", what.c_str());
  std::abort();
}

// The documented errors are one line: a message with a newline breaks the contract.
int refused(const std::exception& e) {
  if (std::strchr(e.what(), '\n')) broken(std::string("a message of several lines: ") + e.what());
  if (!*e.what()) broken("an empty message");
  return 0;
}

// A temporary file of this process, removed on scope exit.
struct TempFile {
  std::string path;
  TempFile(const uint8_t* data, size_t size, const std::string& extension) {
    std::filesystem::path dir = std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                                          : std::filesystem::temp_directory_path();
    path = (dir / ("svo-fuzz-" + std::to_string(::getpid()) + extension)).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    if (!out) broken("cannot write " + path);
  }
  ~TempFile() { ::unlink(path.c_str()); }
};

// Reads little-endian values from the input, zeros once it runs out.
struct Reader {
  const uint8_t* data;
  size_t size, at = 0;
  template <typename T>
  T get() {
    uint8_t bytes[sizeof(T)] = {};
    for (size_t i = 0; i < sizeof(T) && at < size; ++i) bytes[i] = data[at++];
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return v;
  }
};

constexpr uint32_t kMaxVertices = 2048, kMaxTriangles = 2048;

}  // namespace

int svo_load(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);  // aligned for SvoView
  if (bytes.size() >= octree::format::kHeaderBytes) octree::format::seal(bytes);
  try {
    octree::SvoView view(bytes, "fuzz.svo");
    octree::validate_octree(view.copy());
    return 1;
  } catch (const octree::FileError& e) {
    return refused(e);
  }
}

int mesh_arrays(const uint8_t* data, size_t size) {
  Reader in{data, size};
  const uint32_t n = in.get<uint32_t>() % (kMaxVertices + 1), m = in.get<uint32_t>() % (kMaxTriangles + 1);
  const uint8_t flags = in.get<uint8_t>();
  voxelizer::MeshArrays a;
  for (uint32_t i = 0; i < n; ++i) {
    double x = in.get<double>(), y = in.get<double>(), z = in.get<double>();
    a.positions.emplace_back(x, y, z);
  }
  if (flags & 1)
    for (uint32_t i = 0; i < n; ++i) {
      float r = in.get<float>(), g = in.get<float>(), b = in.get<float>();
      a.colours.emplace_back(r, g, b);
    }
  for (uint32_t i = 0; i < m; ++i) {
    int32_t p = in.get<int32_t>(), q = in.get<int32_t>(), r = in.get<int32_t>();
    a.triangles.emplace_back(p, q, r);
  }
  if (flags & 2)
    for (uint32_t i = 0; i < m; ++i) {
      std::array<glm::vec2, 3> uv;
      for (auto& c : uv) c.x = in.get<float>(), c.y = in.get<float>();
      a.face_uv.push_back(uv);
    }
  if (flags & 4)
    for (uint32_t i = 0; i < m; ++i) a.face_texture.push_back(in.get<int32_t>());
  if (flags & 8) {
    voxelizer::Texture t;
    t.width = t.height = 2;
    for (int i = 0; i < 4; ++i) t.texels.emplace_back(0.25f * float(i), 0.5f, 1.0f);
    a.textures.push_back(t);
  }
  if ((flags & 16) && !a.colours.empty()) a.colours.pop_back();  // a count that disagrees (when there are colours)
  voxelizer::TriangleMesh mesh;
  try {
    mesh = voxelizer::make_triangle_mesh("fuzz.obj", std::move(a));
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
  const size_t count = mesh.triangles.size();
  if (count == 0 || mesh.face_normals.size() != count || mesh.face_uv.size() != count ||
      mesh.face_texture.size() != count || mesh.colours.size() != mesh.positions.size()) {
    broken("accepted mesh with inconsistent arrays");
  }
  if (!(mesh.area > 0) || !std::isfinite(mesh.area)) broken("accepted mesh with area " + std::to_string(mesh.area));
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(mesh.bounds.lo[k]) || !std::isfinite(mesh.bounds.hi[k])) broken("non-finite bounds");
  }
  for (size_t f = 0; f < count; ++f) {
    for (int k = 0; k < 3; ++k) {
      if (mesh.triangles[f][k] < 0 || size_t(mesh.triangles[f][k]) >= mesh.positions.size())
        broken("corner out of range");
    }
    if (std::abs(glm::length(mesh.face_normals[f]) - 1.0f) > 1e-3f) broken("normal not unit");
    glm::vec3 c = mesh.colour(f, glm::dvec3(1.0 / 3));
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) broken("non-finite colour");
  }
  return 1;
}

// Reads the bytes as a mesh file named with `extension`; every corner read
// must name a vertex and every face must have a colour.
static int read_mesh_bytes(const uint8_t* data, size_t size, const char* extension) {
  TempFile file(data, size, extension);
  try {
    voxelizer::TriangleMesh mesh = voxelizer::read_mesh(file.path);
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (mesh.triangles[f][k] < 0 || size_t(mesh.triangles[f][k]) >= mesh.positions.size())
          broken("corner out of range");
      }
      (void)mesh.colour(f, glm::dvec3(1.0 / 3));
    }
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int mesh_file(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".obj", ".off", ".ply", ".stl"};
  return read_mesh_bytes(data + 1, size - 1, kExtensions[data[0] % 4]);
}

int gltf(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  return read_mesh_bytes(data + 1, size - 1, data[0] % 2 ? ".glb" : ".gltf");
}

int vdb(const uint8_t* data, size_t size) {
  TempFile file(data, size, ".vdb");
  try {
    auto source = voxelizer::load_vdb(file.path);
    const voxelizer::Box b = source->bounds();
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(b.lo[k]) || !std::isfinite(b.hi[k]) || !(b.lo[k] <= b.hi[k]))
        broken("bounds not finite or ordered");
    }
    if (!(source->surface_area() > 0)) broken("no surface area");
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int camera(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    switch (data[0] % 4) {
      case 0:
        render::parse_camera_json(text, "fuzz.json");
        break;
      case 1:
        render::parse_camera(text);
        break;
      case 2:
        render::parse_light(text, glm::vec3(0));
        break;
      default: {
        render::CameraPath path = render::parse_camera_path(text, "fuzz-path.json");
        if (path.keys.size() < 2 || path.frames < 2) broken("accepted path with fewer than 2 keys or frames");
        // Every camera along an accepted path must be usable.
        const uint32_t frames = std::min<uint32_t>(path.frames, 64);
        for (uint32_t f = 0; f < frames; ++f) {
          render::Camera c = render::sample_path(path.keys, double(f) * double(path.keys.size() - 1) / (frames - 1));
          for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(c.eye[k]) || !std::isfinite(c.target[k]) || !std::isfinite(c.up[k])) {
              broken("a non-finite camera along an accepted path");
            }
          }
        }
      }
    }
    return 1;
  } catch (const std::invalid_argument& e) {
    return refused(e);
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int texture(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  static const char* kExtensions[] = {".png", ".exr", ".ppm", ".tga"};
  TempFile file(data + 2, size - 2, kExtensions[data[0] % 4]);
  try {
    if (data[1] % 2 == 0) {
      voxelizer::Texture t = voxelizer::read_texture(file.path, "fuzz.obj");
      if (t.width <= 0 || t.height <= 0 || t.texels.size() != size_t(t.width) * size_t(t.height)) {
        broken("accepted texture without texels");
      }
      for (const glm::vec3& c : t.texels) {
        for (int k = 0; k < 3; ++k) {
          if (!(c[k] >= 0 && c[k] <= 1e4f)) broken("texel outside [0, 1e4]: " + std::to_string(c[k]));
        }
      }
      (void)t.sample(glm::vec2(0.3f, 0.7f));
    } else {
      render::Image image = render::read_image(file.path);
      if (image.pixels.size() != size_t(image.width) * size_t(image.height) * image.channels.size()) {
        broken("accepted image whose pixel count disagrees with its size");
      }
    }
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int merl(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool tiled = data[0] % 2 == 1;
  uint8_t header[12] = {};
  const size_t head = tiled ? std::min<size_t>(12, size - 1) : size - 1;
  if (tiled) std::memcpy(header, data + 1, head);
  TempFile file(tiled ? header : data + 1, tiled ? 12 : size - 1, ".binary");
  if (tiled) {
    // The payload streamed in chunks of whole periods (zeros without a pattern).
    const uint8_t* pattern = data + 1 + head;
    const size_t period = size - 1 - head;
    std::vector<uint8_t> chunk;
    if (period == 0) {
      chunk.assign(1 << 20, 0);
    } else {
      while (chunk.size() < (1 << 20)) chunk.insert(chunk.end(), pattern, pattern + period);
    }
    std::ofstream out(file.path, std::ios::binary | std::ios::app);
    for (uint64_t left = render::kMerlFileBytes - 12; left > 0;) {
      const size_t n = size_t(std::min<uint64_t>(left, chunk.size()));
      out.write(reinterpret_cast<const char*>(chunk.data()), std::streamsize(n));
      left -= n;
    }
    if (!out) broken("cannot write " + file.path);
  }
  try {
    const render::MerlBrdf brdf = render::load_merl(file.path);
    if (brdf.rgb.size() != 3 * size_t(render::kMerlSamples)) broken("accepted MERL table of the wrong size");
    for (float v : brdf.rgb) {
      if (!(v >= 0) || !std::isfinite(v)) broken("accepted MERL value " + std::to_string(v));
    }
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int environment(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".exr", ".hdr"};
  TempFile file(data + 1, size - 1, kExtensions[data[0] % 2]);
  try {
    const render::Environment env = render::load_environment(file.path);
    if (env.rgb.size() != size_t(env.width) * env.height * 3)
      broken("accepted map whose texels disagree with its size");
    // An accepted map must sample: finite directions and densities, > 0.
    render::ShadingOptions o;
    o.environment = std::make_shared<const render::Environment>(env);
    const render::ShadingTables t = render::build_shading_tables(o, render::builtin_material(0.04f, 0.01f), false);
    svo::math::FuzzLighting lit{{t.params, t.floats.data()}};
    for (float u : {0.0f, 0.37f, 0.99999994f}) {
      const glm::vec4 s = lit.svo_env_sample(lit.shade, glm::vec2(u, 1.0f - u));
      if (!std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(s.z) || !std::isfinite(s.w)) {
        broken("an accepted map sampled a non-finite direction or pdf");
      }
      if (s.w > 0 && !std::isfinite(lit.svo_env_pdf(lit.shade, glm::vec3(s)))) broken("non-finite pdf");
    }
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int material(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const render::Material m = render::parse_material(text, std::filesystem::temp_directory_path(), "fuzz.json");
    // What was accepted writes back to JSON that parses to the same kind.
    if (m.kind != render::BrdfKind::Merl && render::parse_material(render::material_json(m), ".").kind != m.kind) {
      broken("an accepted material does not round-trip");
    }
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int scene_file(const uint8_t* data, size_t size) {
  // The meshes a scene may name, beside it (see write_seeds).
  static const bool meshes = [] {
    const std::filesystem::path dir = TempFile(nullptr, 0, ".json").path;
    std::ofstream(dir.parent_path() / "svo-fuzz-tet.off")
        << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    std::ofstream(dir.parent_path() / "svo-fuzz-groups.obj")
        << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl a\nf 1 3 2\nf 1 2 4\nusemtl b\nf 1 4 3\nf 2 3 4\n";
    return true;
  }();
  (void)meshes;
  TempFile file(data, size, ".json");
  try {
    const voxelizer::TriangleMesh mesh = voxelizer::read_scene_file(file.path);
    const size_t count = mesh.triangles.size();
    if (count == 0 || mesh.face_normals.size() != count || mesh.face_uv.size() != count ||
        mesh.face_texture.size() != count || (!mesh.face_material.empty() && mesh.face_material.size() != count)) {
      broken("accepted scene with inconsistent arrays");
    }
    if (mesh.materials.size() > 255) broken("accepted scene with more than 255 materials");
    for (size_t f = 0; f < count; ++f) {
      if (!mesh.face_material.empty() && mesh.face_material[f] >= mesh.materials.size()) {
        broken("face material out of range");
      }
      if (std::abs(glm::length(mesh.face_normals[f]) - 1.0f) > 1e-3f) broken("normal not unit");
    }
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(mesh.bounds.lo[k]) || !std::isfinite(mesh.bounds.hi[k])) broken("non-finite bounds");
    }
    // Its materials as the voxelizer checks them.
    render::parse_scene_materials(mesh.materials, "fuzz scene");
    return 1;
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
}

int luminaire(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  if (bytes.size() >= 8) {
    const uint64_t sum = XXH64(bytes.data(), bytes.size() - 8, 0);
    for (int k = 0; k < 8; ++k) bytes[bytes.size() - 8 + size_t(k)] = uint8_t(sum >> (8 * k));
  }
  render::LightField field;
  try {
    field = render::parse_light_field(bytes.data(), bytes.size(), "fuzz.lfl");
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
  // What was accepted is valid and writes back to bytes that parse back.
  try {
    render::validate_light_field(field);
    const std::vector<uint8_t> again = render::encode_light_field(field);
    const render::LightField back = render::parse_light_field(again.data(), again.size(), "fuzz-again.lfl");
    if (back.width != field.width || back.height != field.height || back.grid_w != field.grid_w ||
        back.grid_h != field.grid_h || back.images.size() != field.images.size() || back.source != field.source ||
        back.units != field.units) {
      broken("an accepted light field parses back with other counts");
    }
  } catch (const std::runtime_error& e) {
    broken(std::string("an accepted light field does not round-trip: ") + e.what());
  }
  return 1;
}

int tm25(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  if (bytes.size() >= 288) bytes.insert(bytes.begin() + 288, 36000, uint8_t(0));
  TempFile file(bytes.data(), bytes.size(), ".tm25ray");
  render::LightField field;
  try {
    field = render::import_tm25(file.path, 3, 8);
  } catch (const std::runtime_error& e) {
    return refused(e);
  }
  try {
    render::validate_light_field(field);
  } catch (const std::runtime_error& e) {
    broken(std::string("an imported light field is not valid: ") + e.what());
  }
  return 1;
}

std::vector<std::string> target_names() {
  return {"svo_load", "mesh_arrays", "mesh_file", "camera", "texture", "merl", "environment",
          "material", "scene_file",  "luminaire", "tm25",   "gltf",    "vdb"};
}

int run_target(const std::string& name, const uint8_t* data, size_t size) {
  if (name == "svo_load") return svo_load(data, size);
  if (name == "mesh_arrays") return mesh_arrays(data, size);
  if (name == "mesh_file") return mesh_file(data, size);
  if (name == "camera") return camera(data, size);
  if (name == "texture") return texture(data, size);
  if (name == "merl") return merl(data, size);
  if (name == "environment") return environment(data, size);
  if (name == "material") return material(data, size);
  if (name == "scene_file") return scene_file(data, size);
  if (name == "luminaire") return luminaire(data, size);
  if (name == "tm25") return tm25(data, size);
  if (name == "gltf") return gltf(data, size);
  if (name == "vdb") return vdb(data, size);
  throw std::invalid_argument("no fuzz target " + name);
}

}  // namespace svo::fuzz
