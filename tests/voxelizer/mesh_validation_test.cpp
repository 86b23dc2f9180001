// Untrusted meshes (issue 7): make_triangle_mesh's refusals and repairs on
// parsed arrays, and the same cases through files (OpenMesh first).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <limits>

#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"

namespace {

using namespace svo;
namespace fs = std::filesystem;

const double kCorners[8][3] = {{-.5, -.5, -.5}, {.5, -.5, -.5}, {.5, .5, -.5}, {-.5, .5, -.5},
                               {-.5, -.5, .5},  {.5, -.5, .5},  {.5, .5, .5},  {-.5, .5, .5}};
const int kTriangles[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                               {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

voxelizer::MeshArrays cube() {
  voxelizer::MeshArrays a;
  for (auto& c : kCorners) a.positions.emplace_back(c[0], c[1], c[2]);
  for (auto& t : kTriangles) a.triangles.emplace_back(t[0], t[1], t[2]);
  return a;
}

// The refusal of `a`: one line naming "in.obj" and containing `fragment`.
void expect_refused(voxelizer::MeshArrays a, const std::string& fragment) {
  try {
    voxelizer::make_triangle_mesh("in.obj", std::move(a));
    ADD_FAILURE() << "accepted; expected: " << fragment;
  } catch (const std::runtime_error& e) {
    std::string m = e.what();
    EXPECT_EQ(m.rfind("in.obj: ", 0), 0u) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(MeshValidation, TheClosedCubeIsAcceptedWithoutWarning) {
  std::vector<std::string> warnings;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& w) { warnings.push_back(w); };
  auto mesh = voxelizer::make_triangle_mesh("in.obj", cube(), options);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  EXPECT_EQ(mesh.open_edges, 0u);
  EXPECT_EQ(mesh.nonmanifold_edges, 0u);
  EXPECT_NEAR(mesh.area, 6.0, 1e-12);
  EXPECT_EQ(mesh.colours.size(), 8u);
  EXPECT_TRUE(warnings.empty());
}

TEST(MeshValidation, EmptyMeshesAreRefused) {
  expect_refused({}, "the mesh has no faces");
  auto a = cube();
  a.triangles.clear();
  expect_refused(a, "the mesh has no faces");
}

TEST(MeshValidation, NonFiniteAndHugeCoordinatesAreRefused) {
  for (double bad : {std::nan(""), double(INFINITY), -double(INFINITY)}) {
    auto a = cube();
    a.positions[5].y = bad;
    expect_refused(a, "vertex 5 has a non-finite coordinate");
  }
  auto a = cube();
  a.positions[2].z = 2e15;
  expect_refused(a, "vertex 2 has a coordinate beyond +-1e15");
  // Large but within the limit: accepted, with finite float bounds.
  auto big = cube();
  for (auto& p : big.positions) p *= 1e14;
  auto mesh = voxelizer::make_triangle_mesh("in.obj", big);
  EXPECT_TRUE(std::isfinite(mesh.bounds.hi.x) && mesh.bounds.hi.x > 1e13f);
}

TEST(MeshValidation, OutOfRangeIndicesAreRefused) {
  auto a = cube();
  a.triangles[7].y = 8;
  expect_refused(a, "face 7 refers to vertex 8, but the mesh has 8 vertices");
  a = cube();
  a.triangles[0].x = -1;
  expect_refused(a, "face 0 refers to vertex -1, but the mesh has 8 vertices");
  a = cube();
  a.face_texture.assign(12, -1);
  a.face_texture[3] = 0;  // no texture
  expect_refused(a, "face 3 refers to texture 0, but the mesh has 0 textures");
  a.face_texture[3] = -2;
  expect_refused(a, "face 3 refers to texture -2");
}

TEST(MeshValidation, CountsThatDisagreeAreRefused) {
  auto a = cube();
  a.colours.assign(7, glm::vec3(1));
  expect_refused(a, "7 vertex colours for 8 vertices");
  a = cube();
  a.face_uv.resize(11);
  expect_refused(a, "11 face texture coordinates for 12 triangles");
  a = cube();
  a.face_texture.assign(13, -1);
  expect_refused(a, "13 face texture indices for 12 triangles");
  a = cube();
  a.face_uv.resize(12);
  a.face_uv[4][1].x = std::nanf("");
  a.textures.push_back({1, 1, {glm::vec3(1)}});
  a.face_texture.assign(12, 0);
  expect_refused(a, "face 4 has a non-finite texture coordinate");
  a.face_texture[4] = -1;  // untextured: its coordinates are not used
  EXPECT_EQ(voxelizer::make_triangle_mesh("in.obj", a).face_uv[4][1].x, 0.0f);
  a = cube();
  a.textures.push_back({});
  expect_refused(a, "texture 0 has no texels");
}

TEST(MeshValidation, DegenerateTrianglesAreDroppedAndReported) {
  auto a = cube();
  a.triangles.emplace_back(0, 1, 1);  // repeated corner
  a.positions.emplace_back(0.0, -0.5, -0.5);
  a.triangles.emplace_back(0, 1, 8);  // collinear: 8 lies on edge 0-1
  std::vector<std::string> warnings;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& w) { warnings.push_back(w); };
  auto mesh = voxelizer::make_triangle_mesh("in.obj", a, options);
  EXPECT_EQ(mesh.degenerate, 2u);
  EXPECT_EQ(mesh.triangles.size(), 12u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "in.obj: 2 triangles of zero area dropped");
  // Only degenerate triangles, or all corners at one point (zero extent): refused.
  voxelizer::MeshArrays flat;
  flat.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  flat.triangles = {{0, 1, 2}};
  expect_refused(flat, "no triangle of non-zero area (1 degenerate)");
  voxelizer::MeshArrays point;
  point.positions.assign(3, glm::dvec3(4, 5, 6));
  point.triangles = {{0, 1, 2}};
  expect_refused(point, "no triangle of non-zero area");
}

TEST(MeshValidation, OpenAndNonManifoldSurfacesAreReported) {
  std::vector<std::string> warnings;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& w) { warnings.push_back(w); };
  // The cube without its top face (triangles 2 and 3): 4 open edges.
  auto open = cube();
  open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
  auto mesh = voxelizer::make_triangle_mesh("in.obj", open, options);
  EXPECT_EQ(mesh.open_edges, 4u);
  EXPECT_EQ(mesh.nonmanifold_edges, 0u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("in.obj: not a closed manifold surface (4 open edges, 0 non-manifold edges)"),
            std::string::npos)
      << warnings[0];
  // A fin on the cube's edge 0-1: that edge has three triangles.
  warnings.clear();
  auto fin = cube();
  fin.positions.emplace_back(0.0, -1.0, -1.0);
  fin.triangles.emplace_back(0, 1, 8);
  mesh = voxelizer::make_triangle_mesh("in.obj", fin, options);
  EXPECT_EQ(mesh.nonmanifold_edges, 1u);
  EXPECT_EQ(mesh.open_edges, 2u);  // the fin's own two outer edges
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("(2 open edges, 1 non-manifold edges)"), std::string::npos) << warnings[0];
}

// ---- Through files: OpenMesh's parsers first, then the checks above.

fs::path temp_dir() {
  fs::path dir = fs::temp_directory_path() / ("svo_mesh_validation_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string write_file(const std::string& name, const std::string& text) {
  fs::path p = temp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

void expect_file_refused(const std::string& path, const std::string& fragment) {
  try {
    voxelizer::read_mesh(path);
    ADD_FAILURE() << path << " was accepted; expected: " << fragment;
  } catch (const std::runtime_error& e) {
    std::string m = e.what();
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(MeshValidation, BadFilesAreOneLineErrors) {
  // A binary PLY carries an infinite coordinate as it is: our check refuses it.
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const float xyz[9] = {0, 0, 0, 1, INFINITY, 0, 0, 1, 0};
  ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  const uint8_t corners = 3;
  const int32_t face[3] = {0, 1, 2};
  ply.append(reinterpret_cast<const char*>(&corners), 1);
  ply.append(reinterpret_cast<const char*>(face), sizeof face);
  expect_file_refused(write_file("inf.ply", ply), "vertex 1 has a non-finite coordinate");
  // OpenMesh's text readers drop a vertex they cannot parse (inf, nan) with
  // its faces; an OFF file is then read by svo's own reader, which names it.
  expect_file_refused(write_file("inf.off", "OFF\n3 1 0\ninf 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                      "vertex 0 has a non-finite coordinate");
  // Headers that OpenMesh would trust: refused before it reads them.
  expect_file_refused(write_file("type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty floot x\nend_header\n"),
                      "PLY header line 4: expected 'property TYPE NAME'");
  expect_file_refused(
      write_file("count.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n"),
      "element vertex claims 4000000000 entries, more than the file's");
  expect_file_refused(write_file("list.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                 "end_header\n0 0 0\n1 0 0\n0 1 0\n300000 0 1 2\n"),
                      "PLY line 13: a list count '300000' is not an integer from 0 to 1000");
  expect_file_refused(write_file("count.off", "OFF\n900000000 1 0\n0 0 0\n"), "OFF header claims 900000000 vertices");
  expect_file_refused(write_file("negative.off", "OFF\n3 -5 0\n0 0 0\n"),
                      "OFF header: expected the vertex, face and edge counts as non-negative integers");
  expect_file_refused(write_file("binary.off", "OFF BINARY\n"), "binary OFF is not supported");
  expect_file_refused(write_file("degree.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4294967295 0 1 2\n"),
                      "OFF line 6: a face starts with its corner count, 1 to 1000");
  expect_file_refused(write_file("corner.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"),
                      "OFF line 6: corner '3' is not a vertex index");
  expect_file_refused(write_file("corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 /2 3\n"),
                      "OBJ line 4: face corner '/2' is not V, V/T, V//N or V/T/N");
  expect_file_refused(write_file("indented.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n  f /1 2 3\n"),
                      "OBJ line 4: face corner '/1' is not V, V/T, V//N or V/T/N");
  expect_file_refused(write_file("vc.obj", "vc 1 1 1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                      "OBJ line 1: 'vc' vertex colour lines are not supported");
  expect_file_refused(write_file("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
                      "OBJ line 4: a face needs 3 corners");
  expect_file_refused(write_file("huge.off", "OFF\n3 1 0\n1e20 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                      "vertex 0 has a coordinate beyond +-1e15");
  // An index past the vertices: OpenMesh refuses the face; no face is left.
  expect_file_refused(write_file("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), "");
  expect_file_refused(write_file("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "");
  expect_file_refused(write_file("point.obj", "v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n"), "non-zero area");
  expect_file_refused(write_file("empty.obj", ""), "");
}

std::string textured_square(const std::string& texture_name) {
  std::ofstream(temp_dir() / "sq.mtl") << "newmtl t\nKd 1 1 1\nmap_Kd " << texture_name << "\n";
  return write_file("sq.obj",
                    "mtllib sq.mtl\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl t\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
}

TEST(MeshValidation, BadTexturesAreOneLineErrorsNamingMeshAndTexture) {
  std::string obj = textured_square("absent.png");
  expect_file_refused(obj, "texture " + (temp_dir() / "absent.png").string() + " does not exist");
  write_file("garbage.png", "this is not a PNG file at all");
  obj = textured_square("garbage.png");
  expect_file_refused(obj, "texture " + (temp_dir() / "garbage.png").string() + ": ");
  // A PNG header claiming 65536 x 65536 pixels: refused from the header,
  // before 48 GiB of texels are allocated.
  // (A valid PNG: IHDR, an IDAT of 16 zero bytes, IEND, correct CRCs.)
  const unsigned char header[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
                                  0x44, 0x52, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x08, 0x02, 0x00, 0x00,
                                  0x00, 0xe3, 0xe6, 0xa7, 0xb4, 0x00, 0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78,
                                  0x9c, 0x63, 0x60, 0x40, 0x05, 0x00, 0x00, 0x10, 0x00, 0x01, 0x39, 0xbd, 0x8f, 0x65,
                                  0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  write_file("huge.png", std::string(reinterpret_cast<const char*>(header), sizeof header));
  obj = textured_square("huge.png");
  expect_file_refused(obj, "65536x65536x3 samples, more than the limit of 8192x8192x4 (16384 a side)");
}

TEST(MeshValidation, TextureValuesAreClampedAndNaNReadAsZero) {
  fs::path file = temp_dir() / "nan.exr";
  float pixels[2 * 1 * 3] = {std::nanf(""), 2.0f, -1.0f, INFINITY, 0.5f, 1e9f};
  auto out = OIIO::ImageOutput::create(file.string());
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(file.string(), OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::FLOAT)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels));
  out->close();
  auto t = voxelizer::read_texture(file.string(), "m.obj");
  ASSERT_EQ(t.texels.size(), 2u);
  EXPECT_EQ(t.texels[0], glm::vec3(0.0f, 2.0f, 0.0f));
  EXPECT_EQ(t.texels[1], glm::vec3(1e4f, 0.5f, 1e4f));
  // Sampling at a non-finite coordinate reads as 0, not as an index.
  glm::vec3 c = t.sample(glm::vec2(std::nanf(""), INFINITY));
  EXPECT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
}

}  // namespace

// Lattice points whose closest surface point lies on one of the cube's
// edges or corners take the distance's gradient as their normal (issue 20,
// item 2): it turns around the edge continuously, where the closest face's
// normal jumped between lattice points and interpolation drew a staircase
// along the crease. Points over a face's interior keep its normal.
TEST(MeshSource, NormalsTurnAroundConvexEdgesWithTheDistance) {
  voxelizer::TriangleMesh mesh = voxelizer::make_triangle_mesh("cube.obj", cube());
  const voxelizer::Box box = mesh.bounds;
  auto source = voxelizer::mesh_source(std::move(mesh));
  const voxelizer::Lattice lattice = voxelizer::make_lattice(box, 32);
  source->prepare(lattice);
  std::vector<voxelizer::FinePoint> points;
  const int n = int(lattice.resolution);
  source->evaluate(glm::ivec3(0), glm::ivec3(n), points);
  int edge = 0, face = 0;
  const double h = lattice.voxel;
  for (int z = 0; z <= n; ++z)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        const voxelizer::FinePoint& q = points[size_t((z * (n + 1) + y) * (n + 1) + x)];
        if (!q.near || !(q.distance > 0.1 * h)) continue;
        const glm::dvec3 p = lattice.position({x, y, z}), c(q.closest);
        // On an edge or a corner: at least two coordinates at the cube's faces.
        int at_faces = 0;
        for (int k = 0; k < 3; ++k) at_faces += std::abs(std::abs(c[k]) - 0.5) < 1e-5;
        const glm::vec3 n_expected = at_faces >= 2 ? glm::vec3(glm::normalize(p - c)) : q.normal;
        if (at_faces >= 2) {
          ++edge;
          EXPECT_NEAR(glm::length(q.normal - n_expected), 0.0f, 1e-4f) << x << "," << y << "," << z;
        } else {
          ++face;
          // A face's normal: one coordinate +-1, the others 0.
          EXPECT_NEAR(std::abs(q.normal.x) + std::abs(q.normal.y) + std::abs(q.normal.z), 1.0f, 1e-5f);
        }
      }
  EXPECT_GT(edge, 100);
  EXPECT_GT(face, 1000);
}
