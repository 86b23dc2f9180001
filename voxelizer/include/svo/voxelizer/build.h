// From a surface to the pre-filtered bricked octree (DESIGN sections 6-7):
// finest-level values from the source, surface samples, per-level statistics
// over box footprints, sparse topology, channel choice, encoding.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "svo/octree/octree.h"
#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

struct VoxelizeOptions {
  uint32_t resolution = 256;  // finest lattice cells per axis: a power of two >= brick_size
  uint32_t brick_size = 8;    // lattice cells per brick edge: a power of two in [2, 32]
  // Progress: a stage name and the fraction of the whole job done, in [0, 1].
  std::function<void(const std::string& stage, double fraction)> progress;
  // When set, called instead of `progress`, with the stage's items done and
  // in all where the stage counts them (bricks), else 0 and 0. Called from
  // worker threads too: it must be thread-safe.
  std::function<void(const std::string& stage, double fraction, uint64_t done, uint64_t total)> progress_items;
};

struct VoxelizeReport {
  uint64_t samples = 0;           // finest surface samples
  uint64_t filled_voxels = 0;     // lattice points with surface in their footprint, all levels
  double seconds_source = 0;      // source.prepare (e.g. OpenVDB mesh to level set)
  double seconds_samples = 0;     // finest surface samples
  double seconds_statistics = 0;  // coarser levels
  double seconds_bricks = 0;      // topology, channels and brick encoding
  double seconds_total = 0;
};

// The cubic finest lattice around `bounds`: a margin of 4 voxels on each side.
Lattice make_lattice(const Box& bounds, uint32_t resolution);

// Memory voxelize() will need, bytes, from the source's surface area: the
// samples, the per-level statistics, the source's own field and the bricks.
double estimate_memory_bytes(const SurfaceSource& source, uint32_t resolution, uint32_t brick_size);

// Builds the octree. Throws std::invalid_argument for bad options and
// std::runtime_error when the surface leaves no sample at this resolution.
octree::Octree voxelize(SurfaceSource& source, const VoxelizeOptions& options, VoxelizeReport* report = nullptr);

}  // namespace svo::voxelizer
