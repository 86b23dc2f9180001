// Issue 5's claim at far views, where every voxel holds many pixels' worth
// of surface: one prefiltered cone per pixel is closer to the ground truth
// (relMSE) than the one-cone baselines mip, nearest and alpha, and its
// coverage on the ground truth's silhouette pixels is off by less than 0.05;
// and each of our additions to the paper's model brings it closer.
// Two sources: the procedural bumpy sphere (128^3, 96 x 96) and the
// Stanford bunny (libcgal-demo's bunny00.off through OpenVDB and Embree;
// 256^3, 128 x 128), ground truth of 64 stratified rays per pixel. The CPU
// tracer, the same code as the GPU's. The bunny covers only 1,654 pixels of
// a 96 x 96 far view: there one silhouette pixel (coverage 0.31 against the
// truth's 0.08) decided the comparison with mip (docs/RESULTS.md, "Lambert
// past the terminator"); at 128 x 128 it covers about 3,100.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/scenes.h"
#include "temp_dir.h"

namespace svo::reference {
namespace {

void expect_prefiltered_wins(const std::string& name, voxelizer::SurfaceSource& source, const Geometry& truth_geometry,
                             uint32_t resolution, uint32_t size) {
  voxelizer::VoxelizeOptions vo;
  vo.resolution = resolution;
  octree::Octree tree = voxelizer::voxelize(source, vo);
  render::RenderSettings s;
  s.width = s.height = size;
  // The far view of this work: the whole domain framed, a pixel over many voxels.
  render::PresetOptions presets;
  presets.whole_domain = true;
  s.camera = render::view_preset(tree, "far", 1.0f, presets);
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 64;
  const render::Image truth = render::frame_image(render_reference(truth_geometry, rs));
  auto errors = [&](render::Mode mode) {
    s.mode = mode;
    return compare_images(render::frame_image(render::render_cpu(tree, s)), truth);
  };
  ImageErrors ours = errors(render::Mode::Prefiltered);
  std::printf("%s far: prefiltered relMSE %.5f, silhouette coverage error %.3f\n", name.c_str(), ours.relmse,
              ours.coverage_error_silhouette.value_or(-1));
  ASSERT_TRUE(ours.coverage_error_silhouette.has_value());
  ASSERT_GT(ours.silhouette_pixels, 100u);
  EXPECT_LT(*ours.coverage_error_silhouette, 0.05) << name;
  // What our additions to the paper's cone take off relMSE here, one after
  // another (sphere, bunny): the normals' spread over each cone's footprint
  // (9%, 8%; at least 5%); masks curved along the cone, front-facing
  // normals at silhouettes and elements' own normals (24%, 36% more; at
  // least 10%); each element shading the part of the footprint it covers
  // first, from a finer level (36%, 37% more; at least 20%).
  const render::RenderSettings defaults = s;
  s.covered_part = false;
  s.shading_voxel = float(M_SQRT2);
  ImageErrors before_parts = errors(render::Mode::Prefiltered);
  s.curved_masks = s.front_facing = s.element_normals = false;
  ImageErrors spread_only = errors(render::Mode::Prefiltered);
  s.footprint_spread = 0;
  ImageErrors plain = errors(render::Mode::Prefiltered);
  s = defaults;
  std::printf(
      "%s far: prefiltered relMSE, the paper's model %.5f, with the footprint's spread %.5f, with curved masks, "
      "front-facing and elements' normals %.5f, with covered parts from a finer level (ours) %.5f\n",
      name.c_str(), plain.relmse, spread_only.relmse, before_parts.relmse, ours.relmse);
  EXPECT_LT(spread_only.relmse, 0.95 * plain.relmse) << name << ": the footprint's normal spread";
  EXPECT_LT(before_parts.relmse, 0.9 * spread_only.relmse)
      << name << ": curved masks, front-facing and elements' normals";
  EXPECT_LT(ours.relmse, 0.8 * before_parts.relmse) << name << ": covered parts from a finer level";
  for (render::Mode mode : {render::Mode::Mip, render::Mode::Nearest, render::Mode::Alpha}) {
    ImageErrors e = errors(mode);
    std::printf("%s far: %s relMSE %.5f\n", name.c_str(), render::mode_name(mode), e.relmse);
    EXPECT_LT(ours.relmse, e.relmse) << name << ": prefiltered against " << render::mode_name(mode);
  }
}

TEST(FarView, PrefilteredBeatsTheOneConeBaselinesOnTheBumpySphere) {
  auto scene = voxelizer::make_scene("bumpy-sphere");
  auto geometry = scene_geometry(*scene);
  expect_prefiltered_wins("bumpy sphere", *scene, *geometry, 128, 96);
}

TEST(FarView, PrefilteredBeatsTheOneConeBaselinesOnTheBunny) {
  svo::testing::TempDir dir;
  const std::string mesh = svo::testing::extract_bunny(dir);
  auto source = voxelizer::load_mesh(mesh);
  auto geometry = mesh_geometry(voxelizer::read_mesh(mesh));
  expect_prefiltered_wins("bunny00", *source, *geometry, 256, 128);
}

}  // namespace
}  // namespace svo::reference
