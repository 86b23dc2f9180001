#include "svo/voxelizer/statistics.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>
#include <vector>

#include "common/shared_math.h"
#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

octree::Voxel surface_statistics(std::span<const SurfaceSample> samples, std::span<const uint32_t> indices,
                                 glm::vec3 centre) {
  // Samples are uniform per unit of micro-surface area, so their plain sum of
  // normals is the projected-area vector: its direction is the mean normal.
  glm::dvec3 nsum(0);
  for (uint32_t i : indices) nsum += glm::dvec3(samples[i].normal);
  double nlen = glm::length(nsum);
  // Opposite sheets can cancel the mean normal: fall back to the first sample's.
  const glm::dvec3 nbar = nlen > 1e-6 * double(indices.size()) ? nsum / nlen : glm::dvec3(samples[indices[0]].normal);

  // Heights, slopes and attributes are distributions over the footprint's
  // projected area (the pixel's view): each sample weighs its projected area
  // n_i . nbar; facets turned away are hidden behind others and weigh 0.
  auto weight = [&](uint32_t i) { return std::max(0.0, glm::dot(glm::dvec3(samples[i].normal), nbar)); };
  double wsum = 0;
  glm::dvec3 ysum(0), asum(0);
  for (uint32_t i : indices) {
    double w = weight(i);
    wsum += w;
    ysum += w * glm::dvec3(samples[i].position);
    asum += w * glm::dvec3(samples[i].colour);
  }
  if (!(wsum > 0)) {  // nothing faces nbar (degenerate): plain means
    wsum = 0, ysum = asum = glm::dvec3(0);
    for (uint32_t i : indices) {
      wsum += 1, ysum += glm::dvec3(samples[i].position), asum += glm::dvec3(samples[i].colour);
    }
  }
  const glm::dvec3 ybar = ysum / wsum;
  const glm::dvec3 abar = asum / wsum;
  const svo::math::SvoFrame frame = svo::math::svo_tangent_frame(glm::vec3(nbar));
  const glm::dvec3 t(frame.t), b(frame.b);

  double h2 = 0, sw = 0;
  glm::dvec2 slope_sum(0);
  double sxx = 0, syy = 0, sxy = 0;
  for (uint32_t i : indices) {
    double w = weight(i);
    if (w <= 0) continue;
    double h = glm::dot(nbar, glm::dvec3(samples[i].position) - ybar);
    h2 += w * h * h;
    glm::dvec3 n(samples[i].normal);
    double nz = std::max(glm::dot(n, nbar), 0.05);  // near-vertical facets count as steep, not infinite
    glm::dvec2 s(-glm::dot(n, t) / nz, -glm::dot(n, b) / nz);
    slope_sum += w * s;
    sxx += w * s.x * s.x, syy += w * s.y * s.y, sxy += w * s.x * s.y;
    sw += w;
  }
  sw = sw > 0 ? sw : 1;
  const double var_h = h2 / sw;
  const glm::dvec2 mean_slope = slope_sum / sw;

  octree::Voxel v;
  v.nbar = glm::vec3(nbar);
  v.hbar = float(glm::dot(nbar, glm::dvec3(centre) - ybar));
  v.sigma_h = float(std::sqrt(var_h));
  v.slope_cov = glm::vec3(float(std::max(0.0, sxx / sw - mean_slope.x * mean_slope.x)),
                          float(std::max(0.0, syy / sw - mean_slope.y * mean_slope.y)),
                          float(sxy / sw - mean_slope.x * mean_slope.y));
  v.abar = glm::vec3(abar);
  v.a_s = glm::vec3(0);
  // Dominant material: scenes have few, so a short list of counts.
  std::vector<std::pair<uint32_t, uint32_t>> counts;
  for (uint32_t i : indices) {
    uint32_t m = samples[i].material;
    auto it = std::find_if(counts.begin(), counts.end(), [m](const auto& c) { return c.first == m; });
    if (it == counts.end()) {
      counts.push_back({m, 1});
    } else {
      ++it->second;
    }
  }
  auto best = counts.begin();
  for (auto it = counts.begin(); it != counts.end(); ++it) {
    if (it->second > best->second || (it->second == best->second && it->first < best->first)) best = it;
  }
  v.material = best->first;
  v.material_share = float(double(best->second) / double(indices.size()));
  if (v.sigma_h > 0) {
    glm::dvec3 num(0);
    double den = 0;
    for (uint32_t i : indices) {
      double w = weight(i);
      double h = glm::dot(nbar, glm::dvec3(samples[i].position) - ybar);
      double s = svo::math::svo_height_sigmoid(float(h), v.sigma_h);
      num += w * s * (glm::dvec3(samples[i].colour) - abar);
      den += w * s * s;
    }
    if (den > 1e-12) v.a_s = glm::vec3(num / den);
  }
  return v;
}

octree::Voxel two_sided(octree::Voxel v, float voxel, float offset) {
  const float half = 0.5f * kShellVoxels * voxel;
  v.hbar += offset * half;  // from the shell's middle
  if (v.hbar < 0) {
    // The slopes' covariance in the frame of -nbar. Heights change sign,
    // and a_s with them.
    v.slope_cov = svo::math::svo_turned_slope_covariance(v.nbar, v.slope_cov);
    v.nbar = -v.nbar;
    v.hbar = -v.hbar;
    v.a_s = -v.a_s;
  }
  v.hbar -= half;
  return v;
}

}  // namespace svo::voxelizer
