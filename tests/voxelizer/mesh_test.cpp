// Meshes through OpenMesh and OpenVDB: formats, vertex colours, distances,
// and clear errors for files that are not usable meshes.
#include "svo/voxelizer/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <sstream>

#include "grid_mesh.h"
#include "lattice_points.h"
#include "svo/octree/sampler.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/winding.h"
#include "temp_dir.h"

namespace {
using namespace svo;
namespace fs = std::filesystem;

// This process's scratch directory, removed when the process exits.
fs::path temp_dir() {
  static const svo::testing::TempDir dir;
  return dir.path();
}

// A cube [-0.5, 0.5]^3 as 12 triangles, outward-facing.
const float kCorners[8][3] = {{-.5f, -.5f, -.5f}, {.5f, -.5f, -.5f}, {.5f, .5f, -.5f}, {-.5f, .5f, -.5f},
                              {-.5f, -.5f, .5f},  {.5f, -.5f, .5f},  {.5f, .5f, .5f},  {-.5f, .5f, .5f}};
const int kTriangles[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                               {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

std::string write_file(const std::string& name, const std::string& text) {
  fs::path p = temp_dir() / name;
  std::ofstream(p) << text;
  return p.string();
}

// The cube as OFF text; the triangles for which `against(f)` holds wound
// the other way (clockwise seen from outside).
std::string cube_off(const std::function<bool(int)>& against = [](int) { return false; }) {
  std::string s = "OFF\n8 12 0\n";
  for (auto& c : kCorners) s += std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (int f = 0; f < 12; ++f) {
    const int* t = kTriangles[f];
    const int b = against(f) ? t[2] : t[1], c = against(f) ? t[1] : t[2];
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
  }
  return s;
}

// Vertex colours: red on the bottom face (z = -0.5), blue on top.
std::string cube_ply() {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nelement face 12\n"
      "property list uchar int vertex_indices\nend_header\n";
  for (auto& c : kCorners) {
    s += std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) +
         (c[2] < 0 ? " 255 0 0\n" : " 0 0 255\n");
  }
  for (auto& t : kTriangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  return s;
}

std::string cube_obj() {
  std::string s;
  for (auto& c : kCorners)
    s += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (auto& t : kTriangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  return s;
}

std::string cube_stl() {
  std::string s = "solid cube\n";
  for (auto& t : kTriangles) {
    glm::vec3 a(kCorners[t[0]][0], kCorners[t[0]][1], kCorners[t[0]][2]);
    glm::vec3 b(kCorners[t[1]][0], kCorners[t[1]][1], kCorners[t[1]][2]);
    glm::vec3 c(kCorners[t[2]][0], kCorners[t[2]][1], kCorners[t[2]][2]);
    glm::vec3 n = glm::normalize(glm::cross(b - a, c - a));
    s += "facet normal " + std::to_string(n.x) + " " + std::to_string(n.y) + " " + std::to_string(n.z) +
         "\nouter loop\n";
    for (glm::vec3 v : {a, b, c})
      s += "vertex " + std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid cube\n";
}

// Distances at lattice points near the faces of the cube, level by level.
void expect_cube_distances(const octree::Octree& tree) {
  int checked = 0;
  for (uint32_t d = 0; d < tree.depth_count; ++d) {
    float s = tree.voxel_size(d);
    for (const auto& [index, p] : test::lattice_points(tree, d)) {
      // Near the top face, away from edges: the distance is p.z - 0.5.
      if (std::abs(p.x) > 0.3f || std::abs(p.y) > 0.3f || std::abs(p.z - 0.5f) > 0.45f * s) continue;
      auto v = octree::lattice_voxel(tree, d, index);
      ASSERT_TRUE(v.has_value());
      EXPECT_NEAR(v->hbar, p.z - 0.5f, 1e-3f * s + 1e-5f) << "depth " << d;
      EXPECT_GT(v->nbar.z, 0.999f) << "depth " << d;
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
}

TEST(Mesh, EveryFormatGivesTheSameCube) {
  for (auto [name, text] : {std::pair{"cube.off", cube_off()}, std::pair{"cube.obj", cube_obj()},
                            std::pair{"cube.ply", cube_ply()}, std::pair{"cube.stl", cube_stl()}}) {
    SCOPED_TRACE(name);
    auto mesh = voxelizer::load_mesh(write_file(name, text));
    EXPECT_NEAR(mesh->surface_area(), 6.0, 1e-4);
    voxelizer::VoxelizeOptions options;
    options.resolution = 64;
    octree::Octree tree = voxelizer::voxelize(*mesh, options);
    expect_cube_distances(tree);
  }
}

// A cube whose faces are all wound clockwise (inside out, as libcgal-demo's
// tetrahedron, beam and ellipsoid are): the same distances and outward
// normals. Its normals pointed inwards, and it rendered dark.
TEST(Mesh, InsideOutFacesGiveOutwardNormals) {
  const std::string s = cube_off([](int) { return true; });
  auto mesh = voxelizer::load_mesh(write_file("inside_out.off", s));
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(*mesh, options);
  expect_cube_distances(tree);
}

// A cube five of whose faces are wound against their neighbours (as in
// libcgal-demo's cube-shuffled.off, which drew those triangles dark): turned
// to agree, so the distances and outward normals are the cube's, and the
// warning counts them.
TEST(Mesh, FacesWoundAgainstTheirNeighboursAreTurned) {
  const std::string s = cube_off([](int f) { return f % 5 == 1 || f == 4; });  // faces 1, 4, 6, 11
  std::string warning;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& w) { warning += w + "\n"; };
  auto mesh = voxelizer::mesh_source(voxelizer::read_mesh(write_file("shuffled.off", s), options));
  EXPECT_NE(warning.find("4 of its 12 faces were wound against the others or inside out: turned"), std::string::npos)
      << warning;
  voxelizer::VoxelizeOptions vo;
  vo.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(*mesh, vo);
  expect_cube_distances(tree);
}

TEST(Mesh, VertexColoursReachTheVoxels) {
  auto mesh = voxelizer::load_mesh(write_file("colours.ply", cube_ply()));
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(*mesh, options);
  ASSERT_GE(tree.channel_index(octree::Channel::Colour), 0);
  const uint32_t D = tree.depth_count - 1;
  int top = 0, bottom = 0;
  for (const auto& [index, p] : test::lattice_points(tree, D, glm::ivec3(4, 4, 1))) {
    if (std::abs(p.x) > 0.4f || std::abs(p.y) > 0.4f) continue;
    auto v = octree::lattice_voxel(tree, D, index);
    if (!v || std::abs(v->hbar) > 0.5f * tree.voxel_size(D)) continue;
    if (std::abs(p.z - 0.5f) < 0.02f) {
      EXPECT_NEAR(v->abar.b, 1.0f, 0.01f);
      EXPECT_NEAR(v->abar.r, 0.0f, 0.01f);
      ++top;
    }
    if (std::abs(p.z + 0.5f) < 0.02f) {
      EXPECT_NEAR(v->abar.r, 1.0f, 0.01f);
      EXPECT_NEAR(v->abar.b, 0.0f, 0.01f);
      ++bottom;
    }
  }
  EXPECT_GT(top, 10);
  EXPECT_GT(bottom, 10);
}

void expect_error(const std::string& path, const std::string& fragment) {
  try {
    voxelizer::load_mesh(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const std::runtime_error& e) {
    std::string m = e.what();
    EXPECT_NE(m.find(path), std::string::npos) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
  }
}

TEST(Mesh, BadFilesAreOneLineErrorsNamingTheFile) {
  expect_error((temp_dir() / "missing.obj").string(), "no such file");
  expect_error(write_file("empty.off", "OFF\n0 0 0\n"), "no faces");
  expect_error(write_file("garbage.obj", "this is not a mesh\n"), "");
  expect_error(write_file("unknown.xyz", cube_obj()), "");
  // OpenMesh drops a vertex it cannot parse (nan) with the faces using it;
  // the OFF file is then read by svo's own reader, which names the vertex.
  expect_error(write_file("nan.off", "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
               "vertex 0 has a non-finite coordinate");
  expect_error(write_file("flat.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n"), "non-zero area");
}

}  // namespace

#include <OpenImageIO/imageio.h>

namespace {

// A unit square in z = 0 (two triangles, both sides closed by a thin box is
// not needed: the level set of an open sheet is still a band around it) with
// UVs spanning [0, 1]^2 and a texture red for u < 0.5, green beyond.
std::string textured_square(const std::string& texture_name, bool write_texture) {
  fs::path dir = temp_dir();
  if (write_texture) {
    const int w = 64, h = 64;
    std::vector<unsigned char> pixels(size_t(w * h * 3));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        unsigned char* p = &pixels[size_t((y * w + x) * 3)];
        p[0] = x < w / 2 ? 255 : 0, p[1] = x < w / 2 ? 0 : 255, p[2] = 0;
      }
    auto out = OIIO::ImageOutput::create((dir / texture_name).string());
    EXPECT_TRUE(out);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    EXPECT_TRUE(out->open((dir / texture_name).string(), spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    out->close();
  }
  std::ofstream(dir / "square.mtl") << "newmtl checker\nKd 1 1 1\nmap_Kd " << texture_name << "\n";
  std::string obj =
      "mtllib square.mtl\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl checker\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  return write_file("square.obj", obj);
}

TEST(Mesh, TextureColoursThroughUVs) {
  auto mesh = voxelizer::load_mesh(textured_square("checker.png", true));
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(*mesh, options);
  ASSERT_GE(tree.channel_index(octree::Channel::Colour), 0);
  const uint32_t D = tree.depth_count - 1;
  int red = 0, green = 0;
  for (const auto& [index, p] : test::lattice_points(tree, D)) {
    if (std::abs(p.z) > 0.4f * tree.voxel_size(D) || std::abs(p.y) > 0.4f || std::abs(p.x) > 0.45f ||
        std::abs(p.x) < 0.05f) {
      continue;
    }
    auto v = octree::lattice_voxel(tree, D, index);
    ASSERT_TRUE(v.has_value());
    glm::vec3 expected = p.x < 0 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    EXPECT_LT(glm::length(v->abar - expected), 0.02f) << p.x << " " << p.y;
    (p.x < 0 ? red : green)++;
  }
  EXPECT_GT(red, 100);
  EXPECT_GT(green, 100);
}

TEST(Mesh, MissingTextureIsAnErrorNamingIt) {
  std::string obj = textured_square("absent.png", false);
  try {
    voxelizer::load_mesh(obj);
    ADD_FAILURE() << "a mesh whose texture is missing was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(obj), std::string::npos) << e.what();
  }
}

}  // namespace

namespace {

// The material's roughness becomes the micro-BRDF slope variance sigma_rho^2.
TEST(Mesh, MaterialRoughnessFromTheObjMaterial) {
  auto with_material = [](const std::string& name, const std::string& mtl) {
    fs::path dir = temp_dir();
    std::ofstream(dir / (name + ".mtl")) << mtl;
    return write_file(name + ".obj", "mtllib " + name + ".mtl\nusemtl m\n" + cube_obj());
  };
  EXPECT_NEAR(voxelizer::load_mesh(with_material("phong", "newmtl m\nNs 98\n"))->sigma_rho2(), 0.01f, 1e-6f);
  EXPECT_NEAR(voxelizer::load_mesh(with_material("pbr", "newmtl m\nNs 10\nPr 0.5\n"))->sigma_rho2(), 0.125f, 1e-6f);
  EXPECT_NEAR(voxelizer::load_mesh(with_material("two", "newmtl a\nPr 0.2\nnewmtl b\nPr 0.4\n"))->sigma_rho2(),
              (0.02f + 0.08f) / 2, 1e-6f);
  voxelizer::MeshOptions given;
  given.sigma_rho = 0.3f;
  EXPECT_NEAR(voxelizer::load_mesh(with_material("given", "newmtl m\nNs 98\n"), given)->sigma_rho2(), 0.09f, 1e-6f);
  EXPECT_NEAR(voxelizer::load_mesh(write_file("plain.obj", cube_obj()))->sigma_rho2(), 0.01f, 1e-6f);
}

}  // namespace

namespace {

// A scene file places meshes and gives each face its object's material.
TEST(SceneFile, PlacesMeshesAndGivesEachFaceItsMaterial) {
  const std::string cube = write_file("scene_cube.off", cube_off());
  const std::string scene = write_file("scene.json", R"({
    "materials": {"b-gold": {"brdf": "ggx", "f0": [1, 0.8, 0.3]}, "a-merl": {"brdf": "merl", "file": "x.binary"}},
    "objects": [
      {"mesh": "scene_cube.off", "material": "b-gold", "scale": [2, 1, 1], "translate": [10, 0, 0]},
      {"mesh": ")" + cube + R"(", "material": "a-merl", "rotate": [0, 90, 0], "colour": [0.2, 0.4, 0.6]}
    ]})");
  const voxelizer::TriangleMesh mesh = voxelizer::read_scene_file(scene);
  ASSERT_EQ(mesh.triangles.size(), 24u);
  ASSERT_EQ(mesh.face_material.size(), 24u);
  // Materials in the order of their names: a-merl 0, b-gold 1.
  ASSERT_EQ(mesh.materials.size(), 2u);
  EXPECT_NE(mesh.materials[0].find((temp_dir() / "x.binary").string()), std::string::npos) << mesh.materials[0];
  EXPECT_NE(mesh.materials[1].find("ggx"), std::string::npos);
  for (size_t f = 0; f < 24; ++f) {
    EXPECT_EQ(mesh.face_material[f], f < 12 ? 1u : 0u);
    // Faces still face outwards from their object's centre.
    const glm::ivec3 t = mesh.triangles[f];
    const glm::dvec3 centre = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0;
    const glm::dvec3 object = f < 12 ? glm::dvec3(10, 0, 0) : glm::dvec3(0);
    EXPECT_GT(glm::dot(glm::dvec3(mesh.face_normals[f]), centre - object), 0) << f;
  }
  EXPECT_NEAR(mesh.bounds.lo.x, -0.5, 1e-6);
  EXPECT_NEAR(mesh.bounds.hi.x, 11.0, 1e-6);
  EXPECT_NEAR(mesh.area, 10.0 + 6.0, 1e-9);  // the stretched cube 2 x 1 x 1, then the unit cube
  EXPECT_NEAR(mesh.colours.back().z, 0.6f, 1e-6f);
  EXPECT_FALSE(mesh.two_sided);
  // A cube without its top beside the closed one: the scene is drawn two-sided.
  std::string open = "OFF\n8 10 0\n";
  for (auto& c : kCorners)
    open += std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  for (int t = 0; t < 12; ++t) {
    if (t == 2 || t == 3) continue;  // the z = 0.5 face
    open += "3 " + std::to_string(kTriangles[t][0]) + " " + std::to_string(kTriangles[t][1]) + " " +
            std::to_string(kTriangles[t][2]) + "\n";
  }
  write_file("scene_open.off", open);
  const std::string mixed = write_file("scene_mixed.json", R"({"materials": {"m": {"brdf": "lambert"}},
    "objects": [{"mesh": "scene_cube.off", "material": "m"},
                {"mesh": "scene_open.off", "material": "m", "translate": [3, 0, 0]}]})");
  EXPECT_TRUE(voxelizer::read_scene_file(mixed).two_sided);
  // A voxelized scene carries the materials and which one each voxel shows.
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  const octree::Octree tree = voxelizer::voxelize(*voxelizer::mesh_source(mesh), options);
  EXPECT_EQ(tree.materials, mesh.materials);
  EXPECT_GE(tree.channel_index(octree::Channel::Material), 0);
}

TEST(SceneFile, MistakesAreOneLineErrorsNamingTheKey) {
  const std::string cube = write_file("scene_cube.off", cube_off());
  auto expect_error = [](const std::string& json, const std::string& what) {
    const std::string path = write_file("bad_scene.json", json);
    try {
      voxelizer::read_scene_file(path);
      ADD_FAILURE() << "accepted " << json;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("scene file " + path, 0), 0u) << message;
      EXPECT_NE(message.find(what), std::string::npos) << "expected '" << what << "' in: " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  };
  expect_error(R"({"objects": [{"mesh": "scene_cube.off"}], "lights": 1})", "unknown key 'lights'");
  expect_error(R"({"objects": []})", "key 'objects': expected a non-empty array");
  expect_error(R"({"objects": [{"mesh": "scene_cube.off", "material": "x"}]})", "no material named 'x'");
  expect_error(R"({"materials": {"a": {"brdf": "lambert"}, "b": {"brdf": "ggx"}},
                   "objects": [{"mesh": "scene_cube.off"}]})",
               "object 0: key 'material': missing (the scene has 2 materials and");
  expect_error(R"({"objects": [{"mesh": "scene_cube.off", "scale": 0}]})", "key 'scale': must be > 0");
  expect_error(R"({"objects": [{"mesh": "scene_cube.off", "rotate": [1, 2]}]})", "key 'rotate': expected [x, y, z]");
  expect_error(R"({"objects": [{"mesh": "scene_cube.off", "spin": 2}]})", "unknown key 'spin'");
  expect_error(R"({"materials": {"a": "missing.json"}, "objects": [{"mesh": "scene_cube.off"}]})",
               "material 'a': cannot open");
  expect_error(R"({"materials": {"a": "/dev/zero"}, "objects": [{"mesh": "scene_cube.off"}]})", "not a regular file");
  expect_error("{\"objects\": [", "not JSON");
  // Text from the file stays on one line in messages (found by fuzzing).
  expect_error(R"({"objects": [{"mesh": "scene_cube.off"}], "a\nb": 1})", "unknown key 'a\\x0Ab'");
  expect_error(R"({"objects": [{"mesh": "a\nb.off"}]})",
               "key 'mesh': the path 'a\\x0Ab.off' holds a control character");
  // A device or FIFO named as a mesh is refused before it is read (it would hang).
  try {
    voxelizer::read_scene_file(write_file("dev_scene.json", R"({"objects": [{"mesh": "/dev/zero"}]})"));
    ADD_FAILURE() << "read /dev/zero as a mesh";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "/dev/zero: not a regular file");
  }
}

}  // namespace

namespace {

// OBJ usemtl groups become materials (from their MTL entries), a face
// keeping its group's, polygons split into triangles in file order.
TEST(Mesh, UsemtlGroupsBecomeMaterials) {
  write_file("groups.mtl",
             "newmtl shiny\nKd 0.5 0.25 1\nKs 0.9 0.9 0.9\nNs 250\n"
             "newmtl rough\nKd 0.2 0.2 0.2\nPr 0.4\n");
  std::string obj = "mtllib groups.mtl\n";
  for (auto& c : kCorners)
    obj += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) + "\n";
  // The first face before any usemtl, then four quads (two triangles each) of shiny, then the rest.
  obj += "f 1 3 2\nusemtl shiny\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nusemtl rough\nf 1 4 3\nf 1 5 8\nf 1 8 4\n";
  const voxelizer::TriangleMesh mesh = voxelizer::read_mesh(write_file("groups.obj", obj));
  ASSERT_EQ(mesh.triangles.size(), 12u);
  ASSERT_EQ(mesh.materials.size(), 3u);
  EXPECT_NE(mesh.materials[0].find("\"default\""), std::string::npos) << mesh.materials[0];
  EXPECT_NE(mesh.materials[1].find("\"phong\""), std::string::npos) << mesh.materials[1];
  EXPECT_NE(mesh.materials[1].find("250"), std::string::npos) << mesh.materials[1];
  EXPECT_NE(mesh.materials[2].find("\"ggx\""), std::string::npos) << mesh.materials[2];
  const std::vector<uint32_t> expected{0, 1, 1, 1, 1, 1, 1, 1, 1, 2, 2, 2};
  EXPECT_EQ(mesh.face_material, expected);
  // A scene file object without a material keeps the mesh's own.
  write_file("scene_cube.off", cube_off());
  const voxelizer::TriangleMesh scene =
      voxelizer::read_scene_file(write_file("groups_scene.json", R"({"materials": {"a": {"brdf": "lambert"}},
        "objects": [{"mesh": "scene_cube.off", "material": "a"}, {"mesh": "groups.obj", "translate": [3, 0, 0]}]})"));
  ASSERT_EQ(scene.materials.size(), 4u);
  ASSERT_EQ(scene.face_material.size(), 24u);
  EXPECT_EQ(scene.face_material[0], 0u);
  EXPECT_EQ(scene.face_material[12], 1u);
  EXPECT_EQ(scene.face_material[23], 3u);
}

// mtllib naming something that is not a regular file is refused before
// anything opens it (a FIFO or /dev/zero would hang or eat memory; issue
// 22); one that does not exist is a warning, its materials the defaults.
TEST(Mesh, MtllibNamingADeviceIsRefusedAMissingOneWarned) {
  const std::string faces = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n";
  const std::string devzero = write_file("devzero.obj", "mtllib /dev/zero\n" + faces);
  expect_error(devzero, "mtllib /dev/zero: is a character device, expected an MTL material file");
  std::vector<std::string> warnings;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& line) { warnings.push_back(line); };
  const voxelizer::TriangleMesh mesh =
      voxelizer::read_mesh(write_file("nomtl.obj", "mtllib none.mtl\n" + faces), options);
  ASSERT_EQ(mesh.materials.size(), 2u);
  EXPECT_NE(mesh.materials[0].find("lambert"), std::string::npos);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings[0].find("none.mtl does not exist: its materials are not used"), std::string::npos) << warnings[0];
}

}  // namespace

namespace svo {
namespace {

// libcgal-demo's corner_poly.off: a cube with a corner notched out, whose
// top and bottom are L-shaped hexagons. The fan from their first corner
// (8: (0, 1)) covers the notch with a triangle wound backwards.
const char* const kCornerPolyOff =
    "OFF\n12 8 0\n0 2 1\n2 2 1\n2 0 1\n0 2 -1\n2 2 -1\n2 0 -1\n1 1 1\n1 1 -1\n0 1 1\n0 1 -1\n1 0 1\n1 0 -1\n"
    "4  3 0 1 4\n6  8 6 10 2 1 0\n4  9 8 0 3\n6  9 3 4 5 11 7\n4  5 4 1 2\n4  9 7 6 8\n4  11 5 2 10\n"
    "4  11 10 6 7\n";

double total_area(const voxelizer::TriangleMesh& mesh) {
  double area = 0;
  for (const glm::ivec3& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positions[size_t(t.x)], b = mesh.positions[size_t(t.y)], c = mesh.positions[size_t(t.z)];
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

// The notched cube's surface, [0, 2]^2 x [-1, 1] less [0, 1]^2 x [-1, 1]:
// two L-shapes of 3, the walls x = 2 and y = 2 of 4, the walls x = 0 and
// y = 0 and the notch's two walls of 2.
double notched_cube_area() { return 2 * 3 + 2 * 4 + 4 * 2; }

TEST(Polygon, ConvexPolygonsKeepTheirFanNonConvexOnesAreEarClipped) {
  const std::vector<glm::dvec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_EQ(voxelizer::triangulate_polygon(square), (std::vector<glm::ivec3>{{0, 1, 2}, {0, 2, 3}}));
  // The L of corner_poly.off's top, corners 8 6 10 2 1 0, in any orientation.
  std::vector<glm::dvec3> l{{0, 1, 1}, {1, 1, 1}, {1, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};
  for (int turn = 0; turn < 2; ++turn) {
    const std::vector<glm::ivec3> t = voxelizer::triangulate_polygon(l);
    ASSERT_EQ(t.size(), 4u);
    double area = 0;
    glm::dvec3 normal(0);
    for (const glm::ivec3& i : t) {
      const glm::dvec3 n = glm::cross(l[size_t(i.y)] - l[size_t(i.x)], l[size_t(i.z)] - l[size_t(i.x)]);
      normal += n;
      area += 0.5 * glm::length(n);
    }
    EXPECT_NEAR(area, 3.0, 1e-12) << "the triangles cover the L once";
    EXPECT_NEAR(0.5 * glm::length(normal), 3.0, 1e-12) << "all wound as the polygon";
    // The same L in the plane x = 0, wound the other way.
    for (glm::dvec3& p : l) p = glm::dvec3(0, p.y, 2 - p.x);
    std::reverse(l.begin(), l.end());
  }
  // Fewer than four corners: as given.
  EXPECT_EQ(voxelizer::triangulate_polygon(std::vector<glm::dvec3>(square.begin(), square.begin() + 3)),
            (std::vector<glm::ivec3>{{0, 1, 2}}));
}

// kCornerPolyOff as a PLY file of `format` (ascii, binary_little_endian or
// binary_big_endian): float positions, faces as a uchar count and int corners.
std::string corner_poly_ply(const std::string& format) {
  std::istringstream off(kCornerPolyOff);
  std::string line;
  std::getline(off, line);
  std::getline(off, line);
  std::vector<glm::vec3> vertices;
  for (int v = 0; v < 12 && std::getline(off, line); ++v) {
    std::istringstream xyz(line);
    glm::vec3 p;
    xyz >> p.x >> p.y >> p.z;
    vertices.push_back(p);
  }
  std::vector<std::vector<int>> faces;
  while (std::getline(off, line)) {
    std::istringstream words(line);
    int k;
    if (!(words >> k)) continue;
    std::vector<int> face(static_cast<size_t>(k));
    for (int& c : face) words >> c;
    faces.push_back(face);
  }
  std::string ply = "ply\nformat " + format + " 1.0\nelement vertex 12\nproperty float x\nproperty float y\n" +
                    "property float z\nelement face 8\nproperty list uchar int vertex_indices\nend_header\n";
  const bool big = format == "binary_big_endian";
  auto bytes = [&](const void* p, size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (big) std::reverse(b.begin(), b.end());
    ply += b;
  };
  for (const glm::vec3& p : vertices) {
    if (format == "ascii") {
      ply += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    } else {
      for (int k = 0; k < 3; ++k) bytes(&p[k], 4);
    }
  }
  for (const std::vector<int>& face : faces) {
    if (format == "ascii") {
      ply += std::to_string(face.size());
      for (int c : face) ply.append(" ").append(std::to_string(c));
      ply += "\n";
    } else {
      ply += char(face.size());
      for (int c : face) bytes(&c, 4);
    }
  }
  return ply;
}

TEST(Mesh, NonConvexPolygonsKeepTheirShapeInEveryReader) {
  // OpenMesh's OFF reader; svo's own (a comment line before the keyword);
  // OpenMesh's OBJ reader (1-based corners, texture coordinates per corner);
  // OpenMesh's PLY reader, ASCII and binary in both byte orders.
  textured_square("checker.png", true);  // square.mtl, whose material "checker" is textured
  std::string obj = "# the notched cube\nmtllib square.mtl\nusemtl checker\n";
  std::istringstream off(kCornerPolyOff);
  std::string line;
  std::getline(off, line);
  std::getline(off, line);
  for (int v = 0; v < 12 && std::getline(off, line); ++v) {
    obj += "v " + line + "\n";
    std::istringstream xyz(line);
    double x, y, z;
    xyz >> x >> y >> z;
    obj += "vt " + std::to_string(x / 2) + " " + std::to_string(y / 2) + "\n";
  }
  while (std::getline(off, line)) {
    std::istringstream words(line);
    int k;
    if (!(words >> k)) continue;
    obj += "f";
    for (int i = 0, c; i < k && words >> c; ++i) {
      const std::string corner = std::to_string(c + 1);
      obj.append(" ").append(corner).append("/").append(corner);
    }
    obj += "\n";
  }
  const std::vector<std::string> files{write_file("corner_poly.off", kCornerPolyOff),
                                       write_file("corner_poly_own.off", std::string("# own\n") + kCornerPolyOff),
                                       write_file("corner_poly.obj", obj),
                                       write_file("corner_poly.ply", corner_poly_ply("ascii")),
                                       write_file("corner_poly_le.ply", corner_poly_ply("binary_little_endian")),
                                       write_file("corner_poly_be.ply", corner_poly_ply("binary_big_endian"))};
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    std::vector<std::string> warnings;
    voxelizer::MeshOptions options;
    options.warning = [&](const std::string& w) { warnings.push_back(w); };
    const voxelizer::TriangleMesh mesh = voxelizer::read_mesh(file, options);
    EXPECT_EQ(mesh.triangles.size(), 2u * 4u + 6u * 2u);
    EXPECT_NEAR(total_area(mesh), notched_cube_area(), 1e-9);
    EXPECT_EQ(mesh.open_edges, 0u);
    EXPECT_EQ(mesh.nonmanifold_edges, 0u);
    bool said = false;
    for (const std::string& w : warnings) said = said || w.find("2 non-convex polygons split") != std::string::npos;
    EXPECT_TRUE(said);
    if (file.ends_with(".obj")) {
      // Each corner keeps its own texture coordinates.
      ASSERT_EQ(mesh.face_uv.size(), mesh.triangles.size());
      ASSERT_EQ(std::count(mesh.face_texture.begin(), mesh.face_texture.end(), 0),
                std::ptrdiff_t(mesh.triangles.size()));
      for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int c = 0; c < 3; ++c) {
          const glm::dvec3 p = mesh.positions[size_t(mesh.triangles[t][c])];
          EXPECT_NEAR(mesh.face_uv[t][size_t(c)].x, p.x / 2, 1e-5);
          EXPECT_NEAR(mesh.face_uv[t][size_t(c)].y, p.y / 2, 1e-5);
        }
      }
    }
  }
}

// The commonest textured OBJ, a quad with a texture coordinate per corner,
// was refused: OpenMesh fans the quad and leaves its triangles' texture
// coordinates undefined ("face 0 has a non-finite texture coordinate").
TEST(Mesh, TexturedQuadsKeepTheirCornersCoordinates) {
  textured_square("checker.png", true);
  const std::string file = write_file("quad.obj",
                                      "mtllib square.mtl\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl checker\nf 1/1 2/2 3/3 4/4\n");
  const voxelizer::TriangleMesh mesh = voxelizer::read_mesh(file);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  for (size_t t = 0; t < 2; ++t) {
    EXPECT_EQ(mesh.face_texture[t], 0);
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3 p = mesh.positions[size_t(mesh.triangles[t][c])];
      EXPECT_EQ(mesh.face_uv[t][size_t(c)], glm::vec2(float(p.x + 0.5), float(p.y + 0.5)));
    }
  }
}

// Stored finest samples within 1.5 voxels of the surface (and more than
// 0.05 from it) of `mesh` voxelized at 64^3, checked against the side its
// winding number gives: how many were checked, how many were on the wrong
// side (the first five reported).
std::pair<int, int> samples_against_winding(voxelizer::TriangleMesh mesh) {
  const voxelizer::WindingNumber winding(mesh.positions, mesh.triangles);
  const octree::Octree tree = test::voxelize_mesh(std::move(mesh), 64);
  const uint32_t D = tree.depth_count - 1;
  const float h = tree.voxel_size(D);
  int checked = 0, wrong = 0;
  for (const auto& point : test::lattice_points(tree, D)) {
    const octree::LatticeSource at = octree::lattice_source(tree, D, point.index);
    if (at.brick == octree::kNone || at.axes != 0) continue;  // stored samples only
    const float hbar = octree::lattice_voxel(tree, D, point.index)->hbar;
    if (!(std::abs(hbar) > 0.05f * h && std::abs(hbar) < 1.5f * h)) continue;
    ++checked;
    const double w = winding(glm::dvec3(point.position));
    if ((hbar < 0) != (w > 0.5) && ++wrong <= 5) {
      ADD_FAILURE() << "lattice point " << point.index.x << "," << point.index.y << "," << point.index.z << " at "
                    << point.position.x << "," << point.position.y << "," << point.position.z << ": distance "
                    << hbar / h << " voxels, winding number " << w;
    }
  }
  return {checked, wrong};
}

// OpenVDB's sign (its flood fill) put lattice points up to half a voxel
// outside fandisk (a CAD part) inside it: 53 at 64^3, 297 at 256^3, in
// rows beside its edges. The voxelizer checks it against the side of the
// closest feature and, where they disagree, takes the winding number's.
TEST(Mesh, EveryFinestSampleIsOnTheWindingNumbersSide) {
  svo::testing::TempDir dir;
  const auto [checked, wrong] =
      samples_against_winding(voxelizer::read_mesh(svo::testing::extract_cgal_mesh(dir, "fandisk.off")));
  std::printf("fandisk at 64^3: %d stored samples within 1.5 voxels checked, %d on the wrong side\n", checked, wrong);
  EXPECT_GT(checked, 5000);
  EXPECT_EQ(wrong, 0);
}

// Two closed boxes that overlap: inside one, next to the other's faces, the
// closest feature says "outside"; the winding number (2 there) keeps it in.
// (Corners in eighths, so that each box's faces meet exactly: closed.)
TEST(Mesh, OverlappingSolidsKeepTheirInside) {
  voxelizer::MeshArrays boxes;
  test::add_box(boxes, glm::dvec3(-0.5, -0.5, -0.375), glm::dvec3(0.25, 0.125, 0.25), 2);
  test::add_box(boxes, glm::dvec3(-0.125, -0.25, -0.125), glm::dvec3(0.5, 0.5, 0.375), 2);
  voxelizer::TriangleMesh mesh = voxelizer::make_triangle_mesh("boxes", std::move(boxes));
  ASSERT_FALSE(mesh.two_sided) << mesh.surface;
  const auto [checked, wrong] = samples_against_winding(std::move(mesh));
  std::printf("two overlapping boxes at 64^3: %d stored samples checked, %d on the wrong side\n", checked, wrong);
  EXPECT_GT(checked, 5000);
  EXPECT_EQ(wrong, 0);
}

}  // namespace
}  // namespace svo
