// Procedural detail octaves (issue 6): what the voxelizer folds into a
// voxel's statistics against the same statistics measured on the detail
// evaluated explicitly, and the renderer's consistency where an octave
// changes from statistics to explicit drawing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "common/shared_math.h"
#include "svo/octree/sampler.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"

namespace {

using namespace svo;

// The plane z = 0 across the whole lattice, one colour: all the structure
// comes from the detail.
class PlaneScene : public voxelizer::AnalyticScene {
 public:
  explicit PlaneScene(glm::vec3 colour_slope) : colour_slope_(colour_slope) { set_sigma_rho2(0.01f); }
  float distance(glm::vec3 p) const override { return p.z; }
  glm::vec4 distance_gradient(glm::vec3 p) const override { return glm::vec4(0, 0, 1, p.z); }
  glm::vec3 colour(glm::vec3) const override { return glm::vec3(0.5f, 0.4f, 0.3f); }
  glm::vec3 colour_height_slope() const override { return colour_slope_; }
  std::string name() const override { return "plane"; }
  voxelizer::Box bounds() const override { return {glm::vec3(-1, -1, -0.05f), glm::vec3(1, 1, 0.05f)}; }

 private:
  glm::vec3 colour_slope_;
};

octree::Detail plane_detail(const voxelizer::AnalyticScene& scene, uint32_t octaves, float wavelength,
                            float amplitude_ratio = 0.1f) {
  return voxelizer::make_detail(scene, octaves, amplitude_ratio * wavelength, wavelength, 7);
}

math::SvoDetail shared(const octree::Detail& d) { return {d.octaves, d.seed, d.amplitude, d.wavelength, d.gain}; }

// Statistics (statistics.h's definitions) of the plane displaced by every
// octave of `d`, over the box footprint of side `side` centred on (cx, cy):
// the surface z = D(x, y, z) on an n x n grid (uniform in projected area),
// its heights about their mean, its slopes, colour + colour_slope z.
struct Measured {
  double height_variance = 0;
  glm::dvec2 slope_variance{0};
  glm::dvec3 a_s{0};
};

Measured measure(const octree::Detail& d, double cx, double cy, double side, int n) {
  math::SvoDetail sd = shared(d);
  std::vector<double> z(size_t(n) * n);
  std::vector<glm::dvec2> slope(z.size());
  double mean = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      float x = float(cx + side * ((i + 0.5) / n - 0.5)), y = float(cy + side * ((j + 0.5) / n - 0.5));
      float h = 0;
      glm::vec4 g(0);
      for (int it = 0; it < 8; ++it) {  // z = D(x, y, z): a contraction here (|dD/dz| < 0.4)
        g = math::svo_detail_displacement(sd, glm::vec3(x, y, h), 0.0f, 3.0e38f);
        h = g.w;
      }
      size_t k = size_t(j) * n + i;
      z[k] = h;
      // Implicit differentiation of z - D(x, y, z) = 0.
      slope[k] = glm::dvec2(g.x, g.y) / (1.0 - double(g.z));
      mean += h;
    }
  mean /= double(z.size());
  Measured m;
  glm::dvec2 slope_mean(0);
  for (size_t k = 0; k < z.size(); ++k) {
    m.height_variance += (z[k] - mean) * (z[k] - mean);
    slope_mean += slope[k];
  }
  m.height_variance /= double(z.size());
  slope_mean /= double(z.size());
  for (size_t k = 0; k < z.size(); ++k) m.slope_variance += (slope[k] - slope_mean) * (slope[k] - slope_mean);
  m.slope_variance /= double(z.size());
  double sigma = std::sqrt(m.height_variance), sxx = 0;
  glm::dvec3 sxa(0);
  for (size_t k = 0; k < z.size(); ++k) {
    double s = std::erf((z[k] - mean) / (std::sqrt(2.0) * sigma));
    sxx += s * s;
    sxa += s * glm::dvec3(d.colour_slope) * (z[k] - mean);
  }
  m.a_s = sxa / sxx;
  return m;
}

// Octaves finer than the lattice are folded into the statistics; measured on
// the detail itself, over the same footprints, they agree within 10% (mean
// over the voxels of the plane's interior; the quantised channels are within
// 2.2% of what the voxelizer computed).
TEST(Detail, FoldedStatisticsMatchTheExplicitDetail) {
  auto base = std::make_unique<PlaneScene>(glm::vec3(300.0f, 150.0f, -150.0f));
  // Resolution 32 over ~2.6 units: voxels of ~0.08; octaves of wavelength
  // 0.016 and below (every one under 4 voxel / sqrt(2): all statistics).
  octree::Detail detail = plane_detail(*base, 4, 0.016f);
  voxelizer::DetailedScene scene(std::move(base), detail, false);
  voxelizer::VoxelizeOptions options;
  options.resolution = 32;
  octree::Octree tree = voxelizer::voxelize(scene, options);
  ASSERT_EQ(tree.detail.octaves, 4u);

  for (uint32_t depth : {tree.depth_count - 2, tree.depth_count - 1}) {
    const float voxel = tree.voxel_size(depth);
    const int cells = int(tree.brick_size << depth);
    double folded_h = 0, measured_h = 0;
    glm::dvec2 folded_s(0), measured_s(0);
    glm::dvec3 folded_a(0), measured_a(0);
    int count = 0;
    for (int j = 0; j <= cells; ++j)
      for (int i = 0; i <= cells; ++i) {
        glm::ivec3 p(i, j, cells / 2);
        glm::vec3 at = octree::lattice_position(tree, depth, p);
        if (std::abs(at.x) > 0.8f || std::abs(at.y) > 0.8f) continue;
        ASSERT_NEAR(at.z, 0.0f, 1e-5f);
        std::optional<octree::Voxel> v = octree::lattice_voxel(tree, depth, p);
        ASSERT_TRUE(v.has_value());
        Measured m = measure(detail, at.x, at.y, voxel, 48);
        folded_h += double(v->sigma_h) * v->sigma_h;
        folded_s += glm::dvec2(v->slope_cov.x, v->slope_cov.y);
        folded_a += glm::dvec3(v->a_s);
        measured_h += m.height_variance;
        measured_s += m.slope_variance;
        measured_a += m.a_s;
        ++count;
      }
    ASSERT_GT(count, 8) << "depth " << depth;
    SCOPED_TRACE("depth " + std::to_string(depth) + ", voxels " + std::to_string(count));
    std::printf("depth %u (%d voxels): folded / measured: height variance %.3f, slope variance %.3f %.3f, a_s %.3f %.3f %.3f\n",
                depth, count, folded_h / measured_h, folded_s.x / measured_s.x, folded_s.y / measured_s.y,
                folded_a.x / measured_a.x, folded_a.y / measured_a.y, folded_a.z / measured_a.z);
    EXPECT_NEAR(folded_h / measured_h, 1.0, 0.10);
    EXPECT_NEAR(folded_s.x / measured_s.x, 1.0, 0.10);
    EXPECT_NEAR(folded_s.y / measured_s.y, 1.0, 0.10);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(folded_a[c] / measured_a[c], 1.0, 0.10) << "a_s channel " << c;
  }
}

// The same view at 24, 48, 96 and 192 pixels: the pixel footprint halves
// each time and octave 0, then octave 1, change from statistics to explicit
// drawing; the mean colour of the frame (the same patch of surface) must
// not change by more than 2%, nor differ from the ground truth's by more.
TEST(Detail, MeanColourHoldsAcrossTheExplicitStatisticalTransition) {
  auto base = std::make_unique<PlaneScene>(glm::vec3(80.0f, 40.0f, -40.0f));
  octree::Detail detail = plane_detail(*base, 4, 0.02f, 0.15f);
  voxelizer::DetailedScene scene(std::move(base), detail, false);
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(scene, options);

  render::RenderSettings s;
  s.camera.target = glm::vec3(0.1f, -0.05f, 0.0f);
  // 50 degrees from the normal, 1 unit away: the frame spans ~0.25 units.
  const float angle = glm::radians(50.0f);
  s.camera.eye = s.camera.target + glm::vec3(0.0f, -std::sin(angle), std::cos(angle));
  s.camera.up = glm::vec3(0, 0, 1);
  s.camera.fov_deg = 14;
  s.lights[0].vector = glm::vec3(0.3f, 0.4f, 1.0f);
  s.lights[0].radiance = glm::vec3(2.0f);
  s.specular = 0.04f;
  std::vector<glm::dvec3> means;
  std::vector<float> radii;
  for (uint32_t size : {24u, 48u, 96u, 192u}) {
    s.width = s.height = size;
    s.gbuffer = true;
    render::Frame f = render::render_cpu(tree, s);
    glm::dvec3 sum(0);
    double slope_variance = 0;
    for (size_t i = 0; i < f.colour.size(); ++i) {
      ASSERT_EQ(f.colour[i].a, 1.0f);
      sum += glm::dvec3(f.colour[i]);
      slope_variance += f.gbuffer[i].slope_variance();
    }
    slope_variance /= double(f.colour.size());
    // The slopes left as statistics: the octaves finer than the footprint
    // (the plane itself has none) and the micro-BRDF's.
    const float r = 2.0f * std::tan(glm::radians(s.camera.fov_deg) / 2) / float(size) / 1.7724539f;
    const float left = math::svo_detail_moved_variance(shared(detail), 0.0f, r).y + tree.sigma_rho2;
    EXPECT_NEAR(slope_variance / left, 1.0, 0.15) << size << " pixels: slope variance " << slope_variance;
    means.push_back(sum / double(f.colour.size()));
    std::printf("%u pixels: mean colour %.5f %.5f %.5f\n", size, means.back().x, means.back().y, means.back().z);
    radii.push_back(r);
  }
  // Ground truth of the same view: every octave traced explicitly.
  voxelizer::DetailedScene truth(std::make_unique<PlaneScene>(glm::vec3(80.0f, 40.0f, -40.0f)), detail, true);
  auto geometry = reference::scene_geometry(truth);
  reference::ReferenceSettings rs;
  rs.render = s;
  rs.render.width = rs.render.height = 32;
  rs.spp = 64;
  render::Frame f = reference::render_reference(*geometry, rs);
  glm::dvec3 truth_mean(0);
  for (const auto& c : f.colour) truth_mean += glm::dvec3(c);
  truth_mean /= double(f.colour.size());
  std::printf("reference: mean colour %.5f %.5f %.5f\n", truth_mean.x, truth_mean.y, truth_mean.z);
  // Octave 0 (wavelength 0.02) starts to be drawn at radius 0.02 / F and is
  // whole from 0.02 / 2F (F = SVO_DETAIL_DRAWN_FROM): the sizes straddle
  // that whole transition and the start of octave 1's.
  EXPECT_GT(radii.front(), 0.02f / math::SVO_DETAIL_DRAWN_FROM);
  EXPECT_LT(radii.back(), 0.02f / (2.0f * math::SVO_DETAIL_DRAWN_FROM));
  EXPECT_LT(radii.back(), 0.01f / math::SVO_DETAIL_DRAWN_FROM);
  for (size_t i = 1; i < means.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(means[i][c] / means[0][c], 1.0, 0.02) << "from 24 to " << (24 << i) << " pixels, channel " << c;
      EXPECT_NEAR(means[i][c] / truth_mean[c], 1.0, 0.02) << (24 << i) << " pixels against the truth, channel " << c;
      EXPECT_NEAR(means[i][c] / means[i - 1][c], 1.0, 0.02) << "from " << (24 << (i - 1)) << " to " << (24 << i)
                                                            << " pixels, channel " << c;
    }
  }
}

}  // namespace
