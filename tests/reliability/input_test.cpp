// Reliability round two (issue 22): input cases through the svo executable.
// Each hostile input is written by the test into its own directory; `svo
// voxelize` (and `svo reference` where it reads the same meshes) must exit 1
// with one line naming the input and the problem, within a few seconds and a
// bounded memory, and leave an earlier output at the -o path as it was
// (label: cli).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "reliability/run_svo.h"
#include "render/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using svo::testing::bytes_of;
using svo::testing::Limits;
using svo::testing::Outcome;
using svo::testing::run_svo;
using svo::testing::TempDir;

constexpr double kSeconds = 10;  // a refusal's time (hangs ran past 30 s)
// The bound on a run's peak memory: 256 MiB over the executable's start (the cases reached GBs).
long peak_limit_kib() { return svo::testing::startup_peak_kib() + 256 * 1024; }
const Limits kLimits{.seconds = 60};  // a hang is killed and fails
const std::string kEarlier = "an earlier output\n";

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A textured tetrahedron whose OBJ names `mtllib` and whose material
// (when `map_kd` is not empty) names `map_kd` as its texture.
std::string textured_obj(const TempDir& dir, const std::string& name, const std::string& mtllib,
                         const std::string& map_kd = "") {
  if (!map_kd.empty()) write_text(dir / (name + ".mtl"), "newmtl m\nKd 1 1 1\nmap_Kd " + map_kd + "\n");
  const std::string obj = dir / (name + ".obj");
  write_text(obj, "mtllib " + (map_kd.empty() ? mtllib : name + ".mtl") +
                      "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\n"
                      "f 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n");
  return obj;
}

// A closed tetrahedron in `text` OBJ lines, with `extra` lines after.
std::string tetrahedron_obj(const std::string& extra = "") {
  return "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n" + extra;
}

// Runs `args` (+ "-o OUT" over an earlier output) and checks the refusal:
// exit 1, one line naming `input` and holding `problem`, fast, small, the
// earlier output untouched.
void expect_refused(const TempDir& dir, std::vector<std::string> args, const std::string& input,
                    const std::string& problem, const std::string& output_name = "keep.svo") {
  const std::string out = dir / output_name;
  write_text(out, kEarlier);
  args.push_back("-o");
  args.push_back(out);
  const Outcome o = run_svo(args, kLimits);
  SCOPED_TRACE(args[0] + " " + args[1]);
  EXPECT_EQ(o.status, 1) << o.err;
  EXPECT_EQ(o.lines(), 1) << o.err;
  EXPECT_NE(o.err.find(input), std::string::npos) << o.err;
  EXPECT_NE(o.err.find(problem), std::string::npos) << o.err;
  EXPECT_LT(o.seconds, kSeconds) << o.err;
  EXPECT_LT(o.peak_kib, peak_limit_kib()) << o.err;
  const std::vector<char> after = bytes_of(out);
  EXPECT_EQ(std::string(after.begin(), after.end()), kEarlier);
}

void expect_voxelize_refused(const TempDir& dir, const std::string& mesh, const std::string& input,
                             const std::string& problem) {
  expect_refused(dir, {"voxelize", mesh, "--resolution", "32"}, input, problem);
}

void expect_reference_refused(const TempDir& dir, const std::string& mesh, const std::string& input,
                              const std::string& problem) {
  expect_refused(
      dir, {"reference", mesh, "--camera", "3,3,3,0,0,0,0,1,0,40", "--spp", "1", "--width", "16", "--height", "16"},
      input, problem, "keep.png");
}

// ---- Case 3: device files, FIFOs and links to devices named as a texture,
// a material file or the mesh. They hung (OpenImageIO tries every format on
// /dev/zero; OpenMesh reads an mtllib /dev/urandom without end) or grew past
// 2 GB (mtllib /dev/zero).

TEST(Input, TextureNamingADeviceIsRefused) {
  TempDir dir;
  const std::string obj = textured_obj(dir, "zero", "", "/dev/zero");
  expect_voxelize_refused(dir, obj, obj + ": texture /dev/zero", "is a character device, expected an image");
  expect_reference_refused(dir, obj, obj + ": texture /dev/zero", "is a character device, expected an image");
}

TEST(Input, MtllibNamingADeviceIsRefused) {
  TempDir dir;
  // Relative, so that OpenMesh (which opens it after the OBJ's folder) and
  // our material reader both reach the device.
  std::string up;
  for (int i = 0; i < 32; ++i) up += "../";
  for (const std::string device : {"urandom", "zero"}) {
    const std::string obj = textured_obj(dir, device, up + "dev/" + device);
    expect_voxelize_refused(dir, obj, obj + ": mtllib ", "dev/" + device + ": is a character device, expected an MTL");
    expect_reference_refused(dir, obj, obj + ": mtllib ", "dev/" + device + ": is a character device");
  }
  // Absolute: our material reader would open it.
  const std::string obj = textured_obj(dir, "absolute", "/dev/zero");
  expect_voxelize_refused(dir, obj, obj + ": mtllib /dev/zero", "is a character device");
}

TEST(Input, FifoOrLinkToADeviceAsTextureMaterialOrMeshIsRefused) {
  TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "fifo.png").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir / "fifo.mtl").c_str(), 0644), 0);
  ASSERT_EQ(::mkfifo((dir / "fifo.obj").c_str(), 0644), 0);
  fs::create_symlink("/dev/zero", dir / "link.png");
  fs::create_symlink("/dev/zero", dir / "link.mtl");
  fs::create_symlink("/dev/zero", dir / "link.obj");
  std::string obj = textured_obj(dir, "tex_fifo", "", "fifo.png");
  expect_voxelize_refused(dir, obj, obj + ": texture " + (dir / "fifo.png"), "is a FIFO, expected an image");
  expect_reference_refused(dir, obj, obj + ": texture " + (dir / "fifo.png"), "is a FIFO, expected an image");
  obj = textured_obj(dir, "tex_link", "", "link.png");
  expect_voxelize_refused(dir, obj, obj + ": texture " + (dir / "link.png"), "is a character device");
  obj = textured_obj(dir, "mtl_fifo", "fifo.mtl");
  expect_voxelize_refused(dir, obj, obj + ": mtllib " + (dir / "fifo.mtl"), "is a FIFO, expected an MTL");
  expect_reference_refused(dir, obj, obj + ": mtllib " + (dir / "fifo.mtl"), "is a FIFO, expected an MTL");
  obj = textured_obj(dir, "mtl_link", "link.mtl");
  expect_voxelize_refused(dir, obj, obj + ": mtllib " + (dir / "link.mtl"), "is a character device");
  expect_voxelize_refused(dir, dir / "fifo.obj", dir / "fifo.obj", "not a regular file");
  expect_voxelize_refused(dir, dir / "link.obj", dir / "link.obj", "not a regular file");
  expect_reference_refused(dir, dir / "link.obj", dir / "link.obj", "not a regular file");
}

// ---- Case 4: a binary PLY whose face list count is -1, 2^32 - 1 or more
// than its bytes hold (OpenMesh's binary reader looped on it: 95 s, 4.2 GB).

std::string binary_ply(bool big_endian, const std::string& count_type, const std::string& count_bytes,
                       int32_t last_index = 2, int indices = 3) {
  std::string ply = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list " +
                    count_type + " int vertex_indices\nend_header\n";
  auto put = [&](uint32_t u) {
    for (int i = 0; i < 4; ++i) ply += char(big_endian ? (u >> (8 * (3 - i))) & 0xFF : (u >> (8 * i)) & 0xFF);
  };
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (float f : xyz) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    put(u);
  }
  ply += count_bytes;
  const int32_t face[3] = {0, 1, last_index};
  for (int i = 0; i < indices; ++i) put(uint32_t(face[i]));
  return ply;
}

TEST(Input, BinaryPlyListCountsAreScreened) {
  TempDir dir;
  struct Case {
    std::string name, ply, problem;
  };
  const Case cases[] = {
      {"minus_one.ply", binary_ply(false, "int", std::string("\xFF\xFF\xFF\xFF", 4)),
       "PLY face 0: a list count of -1 (from 0 to 1000)"},
      {"huge_be.ply", binary_ply(true, "uint", std::string("\xFF\xFF\xFF\xFF", 4)),
       "PLY face 0: a list count of 4294967295 (from 0 to 1000)"},
      {"short.ply", binary_ply(false, "uchar", "\xFF"), "PLY file ends inside face 0"},
      {"few.ply", binary_ply(false, "uchar", "\x03", 2, 2), "PLY file ends inside face 0"},
      {"two.ply", binary_ply(true, "uchar", "\x02", 2, 2), "PLY face 0: a face of 2 corners (at least 3)"},
  };
  for (const Case& c : cases) {
    write_text(dir / c.name, c.ply);
    expect_voxelize_refused(dir, dir / c.name, dir / c.name, c.problem);
  }
  // The same file with a sound count is read, in either byte order.
  for (bool big : {false, true}) {
    write_text(dir / "ok.ply", binary_ply(big, "uchar", "\x03"));
    const Outcome o = run_svo({"voxelize", dir / "ok.ply", "--resolution", "16", "-o", dir / "ok.svo"}, kLimits);
    EXPECT_EQ(o.status, 0) << o.err;
  }
}

// ---- Case 5: texture budgets, from the headers before anything is decoded
// (six 8192x8192 PNGs of 82 KB took 5 GB and 25 s, then exit 0).

// CRC-32 of PNG chunks (ISO 3309).
uint32_t crc32(const std::string& bytes) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

std::string be32(uint32_t u) { return {char(u >> 24), char((u >> 16) & 0xFF), char((u >> 8) & 0xFF), char(u & 0xFF)}; }

// A valid 8-bit grey PNG of width x height black pixels: its zlib stream a
// fixed-Huffman deflate block of one literal 0 and copies of 258 (RFC 1951
// 3.2.6), 422 KB for 8192x8192.
std::string black_png(uint32_t width, uint32_t height) {
  const uint64_t raw = uint64_t(height) * (width + 1);  // a filter byte per row
  std::string deflate;
  uint32_t acc = 0;
  int bits = 0;
  auto put = [&](uint32_t value, int count) {  // LSB first
    for (int i = 0; i < count; ++i) {
      acc |= ((value >> i) & 1u) << bits;
      if (++bits == 8) deflate += char(acc), acc = 0, bits = 0;
    }
  };
  auto code = [&](uint32_t c, int length) {  // Huffman codes MSB first
    for (int i = length - 1; i >= 0; --i) put((c >> i) & 1u, 1);
  };
  put(1, 1);  // BFINAL
  put(1, 2);  // BTYPE 01: fixed Huffman
  uint64_t left = raw;
  code(0x30, 8), --left;                                       // literal 0
  for (; left >= 258; left -= 258) code(0xC5, 8), code(0, 5);  // length 258 (symbol 285), distance 1
  for (; left > 0; --left) code(0x30, 8);
  code(0, 7);  // end of block
  if (bits) deflate += char(acc);
  const uint32_t adler = uint32_t((raw % 65521) << 16 | 1);  // of zeros: a = 1, b = n
  const std::string zlib = std::string("\x78\x01", 2) + deflate + be32(adler);
  auto chunk = [](const std::string& type, const std::string& data) {
    return be32(uint32_t(data.size())) + type + data + be32(crc32(type + data));
  };
  return std::string("\x89PNG\r\n\x1a\n", 8) +
         chunk("IHDR", be32(width) + be32(height) + std::string("\x08\x00\x00\x00\x00", 5)) + chunk("IDAT", zlib) +
         chunk("IEND", "");
}

TEST(Input, TextureBudgetsAreCheckedFromTheHeaders) {
  TempDir dir;
  const std::string png = black_png(8192, 8192);
  ASSERT_LT(png.size(), 500u * 1024);
  std::string mtl, obj = "mtllib six.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n";
  for (int i = 0; i < 6; ++i) {
    const std::string name = "big" + std::to_string(i) + ".png";
    write_text(dir / name, png);
    mtl += "newmtl m" + std::to_string(i) + "\nKd 1 1 1\nmap_Kd " + name + "\n";
    obj += "usemtl m" + std::to_string(i) + "\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n";
  }
  write_text(dir / "six.mtl", mtl);
  write_text(dir / "six.obj", obj);
  // 6 x 64 Mi pixels: the fifth passes the total of 256 Mi.
  expect_voxelize_refused(dir, dir / "six.obj", dir / "six.obj",
                          "8192x8192 pixels bring the mesh's textures to 320 Mi pixels, more than the limit of 256 Mi "
                          "pixels for all of them (--max-texture-mpix-total raises it)");
  expect_reference_refused(dir, dir / "six.obj", dir / "six.obj", "more than the limit of 256 Mi pixels");
  // The budget of one texture, lowered and raised by the option.
  const std::string one = textured_obj(dir, "one", "", "small.png");
  write_text(dir / "small.png", black_png(2048, 2048));
  expect_refused(dir, {"voxelize", one, "--resolution", "16", "--max-texture-mpix", "1"}, one + ": texture ",
                 "2048x2048x1 samples, more than the limit of 1024x1024x4 (2048 a side); --max-texture-mpix raises it");
  expect_refused(dir, {"voxelize", one, "--resolution", "16", "--max-texture-mpix-total", "3"}, one + ": texture ",
                 "more than the limit of 3 Mi pixels for all of them");
  const Outcome o = run_svo({"voxelize", one, "--resolution", "16", "-o", dir / "one.svo"}, kLimits);
  EXPECT_EQ(o.status, 0) << o.err;
}

// ---- Case 6: a polygon of 100k corners (21 s in OpenMesh's duplicate
// removal, quadratic): refused past kMaxPolygonCorners.

TEST(Input, PolygonOfTooManyCornersIsRefused) {
  TempDir dir;
  std::string obj, face = "f";
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * 3.14159265358979 * i / n;
    // (appended piece by piece: GCC 12 warns of " " + std::to_string falsely)
    obj.append("v ").append(std::to_string(std::cos(a))).append(" ").append(std::to_string(std::sin(a)));
    obj.append(" 0\n");
    face.append(" ").append(std::to_string(i + 1));
  }
  write_text(dir / "polygon.obj", obj + face + "\n");
  expect_voxelize_refused(dir, dir / "polygon.obj", dir / "polygon.obj",
                          "OBJ line 100001: a face of more than 1000 corners (the limit of the mesh readers)");
  // Nor in a PLY.
  std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list ushort int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n1001";
  for (int i = 0; i < 1001; ++i) ply.append(" ").append(std::to_string(i % 3));
  write_text(dir / "polygon.ply", ply + "\n");
  expect_voxelize_refused(dir, dir / "polygon.ply", dir / "polygon.ply",
                          "PLY line 13: a list count '1001' is not an integer from 0 to 1000");
}

// ---- Case 10: input that OpenMesh dropped without a word (exit 0): faces
// with indices that name no vertex, a vertex it cannot parse ("nan") with
// every face naming a later vertex.

TEST(Input, IndicesNamingNoVertexAreRefused) {
  TempDir dir;
  struct Case {
    std::string name, text, problem;
  };
  const std::string ply_header =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 5\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const Case cases[] = {
      {"index.obj", tetrahedron_obj("f 1 2 999999999\n"),
       "OBJ line 9: face corner '999999999' refers to vertex 999999999, but the file has 4 vertices (counted from 1)"},
      {"negative.obj", tetrahedron_obj("f 1 2 -99\n"),
       "OBJ line 9: face corner '-99' refers to vertex -99, but 4 vertices precede the line"},
      {"forward.obj", "f -1 -2 -3\n" + tetrahedron_obj(),
       "OBJ line 1: face corner '-1' refers to vertex -1, but 0 vertices precede the line"},
      {"uv.obj", tetrahedron_obj("vt 0 0\nf 1/1 2/2 3/1\n"),
       "OBJ line 10: face corner '2/2' refers to texture coordinate 2, but the file has 1 texture coordinates"},
      {"nan.obj", "v nan 0 0\n" + tetrahedron_obj("f 1 2 3\n"),
       "OBJ line 1: vertex coordinate 'nan' is not a finite number"},
      {"overflow.obj", tetrahedron_obj("v 1e39 0 0\n"), "OBJ line 9: vertex coordinate '1e39' is not a finite number"},
      {"index.ply", ply_header + "3 0 1 1000000\n", "PLY line 18: a face refers to vertex 1000000, but the file has 4"},
      {"negative.ply", ply_header + "3 0 1 -1\n", "PLY line 18: corner '-1' is not a vertex index"},
  };
  for (const Case& c : cases) {
    write_text(dir / c.name, c.text);
    expect_voxelize_refused(dir, dir / c.name, dir / c.name, c.problem);
  }
  write_text(dir / "index_binary.ply", binary_ply(false, "uchar", "\x03", 1000000));
  expect_voxelize_refused(dir, dir / "index_binary.ply", dir / "index_binary.ply",
                          "PLY face 0: refers to vertex 1000000, but the file has 3 vertices");
  expect_reference_refused(dir, dir / "index.obj", dir / "index.obj", "refers to vertex 999999999");
}

// ---- Case 11: a mesh of 1e-20 failed in OpenVDB ("ArithmeticError:
// Non-zero scale values required", naming no file); a small one that the
// octree's floats can hold is voxelized.

TEST(Input, TinyMeshIsRefusedNamingTheFile) {
  TempDir dir;
  write_text(dir / "tiny.obj", "v 0 0 0\nv 1e-20 0 0\nv 0 1e-20 0\nv 0 0 1e-20\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  expect_voxelize_refused(dir, dir / "tiny.obj", dir / "tiny.obj",
                          "the mesh's bounding box is too small: extent 1e-20, below 1e-12");
  // 1e-6 across: OpenVDB's transform of voxels of 4e-9 (its volume below
  // 3e-15) failed too; the grids now live in index space.
  write_text(dir / "small.obj", "v 0 0 0\nv 1e-6 0 0\nv 0 1e-6 0\nv 0 0 1e-6\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  const Outcome o = run_svo({"voxelize", dir / "small.obj", "--resolution", "256", "-o", dir / "small.svo"}, kLimits);
  EXPECT_EQ(o.status, 0) << o.err;
}

}  // namespace
