// Seed corpora for the fuzz targets, made by the library's own writers.
#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "fuzz_targets.h"
#include "octree/test_trees.h"
#include "render/tm25_writer.h"
#include "svo/octree/svo_file.h"
#include "svo/render/camera.h"
#include "svo/render/camera_path.h"
#include "svo/render/image_io.h"
#include "svo/render/luminaire.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"
#include "svo/voxelizer/vdb.h"

namespace svo::fuzz {

namespace {

namespace fs = std::filesystem;

void put(const fs::path& file, const std::vector<uint8_t>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error(file.string() + ": cannot write seed");
}

std::vector<uint8_t> with_prefix(std::vector<uint8_t> prefix, const std::string& text) {
  prefix.insert(prefix.end(), text.begin(), text.end());
  return prefix;
}

std::vector<uint8_t> file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

const double kCorners[8][3] = {{-.5, -.5, -.5}, {.5, -.5, -.5}, {.5, .5, -.5}, {-.5, .5, -.5},
                               {-.5, -.5, .5},  {.5, -.5, .5},  {.5, .5, .5},  {-.5, .5, .5}};
const int kTriangles[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                               {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

std::string cube_text(const std::string& format) {
  std::ostringstream s;
  if (format == "off") {
    s << "OFF\n8 12 0\n";
    for (auto& c : kCorners) s << c[0] << " " << c[1] << " " << c[2] << "\n";
    for (auto& t : kTriangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  } else if (format == "obj") {
    for (auto& c : kCorners) s << "v " << c[0] << " " << c[1] << " " << c[2] << "\n";
    s << "vt 0 0\nvt 1 0\nvt 1 1\n";
    for (auto& t : kTriangles) s << "f " << t[0] + 1 << "/1 " << t[1] + 1 << "/2 " << t[2] + 1 << "/3\n";
  } else if (format == "ply") {
    s << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 12\n"
         "property list uchar int vertex_indices\nend_header\n";
    for (auto& c : kCorners) s << c[0] << " " << c[1] << " " << c[2] << " 200 100 50\n";
    for (auto& t : kTriangles) s << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  } else {
    s << "solid cube\n";
    for (auto& t : kTriangles) {
      s << "facet normal 0 0 0\nouter loop\n";
      for (int k = 0; k < 3; ++k)
        s << "vertex " << kCorners[t[k]][0] << " " << kCorners[t[k]][1] << " " << kCorners[t[k]][2] << "\n";
      s << "endloop\nendfacet\n";
    }
    s << "endsolid cube\n";
  }
  return s.str();
}

// The cube as a binary PLY (float x y z, uchar-counted int lists) in either
// byte order, so that the mesh-file target starts inside the binary reader.
std::string cube_binary_ply(bool big_endian) {
  std::string s = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\nelement face 12\n"
                  "property list uchar int vertex_indices\nend_header\n";
  auto put4 = [&](const void* p) {
    const char* b = static_cast<const char*>(p);
    for (int i = 0; i < 4; ++i) s += b[big_endian ? 3 - i : i];  // the host is little-endian
  };
  for (auto& c : kCorners) {
    for (double v : c) {
      float f = float(v);
      put4(&f);
    }
  }
  for (auto& t : kTriangles) {
    s += char(3);
    for (int k = 0; k < 3; ++k) put4(&t[k]);
  }
  return s;
}

}  // namespace

std::vector<uint8_t> mesh_arrays_encode(const MeshSeed& seed) {
  std::vector<uint8_t> out;
  auto add = [&](const auto& v) {
    uint8_t bytes[sizeof(v)];
    std::memcpy(bytes, &v, sizeof(v));
    out.insert(out.end(), bytes, bytes + sizeof(v));
  };
  const uint32_t n = uint32_t(seed.positions.size() / 3), m = uint32_t(seed.corners.size() / 3);
  add(n);
  add(m);
  add(uint8_t((seed.colours ? 1 : 0) | (seed.uv ? 2 : 0) | (seed.texture ? 4 | 8 : 0)));
  for (double p : seed.positions) add(p);
  if (seed.colours)
    for (uint32_t i = 0; i < 3 * n; ++i) add(float(i % 7) / 7.0f);
  for (int32_t c : seed.corners) add(c);
  if (seed.uv)
    for (uint32_t i = 0; i < 6 * m; ++i) add(float(i % 5) / 4.0f);
  if (seed.texture)
    for (uint32_t i = 0; i < m; ++i) add(int32_t(i % 2 ? 0 : -1));
  return out;
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
    if (i + 2 < in.size()) v |= uint8_t(in[i + 2]);
    out += k[(v >> 18) & 63], out += k[(v >> 12) & 63];
    out += i + 1 < in.size() ? k[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}

template <typename T>
void append(std::string& bin, const std::vector<T>& v) {
  bin.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// A unit cube: 8 positions (float), 8 colours (normalized bytes), 36
// indices (bytes), one buffer as a data URI.
std::string gltf_cube() {
  std::vector<float> pos;
  std::vector<uint8_t> col;
  for (int i = 0; i < 8; ++i) {
    pos.insert(pos.end(), {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    col.insert(col.end(), {uint8_t(255 * (i & 1)), 128, 200, 255});
  }
  const std::vector<uint8_t> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                    2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  std::string bin;
  append(bin, pos), append(bin, col), append(bin, idx);
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
"nodes": [{"mesh": 0, "translation": [1, 2, 3], "rotation": [0, 0.7071, 0, 0.7071]}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "COLOR_0": 1}, "indices": 2, "material": 0}]}],
"materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1]}}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3"},
 {"bufferView": 1, "componentType": 5121, "normalized": true, "count": 8, "type": "VEC4"},
 {"bufferView": 2, "componentType": 5121, "count": 36, "type": "SCALAR"}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 96}, {"buffer": 0, "byteOffset": 96, "byteLength": 32},
 {"buffer": 0, "byteOffset": 128, "byteLength": 36}],
"buffers": [{"byteLength": 164, "uri": "data:application/octet-stream;base64,)" +
         base64(bin) + "\"}]}";
}

// A quad with a 2x2 PNG baseColorTexture in the GLB's buffer.
std::string gltf_textured_quad(const fs::path& dir) {
  const fs::path file = dir / "texture.png";
  const unsigned char px[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};
  auto out = OIIO::ImageOutput::create(file.string());
  OIIO::ImageSpec spec(2, 2, 3, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, px) || !out->close()) {
    throw std::runtime_error(file.string() + ": cannot write seed image");
  }
  const std::vector<uint8_t> png = file_bytes(file);
  fs::remove(file);
  std::string bin;
  append(bin, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});  // 48 bytes
  append(bin, std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1});              // 32
  append(bin, std::vector<uint16_t>{0, 1, 2, 0, 2, 3});                 // 12
  append(bin, png);
  while (bin.size() % 4) bin += '\0';
  std::string json =
      R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "scale": [2, 2, 2]}],
"meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
"materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 1, 1], "baseColorTexture": {"index": 0}}}],
"textures": [{"source": 0}], "images": [{"bufferView": 3, "mimeType": "image/png"}],
"accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
 {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
 {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
"bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
 {"buffer": 0, "byteOffset": 80, "byteLength": 12}, {"buffer": 0, "byteOffset": 92, "byteLength": )" +
      std::to_string(png.size()) + "}], \"buffers\": [{\"byteLength\": " + std::to_string(bin.size()) + "}]}";
  while (json.size() % 4) json += ' ';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  return "glTF" + u32(2) + u32(uint32_t(28 + json.size() + bin.size())) + u32(uint32_t(json.size())) + "JSON" + json +
         u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
}

int write_seeds(const fs::path& dir) {
  int count = 0;
  auto target = [&](const std::string& name) {
    fs::create_directories(dir / name);
    return dir / name;
  };
  // .svo files.
  {
    fs::path d = target("svo_load");
    octree::write_svo((d / "test_tree.svo").string(), octree::testing::make_test_tree(1));
    octree::write_svo((d / "tiny.svo").string(), octree::testing::make_tiny_tree());
    put(d / "version1.svo", octree::testing::tiny_version1_file());
    // Version 4: a material block and a material channel.
    octree::Octree materials = octree::testing::make_tiny_tree();
    materials.materials = {R"({"brdf": "lambert"})", R"({"brdf": "ggx", "roughness": 0.3})"};
    materials.channels.push_back({octree::Channel::Material, octree::Encoding::MaterialShare8});
    materials.brick_data.emplace_back(materials.pool_samples() * 2, uint8_t(1));
    octree::write_svo((d / "materials.svo").string(), materials);
    // Version 5: a source block, after an empty material block.
    octree::Octree source = octree::testing::make_tiny_tree();
    source.source = R"({"input": "lion.off", "resolution": 64, "surface": "drawn two-sided"})";
    octree::write_svo((d / "source.svo").string(), source);
    count += 5;
  }
  // Parsed meshes: a closed cube, the same with colours, uv and textures, an open square.
  {
    fs::path d = target("mesh_arrays");
    MeshSeed cube;
    for (auto& c : kCorners) cube.positions.insert(cube.positions.end(), c, c + 3);
    for (auto& t : kTriangles) cube.corners.insert(cube.corners.end(), t, t + 3);
    put(d / "cube", mesh_arrays_encode(cube));
    MeshSeed rich = cube;
    rich.colours = rich.uv = rich.texture = true;
    put(d / "cube_textured", mesh_arrays_encode(rich));
    MeshSeed square{{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}};
    put(d / "square", mesh_arrays_encode(square));
    count += 3;
  }
  // Mesh files: the first byte picks the extension (.obj, .off, .ply, .stl).
  {
    fs::path d = target("mesh_file");
    const char* formats[] = {"obj", "off", "ply", "stl"};
    for (uint8_t k = 0; k < 4; ++k)
      put(d / (std::string("cube_") + formats[k]), with_prefix({k}, cube_text(formats[k])));
    put(d / "cube_ply_binary_le", with_prefix({2}, cube_binary_ply(false)));
    put(d / "cube_ply_binary_be", with_prefix({2}, cube_binary_ply(true)));
    // OFF files svo's own reader reads: comment lines before the keyword
    // (as CGAL writes them), face colours.
    put(d / "cube_off_comments_first", with_prefix({1}, "# Output of a CGAL tool\n#CBP\n\n" + cube_text("off")));
    put(d / "tetra_off_face_colours",
        with_prefix({1}, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 1 0 0\n3 0 1 3 0 1 0\n3 0 3 2 0 0 1\n"
                         "3 1 2 3 0.5 0.5 0.5\n"));
    count += 8;
  }
  // Cameras, lights, paths: the first byte picks the parser.
  {
    fs::path d = target("camera");
    render::Camera c;
    c.eye = {0, 0.5f, 3}, c.target = {0, 0, 0}, c.up = {0, 1, 0}, c.fov_deg = 40;
    render::save_camera_json((d / "saved.json").string(), c);
    auto pinhole = file_bytes(d / "saved.json");
    put(d / "camera_json", with_prefix({0}, std::string(pinhole.begin(), pinhole.end())));
    fs::remove(d / "saved.json");
    c.aperture = 0.05f, c.focus = 3;
    render::save_camera_json((d / "saved.json").string(), c);
    auto lens = file_bytes(d / "saved.json");
    put(d / "camera_json_lens", with_prefix({0}, std::string(lens.begin(), lens.end())));
    fs::remove(d / "saved.json");
    put(d / "camera_text", with_prefix({1}, "0,0,3,0,0,0,0,1,0,40"));
    put(d / "light_dir", with_prefix({2}, "dir:0,1,0,3,0.02"));
    put(d / "light_point", with_prefix({2}, "point:2,2,2,5,0.1"));
    render::CameraPath path;
    render::Camera k0 = c, k1 = c;
    k0.aperture = k1.aperture = 0, k0.focus = k1.focus = 0;
    k1.eye = {0.1f, 0.1f, 0.4f}, k1.fov_deg = 30;
    path.keys = {k0, k1};
    path.frames = 12;
    put(d / "path", with_prefix({3}, render::camera_path_json(path)));
    count += 6;
  }
  // Images: first byte the extension (.png, .exr, .ppm, .tga), second the reader.
  {
    fs::path d = target("texture");
    const char* extensions[] = {".png", ".exr", ".ppm", ".tga"};
    for (uint8_t k = 0; k < 4; ++k) {
      fs::path file = d / (std::string("image") + extensions[k]);
      const int w = 4, h = 3, channels = 3;
      std::vector<float> pixels(size_t(w * h * channels));
      for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i % 11) / 10.0f;
      auto out = OIIO::ImageOutput::create(file.string());
      if (!out) throw std::runtime_error(file.string() + ": no OpenImageIO writer");
      OIIO::ImageSpec spec(w, h, channels, k == 1 ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
      if (!out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
        throw std::runtime_error(file.string() + ": cannot write seed image");
      }
      auto bytes = file_bytes(file);
      fs::remove(file);
      for (uint8_t reader = 0; reader < 2; ++reader) {
        std::vector<uint8_t> seed{k, reader};
        seed.insert(seed.end(), bytes.begin(), bytes.end());
        put(d / ("image" + std::to_string(k) + "_" + std::to_string(reader)), seed);
        ++count;
      }
    }
  }
  // MERL files: the first byte 1 expands a header and a repeated pattern
  // to a file of the valid size (fuzz_targets.h), 0 takes the bytes as they are.
  {
    fs::path d = target("merl");
    auto merl_seed = [](uint8_t mode, std::array<int32_t, 3> dims, const std::vector<double>& pattern) {
      std::vector<uint8_t> seed{mode};
      for (int32_t v : dims)
        for (int b = 0; b < 4; ++b) seed.push_back(uint8_t(uint32_t(v) >> (8 * b)));
      for (double v : pattern) {
        uint8_t bytes[8];
        std::memcpy(bytes, &v, 8);
        seed.insert(seed.end(), bytes, bytes + 8);
      }
      return seed;
    };
    // Small values, a missing sample (-1) among them.
    put(d / "tiled", merl_seed(1, {90, 90, 180}, {0.5, 1.0, 2.0, -1.0, 0.25, 3.0, 0.0}));
    put(d / "tiled_missing", merl_seed(1, {90, 90, 180}, {-1.0}));
    put(d / "refused-tiled-nan", merl_seed(1, {90, 90, 180}, {0.5, std::nan(""), 1.0}));
    put(d / "refused-tiled-dims", merl_seed(1, {90, 90, 360}, {0.5}));
    put(d / "refused-truncated", merl_seed(0, {90, 90, 180}, {0.5, 1.0, 2.0}));
    count += 5;
  }
  // Environment maps: first byte .exr (0) or .hdr (1); a small sky in each
  // format, written by the image writer the renderer uses.
  {
    fs::path d = target("environment");
    for (uint8_t k = 0; k < 2; ++k) {
      fs::path file = d / (k == 0 ? "sky.exr" : "sky.hdr");
      render::Frame sky;
      sky.width = 16;
      sky.height = 8;
      for (uint32_t y = 0; y < sky.height; ++y) {
        for (uint32_t x = 0; x < sky.width; ++x) {
          sky.colour.push_back(y < 4 ? glm::vec4(0.3f, 0.5f, 0.9f, 1) : glm::vec4(0.1f, 0.08f, 0.05f, 1));
        }
      }
      sky.colour[19] = glm::vec4(50, 45, 40, 1);  // a sun
      if (k == 0) {
        render::write_colour(file.string(), sky);
      } else {
        auto out = OIIO::ImageOutput::create(file.string());
        std::vector<float> rgb;
        for (const auto& c : sky.colour) rgb.insert(rgb.end(), {c.r, c.g, c.b});
        OIIO::ImageSpec spec(16, 8, 3, OIIO::TypeDesc::FLOAT);
        if (!out || !out->open(file.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()) ||
            !out->close()) {
          throw std::runtime_error(file.string() + ": cannot write seed map");
        }
      }
      auto bytes = file_bytes(file);
      fs::remove(file);
      std::vector<uint8_t> seed{k};
      seed.insert(seed.end(), bytes.begin(), bytes.end());
      put(d / (k == 0 ? "sky_exr" : "sky_hdr"), seed);
      ++count;
    }
  }
  // Materials: one of each analytic kind, and a refused one.
  {
    fs::path d = target("material");
    const char* jsons[] = {R"({"brdf": "lambert", "colour": [0.5, 0.4, 0.3]})",
                           R"({"name": "gold", "brdf": "ggx", "roughness": 0.3, "f0": [1, 0.8, 0.3]})",
                           R"({"brdf": "beckmann", "roughness": 0.1, "ior": 1.5, "diffuse": 0.2})",
                           R"({"brdf": "phong", "exponent": 200, "f0": 0.04})",
                           R"({"brdf": "merl", "file": "missing.binary"})"};
    const char* names[] = {"lambert", "ggx", "beckmann", "phong", "refused-merl-missing"};
    for (int k = 0; k < 5; ++k) {
      const std::string text = jsons[k];
      put(d / names[k], std::vector<uint8_t>(text.begin(), text.end()));
      ++count;
    }
  }
  // Scene files: meshes placed with materials, the OBJ's own groups, a refused one.
  {
    fs::path d = target("scene_file");
    const char* jsons[] = {
        R"({"materials": {"gold": {"brdf": "ggx", "f0": [1, 0.8, 0.3]}, "clay": {"brdf": "lambert"}},
            "objects": [{"mesh": "svo-fuzz-tet.off", "material": "gold", "scale": [2, 1, 1], "rotate": [0, 30, 0]},
                        {"mesh": "svo-fuzz-tet.off", "material": "clay", "translate": [2, 0, 0], "colour": [1, 0, 0]}]})",
        R"({"objects": [{"mesh": "svo-fuzz-groups.obj", "scale": 3}]})",
        R"({"objects": [{"mesh": "svo-fuzz-tet.off", "material": "none"}]})"};
    const char* names[] = {"two-materials", "obj-groups", "refused-unknown-material"};
    for (int k = 0; k < 3; ++k) {
      const std::string text = jsons[k];
      put(d / names[k], std::vector<uint8_t>(text.begin(), text.end()));
      ++count;
    }
  }
  // Light fields (.lfl): both procedural emitters at small sizes (about
  // 3 KB each), one with the other basis and a non-square grid, and refused
  // ones whose checksum the target reseals (so only their values are wrong).
  {
    fs::path d = target("luminaire");
    render::LightField panel = render::make_panel_luminaire(8, 2, 100.0f, 2);
    render::LightField headlight = render::make_headlight_luminaire(8, 2, 500.0f);
    render::LightField odd = render::make_headlight_luminaire(6, 3, 20.0f);
    odd.basis = render::LuminaireBasis::Quadratic;
    odd.grid_h = 1;
    odd.images.resize(3);
    odd.units = "mm";
    odd.metres_per_unit = 0.001f;
    odd.pose = {{0.0f, 1.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 0.5f};
    put(d / "panel.lfl", render::encode_light_field(panel));
    put(d / "headlight.lfl", render::encode_light_field(headlight));
    put(d / "quadratic.lfl", render::encode_light_field(odd));
    std::vector<uint8_t> nan = render::encode_light_field(panel);
    const uint32_t images_at = uint32_t(nan[12]) | uint32_t(nan[13]) << 8;  // the header's length (< 65536)
    const float bad = std::nanf("");
    std::memcpy(&nan[images_at + 4 * 5], &bad, 4);
    put(d / "refused-nan.lfl", nan);
    std::vector<uint8_t> grid = render::encode_light_field(panel);
    grid[36] = 3;  // grid_w 3: more images than bytes
    put(d / "refused-grid.lfl", grid);
    count += 5;
  }
  // TM-25 ray files (the target inserts the description block): a small
  // Lambertian-like square, a photometric one with tristimulus colour and a
  // spectral table, and refused ones (a count that lies, a NaN origin).
  {
    fs::path d = target("tm25");
    testing::Tm25File square;
    square.compact = true;
    for (int k = 0; k < 100; ++k) {
      const float x = float(k % 10) * 0.1f - 0.45f, y = float(k / 10) * 0.1f - 0.45f;
      const float t = 0.1f * float(k % 7), p = 0.9f * float(k);
      square.rays.push_back({x, y, 0.0f, std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t), 0.01f});
    }
    testing::Tm25File warm = square;
    warm.photometric = true;
    warm.tristimulus = true;
    warm.spectrum_points = 0;
    for (auto& r : warm.rays) {
      r.tri_x = 1.2f * r.flux;
      r.tri_z = 0.5f * r.flux;
    }
    testing::Tm25File spectral = square;
    spectral.spectrum_points = 9;
    put(d / "square", testing::encode_tm25(square));
    put(d / "warm", testing::encode_tm25(warm));
    put(d / "spectral", testing::encode_tm25(spectral));
    testing::Tm25File lie = square;
    lie.count_override = 101;
    put(d / "refused-count", testing::encode_tm25(lie));
    testing::Tm25File nan = square;
    nan.rays[7].x = std::nanf("");
    put(d / "refused-nan", testing::encode_tm25(nan));
    count += 5;
  }
  // glTF (issue 21): the first byte picks .gltf (0) or .glb (1). A closed
  // cube with vertex colours, its buffer a data URI; a textured quad in a
  // GLB with its PNG in the buffer.
  {
    fs::path d = target("gltf");
    put(d / "cube_gltf", with_prefix({0}, gltf_cube()));
    put(d / "quad_glb", with_prefix({1}, gltf_textured_quad(d)));
    count += 2;
  }
  // OpenVDB level sets (issue 21): the bumpy sphere voxelized at 16^3 and
  // exported.
  {
    fs::path d = target("vdb");
    auto scene = voxelizer::make_scene("bumpy-sphere");
    voxelizer::VoxelizeOptions options;
    options.resolution = 16;
    voxelizer::export_vdb(voxelizer::voxelize(*scene, options), (d / "sphere").string());
    count += 1;
  }
  return count;
}

}  // namespace svo::fuzz
