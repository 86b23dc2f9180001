// A libcgal-demo mesh's far view against the reference, as the crease and
// speck tests (tests/reference) measure it.
#pragma once

#include <string>

#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/camera.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "temp_dir.h"
#include "test_scenes.h"

namespace svo::reference {

struct FarFrames {
  render::Frame ours;   // the native host's frame
  render::Frame truth;  // the reference at the same camera and lights
  octree::Octree tree;  // what `ours` drew, with `settings`
  render::RenderSettings settings;
};

// data/meshes/`mesh` voxelized at `resolution`, its far preset at `size` x
// `size`, and the reference at `spp`; lit as svo render lights it
// (render::default_lights) when `cli_lights`, else by the renderer's own
// default. Both saved for inspection as `label` and `label`-reference.
inline FarFrames cgal_far_view(const std::string& mesh, uint32_t resolution, uint32_t size, uint32_t spp,
                               bool cli_lights, const std::string& label) {
  svo::testing::TempDir dir;
  const std::string path = svo::testing::extract_cgal_mesh(dir, mesh);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = resolution;
  const octree::Octree tree = voxelizer::voxelize(*voxelizer::load_mesh(path), vo);
  render::RenderSettings s;
  s.width = s.height = size;
  s.camera = render::view_preset(tree, "far");
  if (cli_lights) s.lights = render::default_lights(s.camera);
  FarFrames f;
  f.ours = render::render_cpu(tree, s);
  f.tree = tree;
  f.settings = s;
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = spp;
  f.truth = render_reference(*mesh_geometry(voxelizer::read_mesh(path)), rs);
  test::save_for_inspection(f.ours, label);
  test::save_for_inspection(f.truth, label + "-reference");
  return f;
}

}  // namespace svo::reference
