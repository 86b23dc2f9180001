// Strongly defocused views (issue 20, item 4) against the thin-lens
// reference. A defocused cone's elements are as long as it is wide, many
// voxels for a strong blur. They once started wherever the march entered
// the domain or left an empty node, so neighbouring rows sampled the surface
// at different points of their elements: horizontal streaks through the
// bunny's ears, and, for a blur a third of the object wide, the domain's
// cube drawn through the blob. The march now lands on a grid along the
// axis that depends on the distance alone, and no element is longer than
// the coarsest level resolves (march.glsl, svo_defocus_grid). One cone
// still drew thin parts as wide as the blur and a blur wider than the
// coarsest voxels as boxes; the lens is now split into parts, a cone each
// (tracer.glsl, svo_lens_parts), and both are tested.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>

#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

// Steps in the error, ours - reference (mean over R, G, B), between
// neighbouring pixels: the energy of its differences between rows (along
// columns) over that between columns (along rows), which streaks along rows
// make large and a blur the same in both directions leaves near 1, and the
// number of differences, either way, above 0.05 (streaks and the edges of
// shells or cubes drawn through a blur; the reference's noise at 256 spp
// stays below).
struct Steps {
  double row_to_column = 0;
  int jumps = 0;
};

Steps error_steps(const render::Frame& ours, const render::Frame& truth) {
  auto error = [&](uint32_t x, uint32_t y) {
    const glm::vec4 a = ours.colour[size_t(y) * ours.width + x], b = truth.colour[size_t(y) * truth.width + x];
    return (a.r - b.r + a.g - b.g + a.b - b.b) / 3.0;
  };
  double between_rows = 0, between_columns = 0;
  Steps steps;
  for (uint32_t y = 0; y + 1 < ours.height; ++y)
    for (uint32_t x = 0; x + 1 < ours.width; ++x) {
      const double e = error(x, y), down = error(x, y + 1) - e, right = error(x + 1, y) - e;
      between_rows += down * down;
      between_columns += right * right;
      steps.jumps += (std::abs(down) > 0.05) + (std::abs(right) > 0.05);
    }
  steps.row_to_column = between_rows / std::max(between_columns, 1e-30);
  return steps;
}

struct Blur {
  const char* name;
  float aperture;  // lens radius, in far-view eye distances
  float focus;     // focus distance, in far-view eye distances
  uint32_t lens_parts;  // RenderSettings::lens_parts (0: the tracer's choice)
  double relmse;   // bounds
  double row_to_column;
  int jumps;
  uint64_t outliers;
};

class Defocus : public ::testing::TestWithParam<Blur> {
 protected:
  static void SetUpTestSuite() {
    dir_ = new svo::testing::TempDir();
    const std::string mesh = svo::testing::extract_bunny(*dir_);
    auto source = voxelizer::load_mesh(mesh);
    voxelizer::VoxelizeOptions options;
    options.resolution = 256;
    tree_ = new octree::Octree(voxelizer::voxelize(*source, options));
    geometry_ = mesh_geometry(voxelizer::read_mesh(mesh)).release();
  }
  static void TearDownTestSuite() {
    delete geometry_;
    delete tree_;
    delete dir_;
  }
  static svo::testing::TempDir* dir_;
  static octree::Octree* tree_;
  static Geometry* geometry_;
};
svo::testing::TempDir* Defocus::dir_ = nullptr;
octree::Octree* Defocus::tree_ = nullptr;
Geometry* Defocus::geometry_ = nullptr;

TEST_P(Defocus, RowsAndColumnsBlurAlike) {
  const Blur& b = GetParam();
  render::RenderSettings s;
  s.width = s.height = 160;
  s.camera = render::view_preset(*tree_, "far");
  const float distance = glm::length(s.camera.eye - s.camera.target);
  s.camera.aperture = b.aperture * distance;
  s.camera.focus = b.focus * distance;
  s.lens_parts = b.lens_parts;
  const render::Frame ours = render::render_cpu(*tree_, s);
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 256;
  const render::Frame truth = render_reference(*geometry_, rs);
  svo::test::save_for_inspection(ours, std::string("defocus-") + b.name);
  svo::test::save_for_inspection(truth, std::string("defocus-") + b.name + "-reference");
  const ImageErrors e = compare_images(render::frame_image(ours), render::frame_image(truth));
  const Steps steps = error_steps(ours, truth);
  std::printf(
      "%s: relMSE %.4f, error steps between rows / between columns %.3f, %d steps above 0.05, %llu of %llu "
      "pixels away from silhouettes off by more than %.2f\n",
      b.name, e.relmse, steps.row_to_column, steps.jumps, (unsigned long long)e.outliers,
      (unsigned long long)e.interior_pixels, kOutlierError);
  EXPECT_LT(e.relmse, b.relmse);
  EXPECT_LT(steps.row_to_column, b.row_to_column);
  EXPECT_LT(steps.jumps, b.jumps);
  EXPECT_LE(e.outliers, b.outliers);
}

INSTANTIATE_TEST_SUITE_P(Bunny, Defocus,
                         // One cone (lens_parts 1), measured before the grid:
                         // strong relMSE 0.0080, rows / columns 1.71, 703
                         // steps, 5 pixels off; third relMSE 4.09, 1.39, 2,550
                         // steps, 77 off. With it: 0.0053, 1.01, 561, 8;
                         // 0.260, 1.35, 805, 0. The lens in parts (the
                         // tracer's choice: 2 x 2 and 4 x 4 here): 0.0016,
                         // 1.35, 174, 0; 0.0085, 1.20, 12, 0, which one cone
                         // fails in every figure but rows / columns.
                         ::testing::Values(Blur{"strong", 0.041f, 1.23f, 1, 0.007, 1.3, 650, 12},
                                           Blur{"third", 0.154f, 2.46f, 1, 0.5, 1.6, 1200, 3},
                                           Blur{"strong_parts", 0.041f, 1.23f, 0, 0.0026, 1.6, 300, 0},
                                           Blur{"third_parts", 0.154f, 2.46f, 0, 0.02, 1.6, 60, 0}),
                         [](const ::testing::TestParamInfo<Blur>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace svo::reference
