// A smooth surface seen at a grazing angle shades smoothly (issue 20, item
// 3): no steps between neighbouring voxels. The bunny's ears and neck at
// 512^3 once showed rectangles of flat shade there. The measure is the
// second difference of luminance along rows and columns, L(x-1) - 2 L(x) +
// L(x+1), over pixels that see the sphere at a grazing angle away from its
// silhouette: its 99th percentile against the reference's (whose own noise
// sets the floor). The nearest-voxel baseline, blocky by construction, must
// fail the same bound: the measure sees steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <vector>

#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

// The 99th percentile of |second difference of luminance| along rows and
// columns, over the pixels `use` marks (all three pixels of a difference
// marked).
double second_difference_p99(const render::Frame& f, const std::vector<bool>& use) {
  const int w = int(f.width), h = int(f.height);
  auto luminance = [&](int x, int y) {
    const glm::vec4 c = f.colour[size_t(y * w + x)];
    return (c.r + c.g + c.b) / 3.0;
  };
  auto marked = [&](int x, int y) { return use[size_t(y * w + x)]; };
  std::vector<double> d;
  for (int y = 1; y + 1 < h; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      if (!marked(x, y)) continue;
      if (marked(x - 1, y) && marked(x + 1, y))
        d.push_back(std::abs(luminance(x - 1, y) - 2 * luminance(x, y) + luminance(x + 1, y)));
      if (marked(x, y - 1) && marked(x, y + 1))
        d.push_back(std::abs(luminance(x, y - 1) - 2 * luminance(x, y) + luminance(x, y + 1)));
    }
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + ptrdiff_t(0.99 * double(d.size())), d.end());
  return d[size_t(0.99 * double(d.size()))];
}

TEST(Grazing, ASmoothSphereShadesWithoutStepsBetweenVoxels) {
  const float radius = 0.5f;
  test::SphereScene sphere(radius);
  voxelizer::VoxelizeOptions vo;
  vo.resolution = 256;
  const octree::Octree tree = voxelizer::voxelize(sphere, vo);
  const float voxel = tree.voxel_size(tree.depth_count - 1);
  // A point on the sphere seen 75 degrees from its normal, about 70 voxels
  // away: 2.5 pixels a voxel at 128x128.
  render::RenderSettings s;
  s.width = s.height = 128;
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f)), target = radius * n;
  const glm::vec3 side = glm::normalize(glm::cross(n, glm::vec3(0, 0, 1)));
  const float a = glm::radians(75.0f);
  s.camera.target = target;
  s.camera.eye = target + 70 * voxel * (std::cos(a) * n + std::sin(a) * side);
  s.camera.up = n;
  s.camera.fov_deg = 40;
  s.gbuffer = true;
  // One light near the horizon across the view: the shade changes fast
  // with the normal, as at the bunny's ears.
  render::Light light;
  light.vector = 0.3f * n + glm::cross(n, side);
  s.lights = {light};
  ReferenceSettings rs;
  rs.render = s;
  rs.spp = 256;
  const render::Frame truth = render_reference(*scene_geometry(sphere), rs);
  const render::Frame ours = render::render_cpu(tree, s);
  // Pixels at least 3 pixels from the reference's background that see the
  // sphere 60 degrees or more from its normal (where our G-buffer says the
  // pixel's surface is; the reference keeps none).
  const int w = int(s.width), h = int(s.height);
  std::vector<bool> grazing(size_t(w * h), false);
  int count = 0;
  for (int y = 3; y + 3 < h; ++y)
    for (int x = 3; x + 3 < w; ++x) {
      bool inside = true;
      for (int dy = -3; dy <= 3 && inside; ++dy)
        for (int dx = -3; dx <= 3 && inside; ++dx) inside = truth.colour[size_t((y + dy) * w + x + dx)].a >= 1.0f;
      const render::GBufferTexel& g = ours.gbuffer[size_t(y * w + x)];
      const glm::vec3 to_eye = glm::normalize(s.camera.eye - g.position);
      if (inside && glm::dot(glm::normalize(g.position), to_eye) < 0.5f) grazing[size_t(y * w + x)] = true, ++count;
    }
  ASSERT_GT(count, 2000);
  const double reference = second_difference_p99(truth, grazing);
  svo::test::save_for_inspection(ours, "grazing");
  svo::test::save_for_inspection(truth, "grazing-reference");
  const double prefiltered = second_difference_p99(ours, grazing);
  render::RenderSettings nearest_settings = s;
  nearest_settings.mode = render::Mode::Nearest;
  const render::Frame nearest = render::render_cpu(tree, nearest_settings);
  const double steps = second_difference_p99(nearest, grazing);
  std::printf(
      "%d grazing pixels: 99th percentile |second difference of luminance| reference %.4f, prefiltered %.4f, "
      "nearest %.4f\n",
      count, reference, prefiltered, steps);
  const double bound = 2 * reference + 0.001;
  EXPECT_LT(prefiltered, bound);
  EXPECT_GT(steps, bound) << "the measure does not see the nearest-voxel baseline's steps";
}

}  // namespace
}  // namespace svo::reference
