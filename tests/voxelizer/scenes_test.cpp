// The built-in procedural scenes: names, bounds, distance functions.
#include "svo/voxelizer/scenes.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace {
using namespace svo::voxelizer;

TEST(Scenes, EveryNameBuildsAndUnknownNamesAreRefused) {
  for (const auto& name : scene_names()) {
    auto scene = make_scene(name);
    ASSERT_TRUE(scene);
    EXPECT_EQ(scene->name(), name);
    Box b = scene->bounds();
    glm::vec3 centre = 0.5f * (b.lo + b.hi);
    EXPECT_LT(scene->distance(centre), 0.0f) << name << ": the centre is inside";
    EXPECT_GT(scene->distance(b.hi + glm::vec3(0.1f)), 0.0f) << name << ": outside the bounds is outside";
  }
  EXPECT_THROW(make_scene("teapot"), std::invalid_argument);
}

TEST(Scenes, ProjectionLandsOnTheSurface) {
  for (const auto& name : scene_names()) {
    auto scene = make_scene(name);
    Box b = scene->bounds();
    glm::vec3 centre = 0.5f * (b.lo + b.hi);
    for (int i = 0; i < 50; ++i) {
      glm::vec3 dir = glm::normalize(glm::vec3(std::sin(i * 1.3f), std::cos(i * 0.7f), std::sin(i * 2.1f + 1)));
      // A point near the surface along dir: bisect the sign change.
      float lo = 0, hi = 2;
      for (int k = 0; k < 40; ++k) {
        float mid = 0.5f * (lo + hi);
        (scene->distance(centre + dir * mid) < 0 ? lo : hi) = mid;
      }
      glm::vec3 q = scene->project(centre + dir * (lo + 0.01f));
      EXPECT_LT(std::abs(scene->distance(q)), 1e-4f) << name << " ray " << i;
    }
  }
}

}  // namespace
