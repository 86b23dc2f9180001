// Triangle meshes (OBJ, PLY, OFF, STL through OpenMesh) as a surface source:
// the distance field is OpenVDB's narrow-band level set, whose
// closest-polygon index grid gives attributes at the closest surface point.
#pragma once

#include <array>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

struct MeshOptions {
  // Colour of a mesh without vertex colours (linear RGB); default 0.8 grey.
  std::optional<glm::vec3> colour;
  // Micro-BRDF slope deviation sigma_rho; < 0: from the OBJ's materials
  // (Pr roughness, else Ns Phong exponent), else 0.1.
  float sigma_rho = -1;
};

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
  std::vector<glm::vec3> colours;                 // per vertex, linear RGB (the constant colour without vertex colours)
  std::vector<glm::ivec3> triangles;              // triangles of non-zero area only
  std::vector<glm::vec3> face_normals;            // unit, from the winding (counter-clockwise = front)
  std::vector<int> face_texture;                  // index into textures, or -1
  std::vector<std::array<glm::vec2, 3>> face_uv;  // texture coordinates of the corners
  std::vector<Texture> textures;
  size_t degenerate = 0;  // faces skipped for zero area
  double area = 0;        // scene units squared
  float sigma_rho2 = 0.01f;
  Box bounds;

  // The attribute (linear RGB) at barycentric point `bary` of `triangle`:
  // the texture where the face has one, else the interpolated vertex colours.
  glm::vec3 colour(size_t triangle, glm::dvec3 bary) const;
};

// Reads a mesh file (OBJ, PLY, OFF, STL through OpenMesh) with its vertex
// colours, and for OBJ its textures (map_Kd) and micro-BRDF roughness. The
// file is untrusted: throws std::runtime_error with "<path>: <problem>" for
// an unreadable file, an unknown format, no triangles, non-finite
// coordinates, a zero extent or a missing texture.
TriangleMesh read_mesh(const std::string& path, const MeshOptions& options = {});

// Loads a mesh as a surface source (read_mesh, then OpenVDB's level set in
// prepare()). The file is untrusted: throws std::runtime_error with
// "<path>: <problem>" for an unreadable file, an unknown format, no
// triangles, non-finite coordinates or a zero extent.
std::unique_ptr<SurfaceSource> load_mesh(const std::string& path, const MeshOptions& options = {});

}  // namespace svo::voxelizer
