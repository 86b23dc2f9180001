// OpenVDB level sets in and out (vdb_io.cpp; no OpenVDB types here): a
// .vdb grid as a surface source for `svo voxelize model.vdb`, and an
// octree's finest level written as a .vdb level set for `svo export`, so
// that OpenVDB's tools (vdb_print, vdb_view, vdb_tool) open our octrees.
#pragma once

#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <memory>
#include <optional>
#include <string>

#include "svo/octree/octree.h"
#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

// Most active voxels of a .vdb grid read (from its metadata, before the
// grid is read: 4 bytes each and the tree around them).
inline constexpr double kMaxVdbVoxels = 1e9;

struct VdbOptions {
  std::string grid;                 // the grid's name; empty: the file's only float level set
  std::optional<glm::vec3> colour;  // linear RGB; default 0.8 grey
  float sigma_rho = -1;             // micro-BRDF slope deviation; < 0: 0.1
};

// Whether `path` ends in ".vdb" (any case).
bool is_vdb_path(const std::string& path);

// A float level set (class GRID_LEVEL_SET) of a .vdb file as a surface
// source: its narrow band, resampled to the voxelizer's lattice (OpenVDB's
// resampleToMatch, which rebuilds a level set's band at the new voxel size),
// gives the signed distance; the normal is the distance's gradient, the
// closest point p - d n, the colour constant. The file is untrusted.
// @throw std::runtime_error "<path>: <problem>" (one line): not a regular
//        file; not a .vdb file OpenVDB reads; no grid named options.grid
//        (the message lists the grids); with no name, not exactly one float
//        level set; a grid that is not float ("a Vec3f grid") or not a level
//        set ("a fog volume"); a transform that is not linear with uniform
//        scale; more than kMaxVdbVoxels active voxels; no zero crossing.
std::unique_ptr<SurfaceSource> load_vdb(const std::string& path, const VdbOptions& options = {});

struct VdbExport {
  uint64_t active_voxels = 0;  // voxels of the narrow band written
  double voxel_size = 0;       // scene units
  double background = 0;       // the band's half width, scene units
};

// Writes the finest level of `tree` as a .vdb file holding one FloatGrid
// named `grid_name`, class GRID_LEVEL_SET: the voxels' mean signed distance
// hbar (scene units) within kBandVoxels finest voxels of the surface,
// background kBandVoxels voxels, inside filled negative (signed flood fill);
// index (i, j, k) is lattice point origin + (i, j, k) * voxel, the
// transform says so. Written through files::OutputFile (temporary, fsync,
// rename). @throw std::runtime_error "<path>: ..." one line.
VdbExport export_vdb(const octree::Octree& tree, const std::string& path, const std::string& grid_name = "surface");

}  // namespace svo::voxelizer
