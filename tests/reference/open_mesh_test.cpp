// Open meshes (issue 20, item 0): a box without its lid, a bowl (half a
// sphere) and a wavy sheet render as their reference shows them, from above
// (the inside in view) and up close. OpenVDB's flood fill once guessed their
// inside: the lion's face was a moire of dots. Each triangle is now a thin
// shell seen from both sides, at every level, as the reference's
// double-sided triangles are; where it bounds a volume by the winding
// number (the box's walls, the bowl), the shell lies inside that volume.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <string>

#include "grid_mesh.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"

namespace svo::reference {
namespace {

using voxelizer::MeshArrays;

// The unit cube without its top (y = 1), outward.
MeshArrays lidless_box_of(int cells) {
  MeshArrays m;
  test::add_grid(m, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}, cells);
  test::add_grid(m, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, cells);
  test::add_grid(m, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, cells);
  test::add_grid(m, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, cells);
  test::add_grid(m, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, cells);
  return m;
}
MeshArrays lidless_box() { return lidless_box_of(4); }
// The same with two triangles a face, as libcgal-demo's open_cube.off.
MeshArrays lidless_box_coarse() { return lidless_box_of(1); }

// The lower half of the unit sphere, open at the top, outward.
MeshArrays bowl() {
  MeshArrays m;
  const int around = 48, down = 16;
  m.positions.emplace_back(0, -1, 0);
  for (int j = 1; j <= down; ++j) {
    const double theta = 0.5 * M_PI * j / down;
    for (int i = 0; i < around; ++i) {
      const double phi = 2 * M_PI * i / around;
      m.positions.emplace_back(std::sin(theta) * std::cos(phi), -std::cos(theta), std::sin(theta) * std::sin(phi));
    }
  }
  for (int i = 0; i < around; ++i) m.triangles.emplace_back(0, 1 + i, 1 + (i + 1) % around);
  for (int j = 1; j < down; ++j)
    for (int i = 0; i < around; ++i) {
      const int a = 1 + (j - 1) * around + i, b = 1 + (j - 1) * around + (i + 1) % around;
      const int c = a + around, d = b + around;
      m.triangles.emplace_back(a, c, d);
      m.triangles.emplace_back(a, d, b);
    }
  return m;
}

// A wavy square sheet, y = 0.15 sin(2x) cos(1.5z) over [-1, 1]^2.
MeshArrays sheet() {
  MeshArrays m;
  const int n = 40;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -1 + 2.0 * i / n, z = -1 + 2.0 * j / n;
      m.positions.emplace_back(x, 0.15 * std::sin(2 * x) * std::cos(1.5 * z), z);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, c = a + n + 1;
      m.triangles.emplace_back(a, c + 1, a + 1);
      m.triangles.emplace_back(a, c, c + 1);
    }
  return m;
}

struct Case {
  const char* name;
  MeshArrays (*make)();
  const char* view;
  double relmse;     // bound
  double off_share;  // bound on the share of pixels away from silhouettes off by more than 0.25
  uint64_t specks;   // bound on the pixels covered 3 or more pixels away from the reference's coverage
  bool whole_domain = true;  // the presets framing the whole domain; false: framing the object, as svo render does
};

class OpenMesh : public testing::TestWithParam<Case> {};

TEST_P(OpenMesh, MatchesItsReference) {
  const Case& c = GetParam();
  std::string warning;
  voxelizer::MeshOptions options;
  options.warning = [&](const std::string& w) { warning = w; };
  voxelizer::TriangleMesh mesh = voxelizer::make_triangle_mesh(c.name, c.make(), options);
  ASSERT_GT(mesh.open_edges, 0u);
  EXPECT_NE(warning.find("drawn two-sided"), std::string::npos) << warning;
  voxelizer::VoxelizeOptions vo;
  vo.resolution = 64;
  auto source = voxelizer::mesh_source(mesh);
  octree::Octree tree = voxelizer::voxelize(*source, vo);
  // The provenance svo voxelize records, which the tracer reads (svo_turn_to_eye).
  ASSERT_TRUE(source->two_sided());
  tree.source = R"({"two_sided": true})";
  render::RenderSettings s;
  s.width = s.height = 96;
  // The presets the thresholds were calibrated on (the whole domain framed).
  render::PresetOptions presets;
  presets.whole_domain = c.whole_domain;
  s.camera = render::view_preset(tree, c.view, 1.0f, presets);
  if (std::string(c.view) == "close") {
    // Up close: 8 finest voxels from the surface point, where the close
    // preset stood until it was moved out to 64 voxels across (the
    // calibration's view: the surface fills the image, no rim in it).
    const glm::vec3 back = glm::normalize(s.camera.eye - s.camera.target);
    s.camera.eye = s.camera.target + back * std::max(8 * tree.voxel_size(tree.depth_count - 1), 0.02f * tree.size);
  }
  const render::Image ours = render::frame_image(render::render_cpu(tree, s));
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 16;
  const render::Image truth = render::frame_image(render_reference(*mesh_geometry(std::move(mesh)), rs));
  const ImageErrors e = compare_images(ours, truth);
  std::printf("%s %s: relMSE %.4f, %llu of %llu pixels away from silhouettes off by more than %.2f, %llu specks\n",
              c.name, c.view, e.relmse, (unsigned long long)e.outliers, (unsigned long long)e.interior_pixels,
              kOutlierError, (unsigned long long)e.specks.value_or(0));
  EXPECT_LT(e.relmse, c.relmse);
  EXPECT_LE(double(e.outliers), c.off_share * double(e.interior_pixels));
  ASSERT_TRUE(e.specks.has_value());
  EXPECT_LE(*e.specks, c.specks);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, OpenMesh,
    // Up close, what the issue asks: within relMSE 0.01, no pixel
    // off, no speck. From afar, what remains (measured: relMSE
    // 0.013, 0.30, 0.092, 0.013; 3, 125, 0 and 1 pixels off, on the
    // boxes' rims and the bowl's, which the reference draws without
    // thickness: the bowl's front rim, a voxel of 4.5 pixels here,
    // shows its shell's cap, 1.25 voxels tall). With the shell 2
    // voxels thick they were 0.041, 0.99 and 0.38 (14, 317 and 0
    // pixels off), which the bounds on relMSE refuse; without
    // svo_turn_to_eye (shaders/common/shading.glsl) 0.016, 0.30,
    // 0.092, 0.018 (4, 168, 17 and 6 pixels off: the shell's far half
    // behind the faces), which the bounds on pixels off refuse, and the
    // coarse box's on relMSE. The boxes' walls and the bowl bound a
    // volume by the winding number: their shell lies inside it, so
    // their silhouettes stay where the reference's are. A shell centred
    // on every triangle widened them by a voxel: relMSE 1.14 and 1.67
    // (14 and 314 pixels off), as they refuse the 3.06, 2.35 and 1.38
    // of a shell reaching a voxel beyond open edges (before it ended in
    // a cap there). The coarse box is framed as svo render frames it.
    // Since the cap reaches inside the shell, a sheet's shell ends in a
    // wedge and shading reads the face's normal there (2026-12-08):
    // relMSE 0.0078, 0.0078, 0.013 and 0.0073 from afar (0.013, 0.30,
    // 0.092, 0.013 before), 0, 35, 0 and 0 pixels off (3, 125, 0, 1):
    // the bounds on relMSE refuse the former rims, and on pixels off the
    // bowl's.
    testing::Values(Case{"lidless-box", lidless_box, "close", 0.01, 0, 0}, Case{"bowl", bowl, "close", 0.01, 0, 0},
                    Case{"sheet", sheet, "close", 0.01, 0, 0}, Case{"lidless-box", lidless_box, "far", 0.011, 0.0025, 0},
                    Case{"bowl", bowl, "mid", 0.03, 0.006, 60}, Case{"sheet", sheet, "far", 0.03, 0.001, 0},
                    Case{"lidless-box-coarse", lidless_box_coarse, "far", 0.01, 0.0005, 0, false}),
    [](const testing::TestParamInfo<Case>& info) {
      std::string n = std::string(info.param.name) + "_" + info.param.view + (info.param.whole_domain ? "" : "_framed");
      for (char& ch : n)
        if (ch == '-') ch = '_';
      return n;
    });

}  // namespace
}  // namespace svo::reference
