// Pre-filtered statistics (DESIGN section 6) on surfaces with a known answer:
// a plane, a Gaussian height field, colour a = abar + a_s s(h), and a direct
// recomputation from the finest samples.
#include "svo/voxelizer/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "common/shared_math.h"
#include "lattice_points.h"
#include "svo/octree/sampler.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"

namespace {
using namespace svo;
using voxelizer::AnalyticScene;
using voxelizer::Box;

// A tilted plane, clipped to a cube so that it is a closed solid.
class TiltedSlab : public AnalyticScene {
 public:
  glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.2f, 1.0f));
  float offset = 0.05f;
  float plane(glm::vec3 p) const { return glm::dot(n, p) - offset; }
  float distance(glm::vec3 p) const override {
    float box = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) - 0.8f;
    return std::max(plane(p), box);
  }
  glm::vec3 colour(glm::vec3) const override { return glm::vec3(0.5f, 0.4f, 0.3f); }
  Box bounds() const override { return {glm::vec3(-0.8f), glm::vec3(0.8f)}; }
  std::string name() const override { return "tilted-slab"; }
};

TEST(Statistics, PlaneHasZeroVariancesAndExactDistanceAtEveryLevel) {
  TiltedSlab slab;
  voxelizer::VoxelizeOptions options;
  options.resolution = 128;
  options.brick_size = 8;
  octree::Octree tree = voxelizer::voxelize(slab, options);
  // Constant colour: stored once in the header, not per voxel.
  EXPECT_LT(tree.channel_index(octree::Channel::Colour), 0);
  int checked = 0;
  for (uint32_t d = 0; d < tree.depth_count; ++d) {
    float s = tree.voxel_size(d);
    for (const auto& [index, p] : test::lattice_points(tree, d)) {
      // Away from the clipping faces, and close enough to the plane to be filled.
      if (glm::length(p) > 0.45f || std::abs(slab.plane(p)) > 0.49f * s) continue;
      auto v = octree::lattice_voxel(tree, d, index);
      ASSERT_TRUE(v.has_value()) << "depth " << d << " at " << index.x << "," << index.y << "," << index.z;
      EXPECT_LT(v->sigma_h * v->sigma_h, 1e-6f);
      EXPECT_LT(v->slope_cov.x + v->slope_cov.y, 1e-6f);
      EXPECT_NEAR(v->hbar, slab.plane(p), 1e-3f * s) << "depth " << d;
      EXPECT_GT(glm::dot(v->nbar, slab.n), 0.99999f);
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

// Variances of the height field over the square footprint of a box, by
// quadrature of the closed form: heights about the best plane, slopes about
// their mean (what the voxel statistics estimate from samples).
struct PatchTruth {
  double height_variance, slope_variance;
};
PatchTruth patch_truth(const voxelizer::HeightfieldScene& f, float cx, float cy, float side) {
  const int n = 96;
  std::vector<double> xs, ys, hs;
  glm::dvec2 gsum(0);
  double hsum = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      float x = cx + side * ((i + 0.5f) / n - 0.5f), y = cy + side * ((j + 0.5f) / n - 0.5f);
      xs.push_back(x), ys.push_back(y), hs.push_back(f.height(x, y));
      hsum += hs.back();
      gsum += glm::dvec2(f.gradient(x, y));
    }
  double m = n * n;
  glm::dvec2 g = gsum / m;
  double h0 = hsum / m, hv = 0, sv = 0;
  for (size_t k = 0; k < hs.size(); ++k) {
    double r = hs[k] - (h0 + g.x * (xs[k] - cx) + g.y * (ys[k] - cy));
    hv += r * r;
    glm::dvec2 d = glm::dvec2(f.gradient(float(xs[k]), float(ys[k]))) - g;
    sv += glm::dot(d, d);
  }
  return {hv / m, sv / m};
}

TEST(Statistics, GaussianHeightFieldGivesBackItsVariancesAndColour) {
  const glm::vec3 abar(0.45f, 0.4f, 0.3f), a_s(0.3f, -0.2f, 0.15f);
  // Bumps resolved at the finest level (radius of curvature about 8 voxels),
  // much smaller than the boxes of depths 0 and 1 (0.52 and 0.26 against
  // wavelengths of 0.06 to 0.12).
  voxelizer::HeightfieldScene field(64, 0.06f, 0.12f, 0.003f, 21, abar, a_s);
  voxelizer::VoxelizeOptions options;
  options.resolution = 256;
  options.brick_size = 4;
  octree::Octree tree = voxelizer::voxelize(field, options);
  ASSERT_GE(tree.channel_index(octree::Channel::ColourSlope), 0) << "colour correlates with height";
  for (uint32_t d = 0; d <= 1; ++d) {
    float s = tree.voxel_size(d);
    double sh2 = 0, slope2 = 0, true_sh2 = 0, true_slope2 = 0;
    glm::dvec3 mean_abar(0), mean_as(0);
    int count = 0;
    for (const auto& [index, p] : test::lattice_points(tree, d)) {
      // Boxes that hold the mean surface z = 0 and lie inside the tile.
      if (std::max(std::abs(p.x), std::abs(p.y)) > 0.98f - 0.5f * s || std::abs(p.z) > 0.4f * s) continue;
      auto v = octree::lattice_voxel(tree, d, index);
      ASSERT_TRUE(v.has_value());
      PatchTruth truth = patch_truth(field, p.x, p.y, s);
      sh2 += v->sigma_h * v->sigma_h;
      slope2 += v->slope_cov.x + v->slope_cov.y;
      true_sh2 += truth.height_variance;
      true_slope2 += truth.slope_variance;
      mean_abar += glm::dvec3(v->abar);
      mean_as += glm::dvec3(v->a_s);
      ++count;
    }
    ASSERT_GE(count, 9) << "depth " << d;
    double generating_slope = field.slope_variance().x + field.slope_variance().y;
    EXPECT_NEAR(sh2 / true_sh2, 1.0, 0.05) << "depth " << d;
    EXPECT_NEAR(slope2 / true_slope2, 1.0, 0.05) << "depth " << d;
    // The footprints are large enough for the patches to carry the generating variances.
    EXPECT_NEAR(sh2 / count / field.height_variance(), 1.0, 0.1) << "depth " << d;
    EXPECT_NEAR(slope2 / count / generating_slope, 1.0, 0.1) << "depth " << d;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(mean_abar[c] / count, abar[c], 0.05 * std::abs(abar[c])) << "depth " << d << " channel " << c;
      EXPECT_NEAR(mean_as[c] / count, a_s[c], 0.05 * std::abs(a_s[c])) << "depth " << d << " channel " << c;
    }
    std::printf(
        "depth %u (box %.3f, %d voxels): sigma_h^2 %.4g (patches %.4g, generating %.4g), slope variance %.4g "
        "(patches %.4g, generating %.4g), a_s %.3f %.3f %.3f\n",
        d, s, count, sh2 / count, true_sh2 / count, field.height_variance(), slope2 / count, true_slope2 / count,
        generating_slope, mean_as.x / count, mean_as.y / count, mean_as.z / count);
  }
}

}  // namespace

namespace {

// The stored statistics of a coarse lattice point equal a direct computation
// from the finest surface samples inside its box: recollect the samples by
// brute force over the finest lattice and recompute without the octree.
TEST(Statistics, LevelEqualsDirectComputationFromTheFinestSamples) {
  auto scene = voxelizer::make_scene("bumpy-sphere");
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  options.brick_size = 8;
  octree::Octree tree = voxelizer::voxelize(*scene, options);
  const uint32_t D = tree.depth_count - 1;
  const int N = int(tree.finest_resolution());
  const float h = tree.voxel_size(D);
  // Samples: every finest lattice point within half a voxel of the surface.
  std::vector<voxelizer::SurfaceSample> samples;
  std::vector<voxelizer::FinePoint> points;
  scene->evaluate(glm::ivec3(0), glm::ivec3(N), points);
  for (const auto& p : points) {
    if (p.near && std::abs(p.distance) <= 0.5f * h) samples.push_back({p.closest, p.normal, p.colour});
  }
  ASSERT_GT(samples.size(), 1000u);
  int checked = 0;
  for (uint32_t d = 1; d < D; ++d) {
    const float s = tree.voxel_size(d);
    for (const auto& [index, c] : test::lattice_points(tree, d, glm::ivec3(1, 2, 3))) {
      std::vector<uint32_t> inside;
      for (uint32_t i = 0; i < samples.size(); ++i) {
        glm::vec3 q = (samples[i].position - c) / s;
        if (std::abs(q.x) < 0.5f && std::abs(q.y) < 0.5f && std::abs(q.z) < 0.5f) inside.push_back(i);
      }
      if (inside.size() < 8) continue;  // skip boxes whose membership rounding could change
      auto v = octree::lattice_voxel(tree, d, index);
      ASSERT_TRUE(v.has_value());
      octree::Voxel e = voxelizer::surface_statistics(samples, inside, c);
      EXPECT_NEAR(v->hbar, e.hbar, 1e-4f * s);
      EXPECT_GT(glm::dot(v->nbar, e.nbar), 0.9999f);
      EXPECT_NEAR(v->sigma_h, e.sigma_h, 0.025f * e.sigma_h + 1e-5f * s);  // 8-bit log: +-2.2%
      float tv = v->slope_cov.x + v->slope_cov.y, te = e.slope_cov.x + e.slope_cov.y;
      EXPECT_NEAR(tv, te, 0.05f * te + 1e-6f);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(v->abar[k], e.abar[k], 0.01f);
        EXPECT_NEAR(v->a_s[k], e.a_s[k], 0.01f);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
}

}  // namespace

#include <filesystem>

#include "svo/octree/svo_file.h"

namespace {

// Grooves along the cylinder's axis: slopes vary across the grooves only, so
// the file models anisotropic slopes, and coarse voxels on the side show it.
TEST(Statistics, GroovedCylinderIsAnisotropic) {
  auto scene = voxelizer::make_scene("grooved-cylinder");
  voxelizer::VoxelizeOptions options;
  options.resolution = 128;
  octree::Octree tree = voxelizer::voxelize(*scene, options);
  ASSERT_GE(tree.channel_index(octree::Channel::SlopeCov), 0);
  EXPECT_LT(tree.channel_index(octree::Channel::SlopeDev), 0);
  const uint32_t d = 2;
  int strong = 0, sloped = 0;
  for (const auto& [index, p] : test::lattice_points(tree, d)) {
    float rho = std::sqrt(p.x * p.x + p.z * p.z);
    if (std::abs(p.y) > 0.3f || std::abs(rho - 0.5f) > 0.3f * tree.voxel_size(d)) continue;
    auto v = octree::lattice_voxel(tree, d, index);
    ASSERT_TRUE(v.has_value());
    glm::vec3 c = v->slope_cov;
    float trace = c.x + c.y, diff = c.x - c.y, root = std::sqrt(diff * diff + 4 * c.z * c.z);
    if (trace < 1e-3f) continue;
    ++sloped;
    if (0.5f * (trace + root) > 10.0f * std::max(0.5f * (trace - root), 1e-9f)) ++strong;
  }
  EXPECT_GT(sloped, 20);
  EXPECT_GT(strong, sloped * 8 / 10) << strong << " of " << sloped;
}

// A voxelized scene survives the file bit for bit.
TEST(Statistics, VoxelizedSceneRoundTripsThroughTheFile) {
  auto scene = voxelizer::make_scene("bumpy-sphere");
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  octree::Octree tree = voxelizer::voxelize(*scene, options);
  auto path = std::filesystem::temp_directory_path() / ("svo_roundtrip_" + std::to_string(::getpid()) + ".svo");
  octree::write_svo(path.string(), tree);
  octree::Octree back = octree::load_svo(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(back.brick_count, tree.brick_count);
  EXPECT_EQ(back.depth_first_node, tree.depth_first_node);
  ASSERT_EQ(back.nodes.size(), tree.nodes.size());
  for (size_t i = 0; i < tree.nodes.size(); ++i) {
    ASSERT_EQ(back.nodes[i].children, tree.nodes[i].children);
    ASSERT_EQ(back.nodes[i].brick, tree.nodes[i].brick);
  }
  EXPECT_EQ(back.brick_data, tree.brick_data);
  EXPECT_EQ(back.origin, tree.origin);
  EXPECT_EQ(back.size, tree.size);
}

}  // namespace

namespace {

// The dominant material by covered area (samples are uniform in area) and
// its share; ties go to the lower index.
TEST(Statistics, DominantMaterialAndItsShare) {
  std::vector<voxelizer::SurfaceSample> samples;
  for (uint32_t m : {3u, 1u, 3u, 3u, 2u, 1u, 3u, 3u}) {
    samples.push_back({glm::vec3(0.01f * float(samples.size()), 0, 0), glm::vec3(0, 0, 1), glm::vec3(0.5f), m});
  }
  std::vector<uint32_t> all{0, 1, 2, 3, 4, 5, 6, 7};
  octree::Voxel v = voxelizer::surface_statistics(samples, all, glm::vec3(0));
  EXPECT_EQ(v.material, 3u);
  EXPECT_FLOAT_EQ(v.material_share, 5.0f / 8.0f);
  std::vector<uint32_t> tie{1, 4, 0, 5};  // materials 1, 2, 3, 1: 1 leads
  v = voxelizer::surface_statistics(samples, tie, glm::vec3(0));
  EXPECT_EQ(v.material, 1u);
  EXPECT_FLOAT_EQ(v.material_share, 0.5f);
  std::vector<uint32_t> even{1, 4};  // materials 1 and 2, one each: the lower index
  v = voxelizer::surface_statistics(samples, even, glm::vec3(0));
  EXPECT_EQ(v.material, 1u);
  EXPECT_FLOAT_EQ(v.material_share, 0.5f);
}

// The built-in scene with five materials: the octree carries them, and at
// the finest level each sphere's voxels name its material, whole.
TEST(Statistics, MaterialSpheresCarryTheirMaterials) {
  auto scene = voxelizer::make_scene("material-spheres");
  voxelizer::VoxelizeOptions options;
  options.resolution = 64;
  const octree::Octree tree = voxelizer::voxelize(*scene, options);
  ASSERT_EQ(tree.materials, scene->materials());
  ASSERT_EQ(tree.materials.size(), 5u);
  ASSERT_GE(tree.channel_index(octree::Channel::Material), 0);
  const uint32_t finest = tree.depth_count - 1;
  for (int i = 0; i < 3; ++i) {
    // The top of sphere i (centre (0.75 (i - 1), 0.27, 0), radius 0.3).
    const glm::vec3 top(0.75f * float(i - 1), 0.57f, 0.0f);
    const glm::ivec3 p = glm::ivec3(glm::round((top - tree.origin) / tree.voxel_size(finest)));
    const auto v = octree::lattice_voxel(tree, finest, p);
    ASSERT_TRUE(v.has_value()) << i;
    EXPECT_EQ(v->material, uint32_t(2 + i));
    EXPECT_FLOAT_EQ(v->material_share, 1.0f);
  }
}

// A sheet's voxel seen from behind its mean plane: the normal turns around,
// the slope covariance is the same distribution in the turned frame (trace
// and determinant kept), the colour-height correlation changes sign, and
// hbar is the distance to the shell's near face.
TEST(Statistics, TwoSidedTurnsAVoxelBehindItsSheet) {
  octree::Voxel v;
  v.nbar = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  v.hbar = -0.9f;
  v.slope_cov = glm::vec3(0.04f, 0.01f, 0.012f);
  v.a_s = glm::vec3(0.1f, -0.2f, 0.05f);
  const octree::Voxel t = voxelizer::two_sided(v, 0.5f);
  EXPECT_NEAR(glm::length(t.nbar + v.nbar), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(t.hbar, 0.9f - 0.5f * voxelizer::kShellVoxels * 0.5f);
  EXPECT_NEAR(t.slope_cov.x + t.slope_cov.y, 0.05f, 1e-6f);
  EXPECT_NEAR(t.slope_cov.x * t.slope_cov.y - t.slope_cov.z * t.slope_cov.z, 0.04f * 0.01f - 0.012f * 0.012f, 1e-7f);
  EXPECT_EQ(t.a_s, -v.a_s);
  // In front of it: only the shell's offset.
  v.hbar = 0.9f;
  const octree::Voxel f = voxelizer::two_sided(v, 0.5f);
  EXPECT_EQ(f.nbar, v.nbar);
  EXPECT_EQ(f.slope_cov, v.slope_cov);
  EXPECT_FLOAT_EQ(f.hbar, 0.9f - 0.5f * voxelizer::kShellVoxels * 0.5f);
}

}  // namespace
