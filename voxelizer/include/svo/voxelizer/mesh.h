// Triangle meshes (OBJ, PLY, OFF, STL through OpenMesh) as a surface source:
// the distance field is OpenVDB's narrow-band level set, whose
// closest-polygon index grid gives attributes at the closest surface point.
#pragma once

#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>

#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

struct MeshOptions {
  // Colour of a mesh without vertex colours (linear RGB); default 0.8 grey.
  std::optional<glm::vec3> colour;
  // Micro-BRDF slope deviation sigma_rho; < 0: from the OBJ's materials
  // (Pr roughness, else Ns Phong exponent), else 0.1.
  float sigma_rho = -1;
};

// Loads a mesh. The file is untrusted: throws std::runtime_error with
// "<path>: <problem>" for an unreadable file, an unknown format, no
// triangles, non-finite coordinates or a zero extent.
std::unique_ptr<SurfaceSource> load_mesh(const std::string& path, const MeshOptions& options = {});

}  // namespace svo::voxelizer
