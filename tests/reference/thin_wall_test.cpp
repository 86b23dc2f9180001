// A wall about one voxel thick: the lattice points inside it or on it near
// its far face carry that face's normal, those just outside its near face
// the opposite one. Their trilinear sum shrank the normal to 0.35-0.42 of
// its length and tilted it, a lattice of dots over the near face
// (libcgal-demo's boeing, a CAD bracket whose top wall is 0.2 mm at 0.2 mm
// a voxel; docs/RESULTS.md "Walls one voxel thick"). Shading now leaves out
// the corners whose normal faces clearly away from the eye and opposes the
// most eye-facing corner's (fetch.glsl, svo_facing_weight).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <vector>

#include "grid_mesh.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/mesh.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

TEST(ThinWall, NearFaceShadesWithItsOwnNormal) {
  // At 64^3 the lattice's voxel is the largest extent / 56 (make_lattice):
  // 2 / 56 here, and the domain is centred on the bounds, which a small
  // block below makes symmetric in y: lattice planes at y = k voxels. A
  // plate 2 x 2 and one voxel thick from y = 14.9 to 15.9 voxels: the one
  // plane inside it, at 15, is nearer its far face (normal -y) and the
  // plane above, at 16, holds the near face's (+y), so the interpolated
  // distance's zero, at 15.5, lies where the two normals cancel.
  constexpr int kResolution = 64;
  const double v = 2.0 / (kResolution - 8);
  voxelizer::MeshArrays m;
  test::add_box(m, {-1, 14.9 * v, -1}, {1, 15.9 * v, 1}, 8);
  test::add_box(m, {-0.2, -15.9 * v, -0.2}, {0.2, -10 * v, 0.2}, 2);
  voxelizer::TriangleMesh mesh = voxelizer::make_triangle_mesh("wall.obj", std::move(m));
  ASSERT_FALSE(mesh.two_sided) << mesh.surface;
  auto source = voxelizer::mesh_source(mesh);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = kResolution;
  const octree::Octree tree = voxelizer::voxelize(*source, vo);
  ASSERT_NEAR(tree.voxel_size(tree.depth_count - 1), v, 1e-6);

  // The wall's top from 40 degrees above it, about 1.4 pixels a voxel.
  render::RenderSettings s;
  s.width = s.height = 128;
  s.camera.target = {0, 15.9 * v, 0};
  s.camera.eye = s.camera.target + 3.0f * glm::normalize(glm::vec3(0.55f, 0.64f, 0.53f));
  s.camera.up = {0, 1, 0};
  s.camera.fov_deg = 40;
  s.gbuffer = true;
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 16;
  const render::Frame truth = render_reference(*mesh_geometry(std::move(mesh)), rs);
  const render::Frame ours = render::render_cpu(tree, s);
  svo::test::save_for_inspection(ours, "thin-wall");
  svo::test::save_for_inspection(truth, "thin-wall-reference");

  // The top face's pixels: whole in the reference within 2 pixels, and
  // where our G-buffer puts the surface on it.
  const int w = int(s.width), h = int(s.height);
  std::vector<double> lengths, errors;
  for (int y = 2; y + 2 < h; ++y)
    for (int x = 2; x + 2 < w; ++x) {
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; ++dy)
        for (int dx = -2; dx <= 2 && inside; ++dx) inside = truth.colour[size_t((y + dy) * w + x + dx)].a >= 1.0f;
      const size_t i = size_t(y * w + x);
      const render::GBufferTexel& g = ours.gbuffer[i];
      if (!inside || g.coverage < 0.99f || g.position.y < 15.0f * float(v)) continue;
      lengths.push_back(glm::length(g.normal));
      const glm::vec4 a = ours.colour[i], b = truth.colour[i];
      errors.push_back(std::abs((a.r + a.g + a.b) - (b.r + b.g + b.b)) / 3.0);
    }
  ASSERT_GT(lengths.size(), 2000u);
  auto percentile = [](std::vector<double> x, double q) {
    std::nth_element(x.begin(), x.begin() + ptrdiff_t(q * double(x.size() - 1)), x.end());
    return x[size_t(q * double(x.size() - 1))];
  };
  const double short_normal = percentile(lengths, 0.01), error = percentile(errors, 0.99);
  std::printf("%zu top-face pixels: normal length 1st percentile %.3f; luminance error 99th percentile %.4f\n",
              lengths.size(), short_normal, error);
  EXPECT_GT(short_normal, 0.9);
  EXPECT_LT(error, 0.05);
}

}  // namespace
}  // namespace svo::reference
