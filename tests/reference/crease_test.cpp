// A sharp convex edge seen up close is drawn straight (issue 20: CAD parts'
// edges were notched). A box turned so that its edges cross the lattice
// obliquely, voxelized at 64^3, and one of its edges seen at about 7 pixels
// a finest voxel: the face across the edge once reached into the near face in
// teeth a voxel apart, where corners holding the far face's normal took
// their trilinear share (libcgal-demo's fandisk at 256^3, docs/RESULTS.md
// "Creases"). The measure: the pixels away from silhouettes off by more
// than 0.25 from the reference (the view sees the two faces and, in a
// corner, the background), and relMSE.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "cgal_far_view.h"
#include "grid_mesh.h"
#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

TEST(Crease, AnObliqueBoxEdgeIsDrawnStraight) {
  // The box [-0.55, 0.55]^3 turned 23 degrees about y, then 17 about x.
  const glm::dmat3 turn = glm::dmat3(glm::rotate(glm::dmat4(1), glm::radians(17.0), glm::dvec3(1, 0, 0))) *
                          glm::dmat3(glm::rotate(glm::dmat4(1), glm::radians(23.0), glm::dvec3(0, 1, 0)));
  voxelizer::MeshArrays box;
  const double a = 0.55;
  test::add_box(box, glm::dvec3(-a), glm::dvec3(a), 4);
  for (auto& p : box.positions) p = turn * p;
  voxelizer::TriangleMesh mesh = voxelizer::make_triangle_mesh("box", std::move(box));
  ASSERT_EQ(mesh.open_edges, 0u);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = 64;
  auto source = voxelizer::mesh_source(mesh);
  const octree::Octree tree = voxelizer::voxelize(*source, vo);
  const float voxel = tree.voxel_size(tree.depth_count - 1);
  // The edge between the +x and +y faces, seen from between them and a
  // little along it, 24 voxels away: about 7 pixels a voxel at 128x128.
  const glm::vec3 mid = glm::vec3(turn * glm::dvec3(a, a, 0));
  const glm::vec3 along = glm::vec3(turn * glm::dvec3(0, 0, 1));
  const glm::vec3 out = glm::normalize(glm::vec3(turn * glm::dvec3(1, 1.4, 0)));
  render::RenderSettings s;
  s.width = s.height = 128;
  s.camera.target = mid;
  s.camera.eye = mid + 24 * voxel * glm::normalize(out + 0.2f * along);
  s.camera.up = along;
  s.camera.fov_deg = 40;
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 16;
  const render::Frame truth_frame = render_reference(*mesh_geometry(std::move(mesh)), rs);
  const render::Frame ours_frame = render::render_cpu(tree, s);
  test::save_for_inspection(ours_frame, "crease-ours");
  test::save_for_inspection(truth_frame, "crease-reference");
  const render::Image truth = render::frame_image(truth_frame);
  const render::Image ours = render::frame_image(ours_frame);
  const ImageErrors e = compare_images(ours, truth);
  std::printf("oblique box edge: relMSE %.5f, %llu of %llu pixels off by more than %.2f, 99.9th percentile %.3f\n",
              e.relmse, (unsigned long long)e.outliers, (unsigned long long)e.interior_pixels, kOutlierError,
              e.p999_error);
  // Measured: 6 pixels off and relMSE 0.0039; with every corner at its
  // trilinear weight (svo_plane_weight 1), 133 and 0.0234.
  EXPECT_LE(e.outliers, 20u);
  EXPECT_LT(e.relmse, 0.008);
}

// Where the corners' planes do not fit together the planes' weights are
// left out (issue 20: libcgal-demo's turbine at 128^3 lost 1.5 dB to them,
// its ring drawn as a row of teeth). There, corners whose normals agree
// hold planes that lie apart: the ring steps by 0.73 of a voxel between
// two faces that both face along its axis, and the corners that hold the
// riser's plane are few and placed by the lattice. The weights fade out as
// such planes lie from a quarter to a half of a voxel apart
// (svo_sample_shading). Both meshes as scripts/mesh-sweep.sh draws them:
// 128^3, far view, 256x256, against the reference at 16 spp.
struct SweepCase {
  const char* mesh;
  uint64_t max_outliers;
};

class CreaseSweep : public ::testing::TestWithParam<SweepCase> {};

TEST_P(CreaseSweep, PlanesThatDoNotFitAreLeftOut) {
  const FarFrames f = cgal_far_view(GetParam().mesh, 128, 256, 16, true, std::string("crease-") + GetParam().mesh);
  const ImageErrors e = compare_images(render::frame_image(f.ours), render::frame_image(f.truth));
  std::printf("%s far: relMSE %.5f, %llu of %llu pixels away from silhouettes off by more than %.2f\n",
              GetParam().mesh, e.relmse, (unsigned long long)e.outliers, (unsigned long long)e.interior_pixels,
              kOutlierError);
  EXPECT_LE(e.outliers, GetParam().max_outliers);
}

// Measured (pixels off): fandisk 43 with the fade, 115 without it (86
// without the planes' weights); turbine 74, 92 (73).
INSTANTIATE_TEST_SUITE_P(Meshes, CreaseSweep,
                         ::testing::Values(SweepCase{"fandisk.off", 70}, SweepCase{"turbine.off", 84}),
                         [](const auto& info) { return std::string(info.param.mesh).substr(0, 7); });

// A crease seen from afar, a finest voxel about two pixels wide: the
// lattice rounds it over a voxel, and one Gaussian lobe about the mean of
// its faces' normals drew a line along it brighter than either face (a
// glint the reference does not have: libcgal-demo's cube, octahedron,
// cross, fandisk). Prefiltered shading splits a part of the footprint
// across such a crease into two halves, weighted by where the crease lies
// (svo_shade). The measure: pixels fully covered in both images brighter
// than the reference's brightest by more than 0.05; and the pixels away
// from silhouettes off by more than 0.25. The same octree drawn with one
// lobe (crease_split off) shows that the measure sees the glint.
struct GlintCase {
  const char* mesh;
  size_t max_glints;
  uint64_t max_outliers;
};

class CreaseGlint : public ::testing::TestWithParam<GlintCase> {};

size_t glints(const render::Frame& ours, const render::Frame& truth) {
  auto grey = [](glm::vec4 c) { return (c.x + c.y + c.z) / 3; };
  auto full = [&](size_t i) { return ours.colour[i].w > 0.999f && truth.colour[i].w > 0.999f; };
  float brightest = 0;
  for (size_t i = 0; i < truth.colour.size(); ++i) {
    if (full(i)) brightest = std::max(brightest, grey(truth.colour[i]));
  }
  size_t n = 0;
  for (size_t i = 0; i < ours.colour.size(); ++i) n += full(i) && grey(ours.colour[i]) > brightest + 0.05f;
  return n;
}

TEST_P(CreaseGlint, NoCreaseIsBrighterThanItsFaces) {
  const FarFrames f = cgal_far_view(GetParam().mesh, 128, 256, 16, true, std::string("glint-") + GetParam().mesh);
  render::RenderSettings one_lobe = f.settings;
  one_lobe.crease_split = false;
  const render::Frame unsplit = render::render_cpu(f.tree, one_lobe);
  const ImageErrors e = compare_images(render::frame_image(f.ours), render::frame_image(f.truth));
  const ImageErrors u = compare_images(render::frame_image(unsplit), render::frame_image(f.truth));
  const size_t split_glints = glints(f.ours, f.truth), one_lobe_glints = glints(unsplit, f.truth);
  std::printf("%s far: %zu pixels brighter than the reference's brightest (one lobe: %zu); %llu pixels off (one "
              "lobe: %llu)\n",
              GetParam().mesh, split_glints, one_lobe_glints, (unsigned long long)e.outliers,
              (unsigned long long)u.outliers);
  EXPECT_LE(split_glints, GetParam().max_glints);
  EXPECT_GT(one_lobe_glints, 10u);
  EXPECT_LE(e.outliers, GetParam().max_outliers);
}

// Measured: cube 0 glints (one lobe 16), 58 pixels off (98); octahedron 2
// (40), 2 (60). Split where one flat face's normal showed twice (not two
// faces'), the octahedron drew 0 and 1, but the armadillo's toes dimmed
// (Specks.NoneBesideTheArmadillosThinFeatures).
INSTANTIATE_TEST_SUITE_P(Meshes, CreaseGlint,
                         ::testing::Values(GlintCase{"cube_quad.off", 0, 66}, GlintCase{"octahedron.off", 3, 6}),
                         [](const auto& info) { return std::string(info.param.mesh).substr(0, 4); });

}  // namespace
}  // namespace svo::reference
