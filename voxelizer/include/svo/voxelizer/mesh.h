// Triangle meshes (OBJ, PLY, OFF, STL through OpenMesh) as a surface source:
// the distance field is OpenVDB's narrow-band level set, whose
// closest-polygon index grid gives attributes at the closest surface point.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

// Default texture budgets (MeshOptions): 64 Mi pixels (8192x8192) for one
// texture, 256 Mi pixels for all of a mesh's textures (3 GiB of texels).
inline constexpr double kDefaultMaxTexturePixels = 8192.0 * 8192.0;
inline constexpr double kDefaultMaxTotalTexturePixels = 4 * kDefaultMaxTexturePixels;

// Polygon budget of the mesh readers: at most kMaxPolygonCorners corners a
// polygon (OpenMesh's OBJ reader is quadratic in them: 100k corners took
// 21 s) and kMaxMeshTriangles triangles once polygons are split.
inline constexpr int kMaxPolygonCorners = 1000;
inline constexpr double kMaxMeshTriangles = 100e6;

// The k - 2 triangles of a polygon of k corners (in order), as corner
// numbers 0..k-1 wound as the polygon: its fan from the first corner where
// the polygon is convex (as OpenMesh and the OFF reader split every
// polygon), else ear clipping in the plane of its Newell normal, so that a
// non-convex polygon keeps its shape (libcgal-demo's corner_poly.off: the
// fan of an L-shaped hexagon covers the square the L leaves out). A
// polygon with no ear left (self-intersecting) ends as a fan.
std::vector<glm::ivec3> triangulate_polygon(std::span<const glm::dvec3> corners);

// A mesh whose bounding box is smaller than this on every axis is refused:
// the octree squares voxel sizes in float (1.2e-38 is the smallest normal).
inline constexpr double kMinExtent = 1e-12;

struct MeshOptions {
  // Colour of a mesh without vertex colours (linear RGB); default 0.8 grey.
  std::optional<glm::vec3> colour;
  // Micro-BRDF slope deviation sigma_rho; < 0: from the OBJ's materials
  // (Pr roughness, else Ns Phong exponent), else 0.1.
  float sigma_rho = -1;
  // Receives one line per documented repair or caveat ("<path>: <what>"):
  // degenerate triangles dropped, an open or non-manifold surface, an
  // mtllib file that does not exist. Unset: silent.
  std::function<void(const std::string&)> warning;
  // Texture budgets, in pixels, checked from the images' headers before any
  // is decoded (each texel costs 12 bytes as linear RGB, more while
  // decoding): the largest texture, and all textures of the mesh (of a
  // scene file: of all its meshes) together.
  double max_texture_pixels = kDefaultMaxTexturePixels;
  double max_total_texture_pixels = kDefaultMaxTotalTexturePixels;
};

// Coordinates beyond +-kMaxCoordinate are refused: the renderer squares
// distances in float (3.4e38), and the octree's origin and size are floats.
inline constexpr double kMaxCoordinate = 1e15;

// Share of a surface's area that must look closed to the winding number for
// a surface with holes to be drawn as a solid (TriangleMesh::two_sided).
inline constexpr double kClosedShare = 0.95;

// How surely a triangle of a surface drawn two-sided bounds a volume, from
// m = w + 1/2, w the generalized winding number just in front of it (the
// middle of the jump of 1 through it): near 1/2 it bounds one behind its
// face, near -1/2 one in front (a piece wound inside out), near 0 it is a
// sheet (both sides outside). 0 to 1, ramped over |m| from 0.15 to 0.35:
// how far its shell moves into the volume (mesh_source.cpp), and the share
// of the area that `surface` says bounds a volume.
inline double bounds_volume(double m) { return std::clamp((std::abs(m) - 0.15) / 0.2, 0.0, 1.0); }

// Largest texture read by default (MeshOptions::max_texture_pixels):
// 8192^2 texels of at most 4 channels, twice the budget's square root a
// side; a larger one is refused from its header, before its pixels are
// allocated.
inline constexpr double kMaxTextureTexels = kDefaultMaxTexturePixels;

// A texture in linear RGB (8- and 16-bit files are decoded from sRGB),
// sampled bilinearly with wrap-around; OBJ convention: v up.
struct Texture {
  int width = 0, height = 0;
  std::vector<glm::vec3> texels;  // row-major, top row first
  glm::vec3 sample(glm::vec2 uv) const;
};

// A triangle mesh as read from its file: what the voxelizer and the
// reference ray tracer both use, so that they see the same surface and the
// same attributes.
struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  // Per vertex, the first vertex at the same position: edges and their
  // topology are by position (OpenMesh splits a vertex where the faces
  // around it disagree in winding; faces may be stored with corners of
  // their own).
  std::vector<uint32_t> welded;
  // The edge between vertices a and b, by position (welded): the same key
  // for either direction.
  uint64_t edge_key(int a, int b) const {
    const uint32_t i = welded[size_t(a)], j = welded[size_t(b)];
    return uint64_t(std::min(i, j)) << 32 | std::max(i, j);
  }
  std::vector<glm::vec3> colours;                 // per vertex, linear RGB (the constant colour without vertex colours)
  std::vector<glm::ivec3> triangles;              // triangles of non-zero area only
  std::vector<glm::vec3> face_normals;            // unit, from the winding (counter-clockwise = front)
  std::vector<int> face_texture;                  // index into textures, or -1
  std::vector<std::array<glm::vec2, 3>> face_uv;  // texture coordinates of the corners
  std::vector<Texture> textures;
  std::vector<uint32_t> face_material;  // index into materials per triangle; empty: material 0 everywhere
  std::vector<std::string> materials;   // JSON texts (DESIGN 10.2); empty: none of its own
  size_t degenerate = 0;                // faces skipped for zero area
  size_t open_edges = 0;                // edges of exactly one kept triangle (0: closed)
  size_t nonmanifold_edges = 0;         // edges of three or more kept triangles
  // Drawn two-sided, as a thin shell around every triangle (both sides
  // outside, as the reference's double-sided triangles are): a surface with
  // open or non-manifold edges whose generalized winding number is within
  // 0.05 of 0 and 1 on either side of less than kClosedShare of its area
  // (elsewhere its holes take up more than 5% of the sphere: the lidless box
  // and the lion's open head, not the Chinese dragon's six open edges).
  // Where a triangle bounds a volume by the winding number, its shell lies
  // inside that volume, its outer face on the triangle (mesh_source.cpp).
  // Else a solid (OpenVDB's flood fill decides inside and outside).
  bool two_sided = false;
  // What was decided about inside and outside, and why, one line
  // ("two-sided: ...", "solid: ..."): the warning says it, and the octree
  // records it (svo info).
  std::string surface;
  double area = 0;  // scene units squared
  float sigma_rho2 = 0.01f;
  Box bounds;

  // The attribute (linear RGB) at barycentric point `bary` of `triangle`:
  // the texture where the face has one, else the interpolated vertex colours.
  glm::vec3 colour(size_t triangle, glm::dvec3 bary) const;
};

// What a mesh file holds once parsed, before any check: the input of
// make_triangle_mesh. Corner indices, uv and texture indices come from the
// file and may be anything.
struct MeshArrays {
  std::vector<glm::dvec3> positions;
  std::vector<glm::vec3> colours;                 // empty, or one per position (linear RGB)
  std::vector<glm::ivec3> triangles;              // corner indices into positions
  std::vector<std::array<glm::vec2, 3>> face_uv;  // empty, or one per triangle
  std::vector<int> face_texture;                  // empty, or one per triangle: index into textures or -1
  std::vector<Texture> textures;
  std::vector<uint32_t> face_material;  // empty, or one per triangle: index into materials
  std::vector<std::string> materials;   // JSON texts (at most 255)
};

// Checks and repairs parsed mesh data into a TriangleMesh; `path` names the
// input in messages. Refused, std::runtime_error "<path>: <problem>" (one
// line): no triangles; a per-vertex or per-face array whose count differs
// from the vertex or triangle count; a non-finite coordinate or one beyond
// +-kMaxCoordinate; a corner index outside [0, vertex count); a texture index
// outside [-1, texture count); a non-finite texture coordinate on a textured
// face (those of untextured faces are ignored, set to 0); a texture
// without texels; no triangle of non-zero area; a zero extent or one below
// kMinExtent on every axis.
// Repaired (counted, reported through options.warning): triangles of zero
// area are dropped (they have no normal and bound nothing). Reported, kept:
// open edges (used by one triangle) and non-manifold edges (three or more);
// such a surface is drawn two-sided or as a solid as the winding number
// decides (two_sided), and the warning says which.
TriangleMesh make_triangle_mesh(const std::string& path, MeshArrays arrays, const MeshOptions& options = {});

// Reads a texture image through OpenImageIO into linear RGB (8- and 16-bit
// files decoded from sRGB, at most 3 channels used, one channel as grey),
// with the reader of the file's extension only.
// @throw std::runtime_error "<mesh_path>: texture <file>: <problem>" for a
//        missing file, one that is not regular (a FIFO, a device, a link to
//        one: refused before any library opens it), an unreadable file, an
//        unsupported format, no pixels, more than `max_pixels` texels or 4
//        `max_pixels` samples or twice its square root a side (from the
//        header), an OpenEXR header that check_exr_header refuses.
//        Texel values are clamped to [0, 1e4], NaN read as 0.
Texture read_texture(const std::string& file, const std::string& mesh_path,
                     double max_pixels = kDefaultMaxTexturePixels);

// Reads a mesh file (OBJ, PLY, OFF, STL through OpenMesh) with its vertex
// colours, and for OBJ its textures (map_Kd), micro-BRDF roughness and, with
// two or more usemtl groups, a material per group (face_material, materials:
// GGX from Pr, Phong from Ns and Ks, else Lambert, diffuse Kd). The file is
// untrusted: throws std::runtime_error with "<path>: <problem>" (one line)
// for an unreadable file or one that is not regular, an unknown format, an
// mtllib file that is not regular or above 16 MiB (one that does not exist
// is a warning), a missing or refused texture (read_texture), textures
// whose headers state more than options.max_total_texture_pixels in all
// (checked before any is decoded), and every refusal of make_triangle_mesh,
// which it calls. What OpenMesh 9.0 would trust is checked first, strictly
// (mesh_screen.h): PLY headers and bodies (ASCII and binary), OFF headers
// and bodies, OBJ vertex and face lines; a face index naming no vertex, a
// vertex OpenMesh would drop ("v nan 0 0"), a polygon of more than
// kMaxPolygonCorners corners or more than kMaxMeshTriangles triangles are
// refused with the line or element (binary OFF and OBJ "vc" lines too).
TriangleMesh read_mesh(const std::string& path, const MeshOptions& options = {});

// Loads a mesh as a surface source (read_mesh, then OpenVDB's level set in
// prepare()). The file is untrusted: throws what read_mesh throws.
std::unique_ptr<SurfaceSource> load_mesh(const std::string& path, const MeshOptions& options = {});
// A mesh already read (read_mesh, read_scene_file) as a surface source, its
// materials and face materials included.
std::unique_ptr<SurfaceSource> mesh_source(TriangleMesh mesh);

// Reads a scene file (`svo voxelize --scene-file`, docs/materials.md): a JSON
// object {"materials": {NAME: MATERIAL or "FILE.json", ...}, "objects":
// [{"mesh": FILE, "material": NAME, "scale": s or [x, y, z], "rotate":
// [x, y, z] degrees, "translate": [x, y, z], "colour": [r, g, b]}, ...]},
// paths relative to the scene file. Each mesh is read by read_mesh, placed by
// translate * Rz * Ry * Rx * scale, and merged, each face keeping its
// object's material (face_material, in the order of the materials' names;
// a MERL "file" made absolute). Materials are not parsed here (the
// renderer's parse_material does that); the scene's structure is: unknown
// keys, a missing or unknown material name, a scale <= 0, a file that is
// not regular or above 1 MiB, more than 255 materials or 1024 objects are
// std::runtime_error "scene file PATH: ..." (one line).
TriangleMesh read_scene_file(const std::string& path, const MeshOptions& options = {});

}  // namespace svo::voxelizer
