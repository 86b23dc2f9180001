// The reference under image-based lighting (DESIGN 10.2): the white furnace
// on the exact surface, and the forward pass converging to the reference.
#include <gtest/gtest.h>

#include <cmath>

#include "svo/reference/compare.h"
#include "svo/reference/geometry.h"
#include "svo/reference/reference.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/shading.h"
#include "test_scenes.h"

namespace svo::reference {
namespace {

render::RenderSettings view(std::shared_ptr<const render::Environment> env,
                            std::shared_ptr<const render::Material> material, uint32_t spp) {
  render::RenderSettings s;
  s.width = 40;
  s.height = 32;
  s.camera = test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f);
  s.lights.clear();
  s.ambient = glm::vec3(0);
  s.shading.environment = std::move(env);
  s.shading.material = std::move(material);
  s.shading.spp = spp;
  return s;
}

TEST(ReferenceLighting, AWhiteFurnaceIsOneOnEveryPixel) {
  test::SphereScene sphere(0.5f);  // colour 0.5
  auto geometry = scene_geometry(sphere);
  auto white = std::make_shared<render::Material>();
  white->kind = render::BrdfKind::Lambert;
  white->diffuse = glm::vec3(2.0f);
  ReferenceSettings rs;
  rs.render = view(std::make_shared<const render::Environment>(render::constant_environment(glm::vec3(1))), white, 1);
  rs.spp = 1024;
  const render::Frame f = render_reference(*geometry, rs);
  double worst = 0;
  uint32_t covered = 0;
  for (const auto& c : f.colour) {
    covered += c.a > 0.99f ? 1 : 0;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(double(c[k]) - 1.0));
  }
  EXPECT_GT(covered, 150u);
  EXPECT_LT(worst, 0.01);
}

}  // namespace
}  // namespace svo::reference
