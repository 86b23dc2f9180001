// Pre-filtered statistics of the surface inside a voxel's footprint
// (Heitz & Neyret section 5.2, DESIGN section 6), from the finest-level
// surface samples that fall in it.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>

#include "svo/octree/octree.h"

namespace svo::voxelizer {

// A point of the zero set found from the finest lattice, with the normal and
// attribute there. Each carries the same weight: one per finest lattice
// point within half a voxel of the surface, i.e. a uniform area density.
struct SurfaceSample {
  glm::vec3 position;
  glm::vec3 normal;
  glm::vec3 colour;
  uint32_t material = 0;
  bool sheet = false;  // of an open surface, drawn two-sided (FinePoint::sheet)
  float offset = 0;    // where its shell lies (FinePoint::sheet_offset)
};

// Statistics of `samples[indices]` for a voxel centred at `centre`:
//  - nbar = normalize(sum n_i) (samples are uniform in area: this is the
//    projected-area vector); every other statistic weighs sample i by its
//    projected area w_i = max(0, n_i . nbar), since heights, slopes and
//    colours are distributions over the footprint as the pixel sees it;
//  - ybar = weighted mean of y_i; hbar = nbar . (centre - ybar);
//  - micro-heights h_i = nbar . (y_i - ybar), sigma_h^2 their variance;
//  - slopes of n_i in the frame svo_tangent_frame(nbar): covariance about
//    their mean (slope_cov = (var_x, var_y, cov_xy));
//  - abar = weighted mean colour; a_s = sum s(h_i)(a_i - abar) / sum s(h_i)^2 with
//    s(h) = erf(h / (sqrt(2) sigma_h)), 0 when sigma_h = 0;
//  - material: the one most samples carry (the dominant by surface area;
//    ties to the lower index), material_share: its fraction of the samples.
// Sums in double. `indices` must not be empty.
octree::Voxel surface_statistics(std::span<const SurfaceSample> samples, std::span<const uint32_t> indices,
                                 glm::vec3 centre);

// The statistics `v` of a voxel (at `centre` of lattice spacing `voxel`)
// whose surface is a sheet drawn two-sided, as the finest level draws it: a
// shell kShellVoxels `voxel` thick whose middle lies `offset` (0 to 1) of
// its half width behind the mean plane (FinePoint::sheet_offset), seen from
// the centre's side. Where the centre lies behind the shell's middle, the
// normal turns around (slopes, their covariance and the colour-height
// correlation with it); hbar becomes the distance to the shell's near face.
octree::Voxel two_sided(octree::Voxel v, float voxel, float offset = 0);

}  // namespace svo::voxelizer
