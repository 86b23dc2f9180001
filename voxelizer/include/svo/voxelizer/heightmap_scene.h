// A height field from an image (paper Fig. 9, bottom: "a real-world texture
// which is not really Gaussian"): the surface z = amplitude (map(x, y) -
// mean), bilinear between the map's samples over [-1, 1]^2, closed below
// into a slab like HeightfieldScene, coloured by height as
// a(h) = abar + a_s erf(h / (sqrt(2) sigma_h)). Its statistics are measured
// from the map itself (statistics()), not assumed Gaussian.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "svo/voxelizer/scenes.h"

namespace svo::voxelizer {

// Samples of a scalar map, row-major, row 0 at y = -1 (the image's bottom
// row) and column 0 at x = -1.
struct HeightMap {
  int width = 0, height = 0;
  std::vector<float> values;
  float at(int i, int j) const { return values[size_t(j) * size_t(width) + size_t(i)]; }
};

// The luminance (Rec. 709 weights of linear RGB; 8-bit files decoded from
// sRGB) of an image file read through OpenImageIO, box-filtered down to at
// most `size` samples along its longer side (size 0: as stored).
// Untrusted input.
// @throw std::runtime_error "<path>: <why>" when the file cannot be read, or
//        is smaller than 2x2 samples.
HeightMap read_height_map(const std::string& path, int size);

// Area statistics of the surface over a region of the (x, y) plane,
// integrated exactly for the bilinear surface (2 x 2 Gauss points per map
// cell: heights and slopes are polynomials of degree <= 2 per axis there);
// the colour's statistics with the same points (DESIGN section 6: abar the
// mean, a_s the projection of a - abar on s(h)).
struct SurfaceStatistics {
  double area = 0;
  double mean_height = 0;        // relative to the map's own mean (0 over the whole map)
  double height_variance = 0;    // sigma_h^2 about mean_height
  double skewness = 0;           // third standardised moment of the height (0 for a Gaussian)
  double excess_kurtosis = 0;    // fourth standardised moment - 3 (0 for a Gaussian)
  glm::dvec2 slope_variance{0};  // of dz/dx and dz/dy, about their means
  glm::dvec3 abar{0};
  glm::dvec3 a_s{0};
};

class HeightmapScene : public AnalyticScene {
 public:
  // `map` needs at least 2 x 2 samples; amplitude > 0, scene units per map
  // unit. Throws std::invalid_argument otherwise.
  HeightmapScene(HeightMap map, float amplitude, glm::vec3 abar, glm::vec3 a_s);

  float height(float x, float y) const;
  glm::vec2 gradient(float x, float y) const;
  // Over the region [lo, hi] (clamped to [-1, 1]^2). Throws
  // std::invalid_argument for an empty region.
  SurfaceStatistics statistics(glm::vec2 lo, glm::vec2 hi) const;
  float sigma_h() const { return sigma_h_; }  // over the whole map: the colour's scale
  float amplitude() const { return amplitude_; }
  const HeightMap& map() const { return map_; }

  float distance(glm::vec3 p) const override { return distance_gradient(p).w; }
  glm::vec4 distance_gradient(glm::vec3 p) const override;
  float lipschitz() const override { return lipschitz_; }
  glm::vec3 colour(glm::vec3 surface_point) const override;
  Box bounds() const override;
  std::string name() const override { return "heightmap"; }

 private:
  // Cell (ci, cj) and the coordinates (u, v) in [0, 1] within it of (x, y).
  void locate(float x, float y, int& ci, int& cj, float& u, float& v) const;
  static constexpr float kBottom = -0.6f;
  HeightMap map_;  // already scaled: amplitude (value - mean)
  float amplitude_;
  glm::vec3 abar_, a_s_;
  float sigma_h_ = 0;
  float lipschitz_ = 1;
  float max_height_ = 0;
};

}  // namespace svo::voxelizer
