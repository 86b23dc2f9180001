// What the voxelizer needs from a surface: its bounds, and on the finest
// lattice the signed distance with, near the surface, the closest surface
// point, the normal and the attribute there. Meshes (through OpenVDB) and
// the procedural scenes both provide it.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "svo/octree/octree.h"

namespace svo::voxelizer {

struct Box {
  glm::vec3 lo{0, 0, 0};
  glm::vec3 hi{0, 0, 0};
};

// The finest lattice: point (i, j, k) sits at origin + (i, j, k) * voxel,
// 0 <= i, j, k <= resolution.
struct Lattice {
  glm::dvec3 origin{0, 0, 0};
  double voxel = 1;
  uint32_t resolution = 1;
  glm::dvec3 position(glm::ivec3 index) const;
};

// Width of the band around the surface, in finest voxels, inside which a
// source gives exact values (distance, closest point, normal, colour).
constexpr float kBandVoxels = 3.0f;

// Thickness of the shell drawn around each triangle of an open surface, in
// voxels of each level. The normal turns around inside the shell, halfway.
// Where the shell lies inside the volume a triangle bounds, its width is
// what a hole's rim shows (a cap across the wall) and how far the inside
// seen through the hole is pushed back; on a sheet, half of it widens
// every silhouette. Every open libcgal-demo mesh at 128^3, far view: 1.25
// against 2 raised PSNR on 40 of 44 (median 29.4 to 31.3 dB), but a box
// whose faces lie on lattice planes lost 9 dB to bands, until the tracer
// turned the shell's far half towards the eye (svo_turn_to_eye,
// shaders/common/shading.glsl). docs/RESULTS.md, "Open meshes, round
// four". (When every shell was centred on its triangle, 1.5 left dark
// specks all over the lion's face and 2 was chosen.) Above 1, the
// interpolation always dips below zero.
constexpr float kShellVoxels = 1.25f;
// How far from a sheet, in voxels, a lattice point still matters: within
// half a voxel of the shell's faces, which lie up to kShellVoxels from it
// where the shell lies on one side (FinePoint::sheet_offset). Every brick
// holding such a point is stored (and the mesh's candidate bricks reach
// that far).
constexpr float kShellFaceReach = kShellVoxels + 0.5f;

struct FinePoint {
  float distance = 0;          // signed, negative inside; outside the band at least kBandVoxels voxels in magnitude
                               // (an open surface's shell: within kBandVoxels + kShellVoxels voxels of its
                               // triangles, the distance to the shell; beyond, at least kBandVoxels voxels)
  bool near = false;           // |distance| < kBandVoxels voxels: the fields below are set
  glm::vec3 closest{0, 0, 0};  // closest surface point
  glm::vec3 normal{0, 0, 1};   // unit surface normal at `closest`
  glm::vec3 colour{0, 0, 0};   // linear RGB attribute at `closest`
  uint32_t material = 0;       // index into materials() of the surface at `closest`
  // >= 0: the point lies beside an open surface, drawn as a thin shell
  // around each triangle so that both of its sides are outside: `distance`
  // and `normal` are the shell's (the normal is the unsigned distance's
  // gradient: it faces the point's side, and turns around the sheet's
  // boundary edges), `sheet` the unsigned distance to the triangle itself
  // and `sheet_normal` the triangle's own normal, which coarser levels
  // average; where the triangle bounds a volume, the normal points out of
  // it and the shell lies inside, its middle `sheet_offset` (0 to 1) of
  // half the shell's width behind the triangle (1: its outer face on it).
  float sheet = -1;
  glm::vec3 sheet_normal{0, 0, 1};
  float sheet_offset = 0;
  // Where shading should read another normal than `normal` (zero: none):
  // on an open edge's cap, the face's normal turned to the point's side,
  // while `normal`, the distance's gradient, turns round the edge for the
  // masks (SurfaceSource::shading_normals).
  glm::vec3 shading_normal{0, 0, 0};
};

class SurfaceSource {
 public:
  virtual ~SurfaceSource() = default;
  // Axis-aligned bounds of the surface.
  virtual Box bounds() const = 0;
  // Micro-BRDF slope variance of the material (Heitz & Neyret 5.5).
  virtual float sigma_rho2() const = 0;
  // Surface area (an upper estimate is fine), scene units squared: sizes the
  // memory estimate before anything is allocated.
  virtual double surface_area() const = 0;
  // Memory the source itself needs per finest surface sample (e.g. the
  // OpenVDB narrow band), bytes.
  virtual double bytes_per_sample() const { return 0; }
  // Procedural detail octaves carried by the surface (octaves = 0: none).
  // The values the source gives hold only the octaves the lattice can draw;
  // the voxelizer folds the others into the statistics and records this in
  // the octree for the renderer (shaders/common/detail.glsl).
  virtual octree::Detail detail() const { return {}; }
  // The surface's materials as JSON texts (DESIGN 10.2), carried into the
  // octree; FinePoint::material indexes them. Empty: the scene has none of
  // its own (the renderer's --material or built-in one applies).
  virtual std::vector<std::string> materials() const { return {}; }
  // What was decided about the surface's inside and outside, one line
  // (TriangleMesh::surface); empty where there was nothing to decide.
  virtual std::string surface() const { return {}; }
  // Whether some of the surface is drawn two-sided, as a thin shell
  // (TriangleMesh::two_sided): the octree records it, and a defocused
  // frame splits its lens finer there (render::lens_parts).
  virtual bool two_sided() const { return false; }
  // Whether some FinePoint::shading_normal may be set: the octree then
  // stores a shading normal channel.
  virtual bool shading_normals() const { return false; }
  // Called once before any other query below, with the lattice to serve.
  virtual void prepare(const Lattice& lattice) = 0;
  // Finest-level bricks (`brick_size` cells, brick b owns lattice points
  // b * brick_size + [0, brick_size)) that may own a point within half a
  // voxel of the surface. May over-approximate, never miss one.
  virtual std::vector<glm::ivec3> candidate_bricks(uint32_t brick_size) const = 0;
  // Evaluates lattice points lo..hi (inclusive, x fastest, then y, then z)
  // into `out`. Points outside 0..resolution are allowed. Thread-safe.
  // `near_within` (scene units, at most the band) narrows which points get
  // the closest point, normal and colour, for callers that need fewer.
  virtual void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const = 0;
  void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out) const { evaluate(lo, hi, out, 1e30f); }
};

}  // namespace svo::voxelizer
