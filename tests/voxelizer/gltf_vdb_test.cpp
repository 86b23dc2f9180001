// glTF 2.0 and OpenVDB inputs, and the .vdb export (issue 21): tiny files
// written here (a textured quad, a cube), hostile ones refused with one line
// naming the file, and an export read back against the octree it came from.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "svo/octree/octree.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/scenes.h"
#include "svo/voxelizer/vdb.h"
#include "temp_dir.h"

namespace {

using namespace svo;
namespace fs = std::filesystem;
using nlohmann::json;

// This process's scratch directory, removed when the process exits.
fs::path temp_dir() {
  static const svo::testing::TempDir dir;
  return dir.path();
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

// A 4x4 PNG, quadrants top-left red, top-right green, bottom-left blue,
// bottom-right white (8-bit sRGB).
std::string quadrant_png() {
  const fs::path file = temp_dir() / "quadrants.png";
  unsigned char px[4][4][3];
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const int q = (y >= 2) * 2 + (x >= 2);
      const unsigned char c[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
      for (int k = 0; k < 3; ++k) px[y][x][k] = c[q][k];
    }
  auto out = OIIO::ImageOutput::create(file.string());
  OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::UINT8);
  EXPECT_TRUE(out->open(file.string(), spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px));
  out->close();
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += k[(v >> s) & 63];
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += k[(v >> 18) & 63], out += k[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += k[(v >> 18) & 63], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += '=';
  }
  return out;
}

// A glTF document under construction: one buffer, views appended to it.
struct Doc {
  json j = {{"asset", {{"version", "2.0"}}}, {"scene", 0}};
  std::string bin;

  template <typename T>
  int view(const std::vector<T>& data) {
    while (bin.size() % 4) bin += '\0';
    const size_t at = bin.size();
    bin.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(T));
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", at}, {"byteLength", data.size() * sizeof(T)}});
    return int(j["bufferViews"].size()) - 1;
  }
  int accessor(int view, int component, size_t count, const char* type) {
    j["accessors"].push_back({{"bufferView", view}, {"componentType", component}, {"count", count}, {"type", type}});
    return int(j["accessors"].size()) - 1;
  }
  // .gltf with the buffer as a data URI (or a file `bin_name` beside it).
  fs::path write_gltf(const std::string& name, const std::string& bin_name = "") {
    j["buffers"] = json::array({{{"byteLength", bin.size()}}});
    if (bin_name.empty()) {
      j["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    } else {
      j["buffers"][0]["uri"] = bin_name;
      write_bytes(temp_dir() / bin_name, bin);
    }
    write_bytes(temp_dir() / name, j.dump());
    return temp_dir() / name;
  }
  fs::path write_glb(const std::string& name) {
    while (bin.size() % 4) bin += '\0';
    j["buffers"] = json::array({{{"byteLength", bin.size()}}});
    std::string text = j.dump();
    while (text.size() % 4) text += ' ';
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    std::string glb = "glTF" + u32(2) + u32(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
    glb += u32(uint32_t(text.size())) + "JSON" + text + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
    write_bytes(temp_dir() / name, glb);
    return temp_dir() / name;
  }
};

// A unit quad in z = 0 (counter-clockwise from +z), uv over the texture's
// quadrant centres: vertex 0 at uv (0.25, 0.25) (top-left: red), vertex 1 at
// (0.75, 0.25) (top-right: green), vertex 3 at (0.25, 0.75) (bottom-left: blue).
Doc textured_quad(bool embed_image_in_buffer) {
  Doc d;
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<float> uv = {0.25f, 0.25f, 0.75f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  const int p = d.accessor(d.view(pos), 5126, 4, "VEC3");
  const int t = d.accessor(d.view(uv), 5126, 4, "VEC2");
  const int i = d.accessor(d.view(idx), 5123, 6, "SCALAR");
  d.j["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", p}, {"TEXCOORD_0", t}}}, {"indices", i}, {"material", 0}}})}}});
  d.j["nodes"] = json::array({{{"mesh", 0}}});
  d.j["scenes"] = json::array({{{"nodes", {0}}}});
  d.j["materials"] = json::array(
      {{{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 0.5, 1.0, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}}});
  d.j["textures"] = json::array({{{"source", 0}}});
  const std::string png = quadrant_png();
  if (embed_image_in_buffer) {
    const int v = d.view(std::vector<char>(png.begin(), png.end()));
    d.j["images"] = json::array({{{"bufferView", v}, {"mimeType", "image/png"}}});
  } else {
    write_bytes(temp_dir() / "quad_texture.png", png);
    d.j["images"] = json::array({{{"uri", "quad_texture.png"}}});
  }
  return d;
}

// The colour at a triangle corner that is vertex `v`.
glm::vec3 corner_colour(const voxelizer::TriangleMesh& m, int v) {
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (m.triangles[t][k] == v) {
        glm::dvec3 bary(0);
        bary[k] = 1;
        return m.colour(t, bary);
      }
  ADD_FAILURE() << "no corner at vertex " << v;
  return glm::vec3(-1);
}

void expect_near(glm::vec3 a, glm::vec3 b, const char* what) {
  EXPECT_NEAR(a.x, b.x, 1e-3) << what;
  EXPECT_NEAR(a.y, b.y, 1e-3) << what;
  EXPECT_NEAR(a.z, b.z, 1e-3) << what;
}

TEST(Gltf, TexturedQuadWithExternalFiles) {
  const fs::path path = textured_quad(false).write_gltf("quad.gltf", "quad.bin");
  const voxelizer::TriangleMesh m = voxelizer::read_mesh(path.string());
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.textures.size(), 1u);
  for (const auto& n : m.face_normals) expect_near(n, glm::vec3(0, 0, 1), "counter-clockwise from +z");
  // Texture times baseColorFactor (1, 0.5, 1); glTF's v runs down the image.
  expect_near(corner_colour(m, 0), glm::vec3(1, 0, 0), "top-left quadrant, red");
  expect_near(corner_colour(m, 1), glm::vec3(0, 0.5f, 0), "top-right quadrant, green x 0.5");
  expect_near(corner_colour(m, 3), glm::vec3(0, 0, 1), "bottom-left quadrant, blue");
}

TEST(Gltf, GlbWithEmbeddedImageAndNodeTransform) {
  Doc d = textured_quad(true);
  // Translated by (10, 0, 0), scaled 2, mirrored in x: the winding flips back.
  d.j["nodes"] = json::array({{{"children", {1}}, {"translation", {10, 0, 0}}}, {{"mesh", 0}, {"scale", {-2, 2, 2}}}});
  const fs::path path = d.write_glb("quad.glb");
  const voxelizer::TriangleMesh m = voxelizer::read_mesh(path.string());
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_NEAR(m.bounds.lo.x, 8, 1e-6);
  EXPECT_NEAR(m.bounds.hi.x, 10, 1e-6);
  EXPECT_NEAR(m.bounds.hi.y, 2, 1e-6);
  for (const auto& n : m.face_normals) expect_near(n, glm::vec3(0, 0, 1), "mirrored: winding flipped");
  expect_near(corner_colour(m, 0), glm::vec3(1, 0, 0), "red from the embedded PNG");
}

// A closed cube (12 triangles) with COLOR_0 and a baseColorFactor, as a
// triangle list.
Doc colour_cube() {
  Doc d;
  std::vector<float> pos, col;
  for (int i = 0; i < 8; ++i) {
    pos.insert(pos.end(), {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
    col.insert(col.end(), {1.0f, 1.0f, 0.5f});
  }
  const std::vector<uint32_t> idx = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                     2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  const int p = d.accessor(d.view(pos), 5126, 8, "VEC3");
  const int c = d.accessor(d.view(col), 5126, 8, "VEC3");
  const int i = d.accessor(d.view(idx), 5125, 36, "SCALAR");
  d.j["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", p}, {"COLOR_0", c}}}, {"indices", i}, {"material", 0}}})}}});
  d.j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 1.0, 1.0, 1.0}}}}}});
  d.j["nodes"] = json::array({{{"mesh", 0}}});
  d.j["scenes"] = json::array({{{"nodes", {0}}}});
  return d;
}

TEST(Gltf, VertexColoursTimesFactorOnAClosedCube) {
  const voxelizer::TriangleMesh m = voxelizer::read_mesh(colour_cube().write_gltf("cube.gltf").string());
  EXPECT_EQ(m.triangles.size(), 12u);
  EXPECT_EQ(m.open_edges, 0u);
  expect_near(corner_colour(m, 0), glm::vec3(0.5f, 1.0f, 0.5f), "COLOR_0 x baseColorFactor");
  // Outward normals: face z = 0 points down.
  EXPECT_LT(m.face_normals[0].z, -0.99f);
}

// The refusal of the file `path`: one line starting with the path and
// containing `fragment`.
void expect_refused(const fs::path& path, const std::string& fragment) {
  try {
    voxelizer::read_mesh(path.string());
    ADD_FAILURE() << path << " accepted; expected: " << fragment;
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(GltfHostile, AccessorBeyondItsView) {
  Doc d = colour_cube();
  d.j["accessors"][0]["count"] = 9;  // 9 positions in a view of 8
  expect_refused(d.write_gltf("past_view.gltf"), "run past its view's 96 bytes");
}

TEST(GltfHostile, HugeCount) {
  Doc d = colour_cube();
  d.j["accessors"][2]["count"] = 4000000000ull;
  expect_refused(d.write_gltf("huge_count.gltf"), "more than the budget");
  d.j["accessors"][2]["count"] = 36;
  d.j["bufferViews"][0]["byteLength"] = 1ull << 40;
  expect_refused(d.write_gltf("huge_view.gltf"), "run past its buffer's");
}

TEST(GltfHostile, IndexNamingNoVertex) {
  Doc d = colour_cube();
  d.j["accessors"][2]["count"] = 3;
  d.j["accessors"][2]["byteOffset"] = 0;
  const std::vector<uint32_t> idx = {0, 1, 800};
  d.j["accessors"][2]["bufferView"] = d.view(idx);
  expect_refused(d.write_gltf("bad_index.gltf"), "index 800 names no vertex of a primitive of 8");
}

TEST(GltfHostile, IndicesOutOfRange) {
  Doc d = colour_cube();
  d.j["meshes"][0]["primitives"][0]["indices"] = 99;
  expect_refused(d.write_gltf("bad_accessor.gltf"), "accessor");  // tinygltf's check or ours
  d = colour_cube();
  d.j["accessors"][0]["bufferView"] = 7;
  expect_refused(d.write_gltf("bad_view.gltf"), "buffer view 7");
  d = colour_cube();
  d.j["nodes"][0]["mesh"] = 5;
  expect_refused(d.write_gltf("bad_mesh.gltf"), "");
}

TEST(GltfHostile, BadJsonAndContainers) {
  write_bytes(temp_dir() / "bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
  expect_refused(temp_dir() / "bad.gltf", "not valid JSON");
  write_bytes(temp_dir() / "deep.gltf", std::string(100000, '[') + std::string(100000, ']'));
  expect_refused(temp_dir() / "deep.gltf", "JSON nested 100000 deep");
  write_bytes(temp_dir() / "v1.gltf", "{\"asset\": {\"version\": \"1.0\"}}");
  expect_refused(temp_dir() / "v1.gltf", "glTF version 1.0");
  write_bytes(temp_dir() / "text.glb", "{\"asset\": {\"version\": \"2.0\"}}");
  expect_refused(temp_dir() / "text.glb", "not a GLB file");
  std::string glb = colour_cube().write_glb("cut.glb").string();
  std::ifstream in(glb, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  write_bytes(glb, bytes.substr(0, bytes.size() / 2));
  expect_refused(glb, "GLB header states");
}

TEST(GltfHostile, UnsupportedFeaturesSaySo) {
  Doc d = colour_cube();
  d.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expect_refused(d.write_gltf("draco.gltf"), "requires extension KHR_draco_mesh_compression, which is not supported");
  d = colour_cube();
  d.j["accessors"][0]["sparse"] = {
      {"count", 1}, {"indices", {{"bufferView", 2}, {"componentType", 5125}}}, {"values", {{"bufferView", 0}}}};
  expect_refused(d.write_gltf("sparse.gltf"), "sparse accessors are not supported");
  d = textured_quad(false);
  d.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
  expect_refused(d.write_gltf("texcoord1.gltf"), "only TEXCOORD_0 is supported");
}

TEST(GltfHostile, NodeCycleAndExponentialInstancing) {
  Doc d = colour_cube();
  d.j["nodes"] = json::array({{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}});
  expect_refused(d.write_gltf("cycle.gltf"), "node hierarchy deeper than 64");
  d = colour_cube();
  d.j["nodes"] = json::array();
  for (int i = 0; i < 40; ++i) d.j["nodes"].push_back({{"children", {i + 1, i + 1}}});
  d.j["nodes"].push_back({{"mesh", 0}});
  expect_refused(d.write_gltf("fanout.gltf"), "node instances");
}

TEST(GltfHostile, FilesThatAreNotRegular) {
  Doc d = textured_quad(false);
  d.j["images"][0]["uri"] = "/dev/zero";
  expect_refused(d.write_gltf("dev_zero.gltf"), "/dev/zero");
  const fs::path fifo = temp_dir() / "fifo.bin";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  d = colour_cube();
  const fs::path path = d.write_gltf("fifo.gltf");
  std::string text = d.j.dump();
  d.j["buffers"][0]["uri"] = "fifo.bin";
  write_bytes(path, d.j.dump());
  expect_refused(path, "FIFO");
  expect_refused(temp_dir(), "directory");
}

// tinygltf 2.7 hands its image loader a buffer view's bytes without
// checking the view against its buffer (found by the gltf fuzz target):
// images are read by us, the range checked.
TEST(GltfHostile, ImageViewBeyondItsBuffer) {
  Doc d = textured_quad(true);
  d.j["bufferViews"][3]["byteLength"] = 100000;
  expect_refused(d.write_glb("image_view.glb"), "image 0: its view's bytes 92 + 100000 run past its buffer's");
  d = textured_quad(true);
  d.j["images"][0] = {{"uri", "data:image/png;base64,%%%"}};
  expect_refused(d.write_glb("image_uri.glb"), "image 0: a data URI that is not base64");
}

TEST(GltfHostile, TextureBudget) {
  const fs::path path = textured_quad(true).write_glb("budget.glb");
  voxelizer::MeshOptions options;
  options.max_texture_pixels = 8;  // the texture has 16
  try {
    voxelizer::read_mesh(path.string(), options);
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("more than the limit"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("image 0"), std::string::npos) << e.what();
  }
}

// The bumpy sphere voxelized, exported to .vdb, read back as a source on
// the octree's own lattice: the distances agree with the octree's finest
// level within the band; voxelized again, the sphere has the same extent.
TEST(Vdb, ExportReadsBackAndVoxelizes) {
  auto scene = voxelizer::make_scene("bumpy-sphere");
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  const octree::Octree tree = voxelizer::voxelize(*scene, options);
  const fs::path vdb = temp_dir() / "sphere.vdb";
  const voxelizer::VdbExport report = voxelizer::export_vdb(tree, vdb.string());
  EXPECT_GT(report.active_voxels, 1000u);
  EXPECT_NEAR(report.voxel_size, tree.voxel_size(tree.depth_count - 1), 1e-6);

  auto source = voxelizer::load_vdb(vdb.string());
  voxelizer::Lattice lattice;
  lattice.origin = glm::dvec3(tree.origin);
  lattice.voxel = report.voxel_size;
  lattice.resolution = tree.finest_resolution();
  source->prepare(lattice);
  // Along the x axis through the centre: the crossing matches.
  const int mid = int(lattice.resolution / 2);
  std::vector<voxelizer::FinePoint> row;
  source->evaluate({0, mid, mid}, {int(lattice.resolution), mid, mid}, row);
  int near = 0, sign_changes = 0;
  for (size_t i = 0; i < row.size(); ++i) {
    near += row[i].near;
    if (i && (row[i].distance < 0) != (row[i - 1].distance < 0)) ++sign_changes;
    if (row[i].near) {
      EXPECT_NEAR(glm::length(row[i].normal), 1.0f, 1e-4f);
    }
  }
  EXPECT_EQ(sign_changes, 2) << "one sphere: in and out once along the axis";
  EXPECT_GE(near, 4);
  // Voxelized from the .vdb: the same bounds within two voxels.
  const octree::Octree again = voxelizer::voxelize(*voxelizer::load_vdb(vdb.string()), options);
  const voxelizer::Box a = scene->bounds(), b = source->bounds();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.lo[k], b.lo[k], 2.5 * report.voxel_size);
    EXPECT_NEAR(a.hi[k], b.hi[k], 2.5 * report.voxel_size);
  }
  EXPECT_GT(again.brick_count, 0u);
}

void expect_vdb_refused(const fs::path& path, const std::string& fragment, const std::string& grid = "") {
  try {
    voxelizer::VdbOptions options;
    options.grid = grid;
    voxelizer::load_vdb(path.string(), options);
    ADD_FAILURE() << path << " accepted; expected: " << fragment;
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path.string() + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(VdbHostile, RefusedWithOneLine) {
  auto scene = voxelizer::make_scene("bumpy-sphere");
  voxelizer::VoxelizeOptions options;
  options.resolution = 32;
  const fs::path vdb = temp_dir() / "small.vdb";
  voxelizer::export_vdb(voxelizer::voxelize(*scene, options), vdb.string());
  expect_vdb_refused(vdb, "no grid named \"density\" (the file holds \"surface\" (float level set))", "density");
  std::ifstream in(vdb, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  // The class "level set" patched to "staggered" (same length).
  std::string patched = bytes;
  const size_t at = patched.find("level set");
  ASSERT_NE(at, std::string::npos);
  patched.replace(at, 9, "staggered");
  write_bytes(temp_dir() / "staggered.vdb", patched);
  expect_vdb_refused(temp_dir() / "staggered.vdb", "no float level set");
  expect_vdb_refused(temp_dir() / "staggered.vdb", "is not a level set", "surface");
  write_bytes(temp_dir() / "cut.vdb", bytes.substr(0, bytes.size() / 2));
  expect_vdb_refused(temp_dir() / "cut.vdb", "");
  write_bytes(temp_dir() / "text.vdb", "not a vdb file at all");
  expect_vdb_refused(temp_dir() / "text.vdb", "not a .vdb file (no VDB magic number)");
  // A metadata value claiming 2 GiB: OpenVDB would allocate and zero it.
  std::string huge = bytes;
  const uint32_t size = 0x7fffffff;
  std::memcpy(&huge[at - 4], &size, 4);
  write_bytes(temp_dir() / "huge_meta.vdb", huge);
  expect_vdb_refused(temp_dir() / "huge_meta.vdb", "grid 0's metadata entry 0 runs past its end");
  // A delayed-load entry claiming 2^31 leaf nodes: OpenVDB would allocate
  // and zero 9 bytes for each (a timeout of the vdb fuzz target).
  std::string leaves = bytes;
  const size_t delayed = leaves.find("__delayedload");
  ASSERT_NE(delayed, std::string::npos);
  const uint32_t many = 0x80000000u;
  std::memcpy(&leaves[delayed + 13 + 4], &many, 4);  // after the type name and the value's size
  write_bytes(temp_dir() / "leaves.vdb", leaves);
  expect_vdb_refused(temp_dir() / "leaves.vdb",
                     "grid 0's metadata entry 5 (delayed-load) claims 2147483648 leaf nodes, more than a file of");
  // A fixed-size value whose type says 16 bytes where the file stores 12:
  // OpenVDB would read 16 and lose its place in the stream.
  std::string vec4 = bytes;
  const size_t vec3 = vec4.find("vec3i");
  ASSERT_NE(vec3, std::string::npos);
  vec4[vec3 + 3] = '4';
  write_bytes(temp_dir() / "vec4.vdb", vec4);
  expect_vdb_refused(temp_dir() / "vec4.vdb", "grid 0's metadata entry 2 (vec4i) states 12 bytes, not 16");
  // A root tile, inserted after the root's tile and child counts: OpenVDB's
  // RootNode::readTopology reads its "active" byte straight into a bool.
  auto with_root_tile = [&](char active) {
    std::string b = bytes;
    const std::string map = "UniformScaleTranslateMap", type = "Tree_float_5_4_3";
    const size_t m = b.find(map), d = b.find(type);
    if (m == std::string::npos || d == std::string::npos) return std::string();
    const size_t counts = m + map.size() + 6 * 24 + 4 + 4;  // the map, buffer count, background
    const uint32_t one = 1;
    std::memcpy(&b[counts], &one, 4);
    std::string tile(17, '\0');
    const int32_t origin[3] = {8 * 4096, 0, -4096};
    std::memcpy(&tile[0], origin, 12);
    std::memcpy(&tile[12], &b[counts - 4], 4);  // the background
    tile[16] = active;
    b.insert(counts + 8, tile);
    // The grid's block and end positions, after its type and empty parent.
    int64_t p[3];
    std::memcpy(p, &b[d + type.size() + 4], 24);
    p[1] += 17, p[2] += 17;
    std::memcpy(&b[d + type.size() + 4], p, 24);
    return b;
  };
  const std::string inactive = with_root_tile(0);
  ASSERT_FALSE(inactive.empty());
  write_bytes(temp_dir() / "tile0.vdb", inactive);
  EXPECT_NO_THROW(voxelizer::load_vdb((temp_dir() / "tile0.vdb").string()));
  write_bytes(temp_dir() / "tile1.vdb", with_root_tile(1));
  expect_vdb_refused(temp_dir() / "tile1.vdb", "active voxels, more than the limit of 1e9");
  write_bytes(temp_dir() / "tile2.vdb", with_root_tile(2));
  expect_vdb_refused(temp_dir() / "tile2.vdb", "grid 0's root tile 0 has active flag 2 (0 or 1 expected)");
  fs::remove(temp_dir() / "zero.vdb");
  fs::create_symlink("/dev/zero", temp_dir() / "zero.vdb");
  expect_vdb_refused(temp_dir() / "zero.vdb", "character device");
}

}  // namespace
