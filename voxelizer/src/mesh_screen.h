// Screening of mesh files before OpenMesh reads them (mesh_screen.cpp).
// OpenMesh 9.0 trusts what a file says: its PLY reader writes through a
// wild pointer on a property type it does not know, its readers reserve
// memory for a header's counts and loop over a list's count as read, its
// OBJ reader is quadratic in a polygon's corners, opens every mtllib file
// it is given (a FIFO or /dev/zero hangs it) and drops faces and vertices
// it cannot use without a word. Everything it would trust is checked here
// first, strictly; the files are untrusted.
#pragma once

#include <cstddef>
#include <functional>
#include <glm/vec2.hpp>
#include <string>
#include <vector>

namespace svo::voxelizer::screen {

// A file's polygons of 4 or more corners as it lists them, for
// resplit_polygons: where each one's triangles start once every face is
// fanned (a face of k corners makes k - 2), its corners (0-based vertex
// indices; -1 where one cannot be read) and, where every corner names one,
// their texture coordinates. Triangles take no memory here.
struct FilePolygon {
  size_t first_triangle = 0;
  std::vector<int> corners;
  std::vector<glm::vec2> uv;  // empty, or one per corner
};
struct FilePolygons {
  std::vector<FilePolygon> polygons;
  size_t triangles = 0;  // of all faces, fanned
  // Adds a face of `corners` (and their `uv`, if any): kept if a polygon.
  void add(std::vector<int> corners, std::vector<glm::vec2> uv) {
    const size_t k = corners.size();
    if (k > 3) polygons.push_back({triangles, std::move(corners), std::move(uv)});
    triangles += k >= 3 ? k - 2 : 0;
  }
  // Counts a triangle face.
  void add_triangle() { ++triangles; }
};

// The path's extension in lower case (".obj").
std::string lower_extension(const std::string& path);

// "" when OpenMesh may be given the mesh file at `path` (a regular file),
// else the problem, without the path ("PLY line 13: ..."). PLY: the header,
// and the body (ASCII or binary, either byte order) walked element by
// element: list counts from 0 to kMaxPolygonCorners, faces of 3 or more
// corners whose indices name a vertex, the bytes there. OFF: header and
// body. OBJ: vertex lines whose three coordinates OpenMesh reads (not
// "nan", "inf", 1e39), face corners V, V/T,
// V//N or V/T/N whose V and T indices name a vertex and a texture
// coordinate of the file, at most kMaxPolygonCorners corners a face. STL:
// the triangle count of a binary file, the facets of an ASCII one. All:
// at most kMaxMeshTriangles triangles.
// `triangles`, when given: the triangles the file's faces make (k - 2 for
// a face of k corners), or -1 when nothing was screened. `own_reader`,
// when given: why an OFF file must be read by svo's own reader, or "":
// "faces with colours" (numbers after a face's corners, which OpenMesh's
// reader misreads), "comment lines before the OFF keyword" (as CGAL writes
// them; OpenMesh's reader refuses the file). `polygons`, when given:
// whether an OFF or OBJ file has a face of more than 3 corners.
// `ply_polygons`, when given: a PLY file's faces of more than 3 corners, as
// it lists them (OpenMesh fans them; mesh_read.cpp splits non-convex ones
// again).
std::string screen_mesh_file(const std::string& path, double* triangles = nullptr, std::string* own_reader = nullptr,
                             bool* polygons = nullptr, FilePolygons* ply_polygons = nullptr);

// Checks the OBJ's mtllib files where OpenMesh and read_mtl_materials look
// for them (relative to the OBJ): each must be a regular file of at most
// kMaxMtlBytes. `warning` gets one line for each that does not exist.
// @throw std::runtime_error "<obj>: mtllib <file>: is a FIFO, expected an
//        MTL material file" and the like (one line).
void check_obj_material_files(const std::string& path, const std::function<void(const std::string&)>& warning);

// Largest MTL file read.
inline constexpr unsigned long long kMaxMtlBytes = 16ull << 20;

}  // namespace svo::voxelizer::screen
