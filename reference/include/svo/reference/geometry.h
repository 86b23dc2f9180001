// The source geometry as the reference ray tracer sees it (DESIGN section 9):
// the procedural scenes through their own distance functions, triangle
// meshes through Embree. Never the octree: the ground truth must not share
// code with what it judges.
#pragma once

#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/scenes.h"

namespace svo::reference {

// A ray's first surface point.
struct SurfaceHit {
  double t = 0;  // distance along the (unit) ray direction, scene units
  glm::dvec3 position{0};
  glm::vec3 normal{0, 0, 1};  // unit true normal, on the side the ray came from
  glm::vec3 colour{0};        // linear RGB attribute at `position`
  uint32_t material = 0;      // the scene's material at `position` (an index into its materials)
};

// Rays against a surface. Every query is thread-safe. Directions are unit
// vectors; t ranges are in scene units.
class Geometry {
 public:
  virtual ~Geometry() = default;
  // The first surface point along o + t d with t in [t_min, t_max], or nullopt.
  virtual std::optional<SurfaceHit> intersect(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const = 0;
  // Whether any surface point lies on o + t d for t in [t_min, t_max] (shadow rays).
  virtual bool occluded(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const = 0;
  // Micro-BRDF slope variance sigma_rho^2 of the material (Heitz & Neyret 5.5).
  virtual float sigma_rho2() const = 0;
  virtual voxelizer::Box bounds() const = 0;
  // The scene's materials as JSON texts (SurfaceSource::materials); empty: none of its own.
  virtual std::vector<std::string> materials() const { return {}; }
  // How far above a hit (along its normal) a shadow ray must start so that it
  // does not find the surface it leaves: a few times the precision of a hit.
  virtual double shadow_offset() const = 0;
};

// Sphere tracing of scene.distance(): steps of distance / lipschitz() from
// where the ray enters the scene's bounds (grown by 2% of their extent), a
// hit where the distance falls below 1e-6 of the extent, then Newton steps
// along the ray onto the zero crossing. Positions along the ray are kept in
// double; the scenes evaluate their functions in float. Normal: the
// normalised gradient (AnalyticScene::normal); colour: scene.colour() at the
// hit. `scene` must outlive the geometry.
std::unique_ptr<Geometry> scene_geometry(const voxelizer::AnalyticScene& scene);

// Embree (robust mode, high-quality BVH) over the mesh's triangles. The
// normal is the triangle's own (as the voxelizer uses), turned towards the
// ray's origin; the colour is the mesh's attribute at the hit's barycentric
// point (TriangleMesh::colour: texture or vertex colours, as the voxelizer
// reads them). The mesh is copied into Embree's buffers and kept for the
// attributes.
// @throw std::runtime_error "Embree: <message>" when the device or the BVH cannot be built.
std::unique_ptr<Geometry> mesh_geometry(voxelizer::TriangleMesh mesh);

}  // namespace svo::reference
