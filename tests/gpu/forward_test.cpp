// The forward-shading pass (render::ForwardPass, shaders/common/forward.glsl)
// on both hosts: the white furnace renders radiance 1 on every pixel, the
// hosts agree on an environment map with a glossy material, and the
// environment is seen behind the object.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../render/test_lighting.h"
#include "../render/test_scenes.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/shading.h"

namespace svo::render {
namespace {

class ForwardOnBothHosts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    test::SphereScene sphere(0.5f);  // colour 0.5
    tree_ = new octree::Octree(test::voxelize(sphere, 64));
  }
  static void TearDownTestSuite() { delete tree_; }

  void SetUp() override {
    vk::ContextOptions options;
    options.device = "llvmpipe";
    options.validation = true;
    context_ = std::make_unique<vk::Context>(options);
    renderers_.push_back(std::make_unique<NativeRenderer>(*tree_));
    renderers_.push_back(std::make_unique<GpuRenderer>(*context_, *tree_));
    for (auto& r : renderers_) r->add_pass(make_pass("forward"));
  }

  RenderSettings settings(const Environment& env, const Material& material, uint32_t spp) const {
    RenderSettings s;
    s.width = 48;
    s.height = 40;
    s.camera = test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f);
    s.lights.clear();
    s.ambient = glm::vec3(0);
    s.shading.environment = std::make_shared<const Environment>(env);
    s.shading.material = std::make_shared<const Material>(material);
    s.shading.spp = spp;
    return s;
  }

  static octree::Octree* tree_;
  std::unique_ptr<vk::Context> context_;
  std::vector<std::unique_ptr<Renderer>> renderers_;
};

octree::Octree* ForwardOnBothHosts::tree_ = nullptr;

TEST_F(ForwardOnBothHosts, AWhiteFurnaceIsOneOnEveryPixel) {
  Material white;
  white.kind = BrdfKind::Lambert;
  white.diffuse = glm::vec3(2.0f);  // times the sphere's abar 0.5: albedo 1
  const RenderSettings s = settings(constant_environment(glm::vec3(1.0f)), white, 1024);
  for (auto& r : renderers_) {
    const Frame f = r->render(s);
    uint32_t covered = 0, off = 0;
    double worst = 0, mean = 0;
    float worst_alpha = 0;
    for (const auto& c : f.colour) {
      covered += c.a > 0.99f ? 1 : 0;
      const double e = std::abs(double(c.g) - 1.0);
      if (e > worst) worst = e, worst_alpha = c.a;
      off += e > 0.01 ? 1 : 0;
      mean += c.g;
    }
    test::save_for_inspection(f, std::string("furnace_") + host_name(r->host()));
    std::printf("%s: furnace mean %.5f, worst %.5f at coverage %.3f, %u pixels off by > 1%%\n", host_name(r->host()),
                mean / double(f.colour.size()), worst, worst_alpha, off);
    EXPECT_GT(covered, 200u) << host_name(r->host());
    EXPECT_LT(worst, 0.01) << host_name(r->host()) << ": the furnace is not 1 within 1%";
  }
}

TEST_F(ForwardOnBothHosts, BothHostsAgreeUnderAnEnvironmentWithAGlossyMaterial) {
  Material ggx;
  ggx.kind = BrdfKind::Ggx;
  ggx.diffuse = glm::vec3(0.8f);
  ggx.f0 = glm::vec3(0.9f, 0.6f, 0.3f);
  ggx.roughness = 0.15f;
  RenderSettings s = settings(test::sky(), ggx, 16);
  s.shading.env_rotate_deg = 30;
  const Frame a = renderers_[0]->render(s);
  const Frame b = renderers_[1]->render(s);
  ASSERT_EQ(a.colour.size(), b.colour.size());
  double diff = 0, sum = 0;
  for (size_t i = 0; i < a.colour.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      diff += std::abs(double(a.colour[i][k]) - double(b.colour[i][k]));
      sum += std::abs(double(a.colour[i][k]));
    }
  }
  EXPECT_GT(sum, 0);
  // The same samples on both hosts: only float rounding differs (a sample
  // that lands on the other side of a CDF step changes one pixel).
  EXPECT_LT(diff / sum, 0.01);
  test::save_for_inspection(a, "forward_ggx_native");
  test::save_for_inspection(b, "forward_ggx_lavapipe");
}

TEST_F(ForwardOnBothHosts, TheEnvironmentIsTheBackground) {
  Material white;
  white.kind = BrdfKind::Lambert;
  RenderSettings s = settings(test::sky(), white, 1);
  for (auto& r : renderers_) {
    const Frame f = r->render(s);
    // The top-left corner looks up into the sky (blue), off the sphere.
    const glm::vec4 corner = f.colour[0];
    EXPECT_EQ(corner.a, 0.0f);
    EXPECT_GT(corner.b, corner.r) << host_name(r->host());
    EXPECT_NEAR(corner.b, 0.9f, 0.05f) << host_name(r->host());
  }
}

// A scene with five materials (its own, carried by the octree): both hosts
// look up the same materials into the G-buffer and shade each pixel with
// its own.
TEST(ForwardMaterials, BothHostsShadeEachPixelWithItsMaterials) {
  const auto scene = voxelizer::make_scene("material-spheres");
  const octree::Octree tree = test::voxelize(*scene, 64);
  ASSERT_EQ(tree.materials.size(), 5u);
  vk::ContextOptions options;
  options.device = "llvmpipe";
  options.validation = true;
  vk::Context context(options);
  NativeRenderer native(tree);
  GpuRenderer vulkan(context, tree);
  RenderSettings s;
  s.width = 48;
  s.height = 32;
  s.camera = test::looking_at_origin({0.0f, 1.1f, 2.2f}, 40.0f);
  s.camera.target = glm::vec3(0, 0.15f, 0);
  s.lights.clear();
  s.ambient = glm::vec3(0);
  s.gbuffer = true;
  s.shading.environment = std::make_shared<const Environment>(test::sky());
  s.shading.spp = 16;
  Frame frames[2];
  int host = 0;
  for (Renderer* r : {static_cast<Renderer*>(&native), static_cast<Renderer*>(&vulkan)}) {
    r->add_pass(make_pass("forward"));
    frames[host++] = r->render(s);
  }
  const Frame &a = frames[0], &b = frames[1];
  ASSERT_EQ(a.gbuffer.size(), b.gbuffer.size());
  int covered = 0, same = 0;
  bool seen[5] = {};
  double diff = 0, sum = 0;
  for (size_t i = 0; i < a.gbuffer.size(); ++i) {
    const GBufferTexel &x = a.gbuffer[i], &y = b.gbuffer[i];
    if (x.coverage < 0.99f || y.coverage < 0.99f) continue;
    ++covered;
    same += x.material == y.material && x.material2 == y.material2 && std::abs(x.material_mix - y.material_mix) < 1e-3f;
    ASSERT_LT(x.material, 5u);
    seen[x.material] = true;
    for (int k = 0; k < 3; ++k) {
      diff += std::abs(double(a.colour[i][k]) - double(b.colour[i][k]));
      sum += std::abs(double(a.colour[i][k]));
    }
  }
  EXPECT_GT(covered, 400);
  EXPECT_GE(same, covered * 99 / 100) << "the hosts' G-buffers name other materials";
  for (int m = 0; m < 5; ++m) EXPECT_TRUE(seen[m]) << "no pixel shows material " << m;
  EXPECT_LT(diff / sum, 0.01);
  test::save_for_inspection(a, "forward_materials_native");
  test::save_for_inspection(b, "forward_materials_lavapipe");
}

}  // namespace
}  // namespace svo::render
