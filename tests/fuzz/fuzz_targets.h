// The fuzz targets' bodies (STYLE 9), shared by the libFuzzer executables
// (fuzz_main.cpp, Clang only) and by the replay test (fuzz_replay_test.cpp,
// every compiler), which runs the seed corpora and the regression inputs
// under regressions/<target>/ through the same code.
//
// Contract of each: any bytes give either an accepted input (return 1) or
// the one-line error the input's API documents (return 0); never a crash, a
// hang, a sanitizer report or another exception.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace svo::fuzz {

// The .svo loader: checksums recomputed first (so that mutations reach the
// checks behind them), then SvoView and validate_octree.
int svo_load(const uint8_t* data, size_t size);

// make_triangle_mesh on arrays decoded from the bytes (mesh_arrays_encode's
// layout); an accepted mesh is then checked: corners in range, a unit
// normal per triangle, finite bounds, and a colour at every triangle.
int mesh_arrays(const uint8_t* data, size_t size);

// read_mesh on the bytes written to a temporary file; the first byte picks
// the extension (.obj, .off, .ply, .stl): OpenMesh's parsers, then ours.
int mesh_file(const uint8_t* data, size_t size);

// The camera and light parsers; the first byte picks one: 0 parse_camera_json,
// 1 parse_camera (the --camera text), 2 parse_light, 3 parse_camera_path.
int camera(const uint8_t* data, size_t size);

// Images we read: the bytes written to a temporary file, the first byte
// picks the extension (.png, .exr, .ppm, .tga) and the second the reader
// (even: read_texture of meshes, odd: read_image of `svo compare`).
int texture(const uint8_t* data, size_t size);

// load_merl on the bytes written to a temporary file; the first byte picks
// how: even, the rest verbatim; odd, a file of the valid size (35 MB) whose
// first 12 bytes are the next 12 (zero-padded) and whose payload repeats the
// bytes after them (zeros if none), so that small inputs reach the value
// checks. An accepted table is checked: 3 x 90 x 90 x 180 finite values >= 0.
int merl(const uint8_t* data, size_t size);

// load_environment on the bytes written to a temporary file (first byte:
// .exr or .hdr); an accepted map must build its distribution and sample
// finite directions and densities.
int environment(const uint8_t* data, size_t size);

// parse_material on the bytes as JSON text; an accepted analytic material
// must write back (material_json) to JSON of the same kind.
int material(const uint8_t* data, size_t size);

// read_scene_file on the bytes written to a temporary .json, beside which
// svo-fuzz-tet.off (a tetrahedron) and svo-fuzz-groups.obj (two usemtl
// groups) lie; an accepted scene is checked (arrays of one length, material
// indices in range, unit normals, finite bounds) and its materials parsed.
int scene_file(const uint8_t* data, size_t size);

// parse_light_field on the bytes (a .lfl file, docs/luminaire.md), its
// trailing XXH64 recomputed first (so that mutations reach the checks
// behind it); an accepted field must pass validate_light_field and encode
// to bytes that parse back to the same counts.
int luminaire(const uint8_t* data, size_t size);

// import_tm25 (grid 3, resolution 8) on a TM-25 ray file made from the
// bytes: when there are at least 288, the 36000-byte description block
// (nine UTF-32 strings, zeros) is inserted after the first 288, so that
// small seeds reach the rays; an accepted import must pass
// validate_light_field.
int tm25(const uint8_t* data, size_t size);

// read_mesh on the bytes written to a temporary file; the first byte picks
// the extension (even: .gltf, odd: .glb): the GLB and JSON screens,
// tinygltf, then our accessor checks and read_texture (issue 21).
int gltf(const uint8_t* data, size_t size);

// load_vdb on the bytes written to a temporary .vdb file (OpenVDB's reader
// behind our checks); an accepted source must have finite, ordered bounds
// and a positive surface area (issue 21).
int vdb(const uint8_t* data, size_t size);

// The layout mesh_arrays decodes: u32 vertex count, u32 triangle count,
// u8 flags (1 colours, 2 uv, 4 texture indices, 8 one 2x2 texture), then
// positions (3 f64 each), colours (3 f32), triangles (3 i32), uv (6 f32),
// texture indices (i32). Short input is zero-padded.
struct MeshSeed {
  std::vector<double> positions;  // 3 per vertex
  std::vector<int32_t> corners;   // 3 per triangle
  bool colours = false, uv = false, texture = false;
};
std::vector<uint8_t> mesh_arrays_encode(const MeshSeed& seed);

// Writes a seed corpus per target into dir/<target>/ (targets: svo_load,
// mesh_arrays, mesh_file, camera, texture, merl, environment, material, scene_file, luminaire, tm25, gltf, vdb), made by the
// library's own writers; seeds named refused-* are inputs the loader must refuse. Returns
// the number of files written.
int write_seeds(const std::filesystem::path& dir);

std::vector<std::string> target_names();
int run_target(const std::string& name, const uint8_t* data, size_t size);

}  // namespace svo::fuzz
