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

// Pre-convolved shading (--env-preconvolved) in the white furnace, where
// every lookup is exact: a white Lambert surface is 1 on every pixel, and a
// glossy Phong lobe of f0 1 reflects its directional albedo, as the sampled
// pass finds it (the 16-direction quadrature of svo_specular_albedo against
// 1024 samples).
TEST_F(ForwardOnBothHosts, PreconvolvedFurnaceIsOneOrTheLobesAlbedo) {
  const Environment furnace = constant_environment(glm::vec3(1.0f));
  const auto pre = std::make_shared<const PreconvolvedEnvironment>(preconvolve_environment(furnace));
  Material white;
  white.kind = BrdfKind::Lambert;
  white.diffuse = glm::vec3(2.0f);  // times the sphere's abar 0.5
  Material glossy;
  glossy.kind = BrdfKind::Phong;
  glossy.diffuse = glm::vec3(0.0f);
  glossy.f0 = glm::vec3(1.0f);
  glossy.exponent = 200.0f;
  for (const Material* m : {&white, &glossy}) {
    RenderSettings s = settings(furnace, *m, 1024);
    const Frame sampled = renderers_[0]->render(s);
    s.shading.preconvolved = pre;
    for (auto& r : renderers_) {
      const Frame f = r->render(s);
      uint32_t covered = 0;
      double worst = 0, worst_sampled = 0;
      for (size_t i = 0; i < f.colour.size(); ++i) {
        if (!(f.colour[i].a > 0.99f)) continue;
        ++covered;
        worst = std::max(worst, std::abs(double(f.colour[i].g) - (m == &white ? 1.0 : double(sampled.colour[i].g))));
        worst_sampled = std::max(worst_sampled, std::abs(double(sampled.colour[i].g) - 1.0));
      }
      std::printf("%s, %s: worst %.4f (the sampled pass: %.4f from 1)\n", host_name(r->host()), brdf_name(m->kind),
                  worst, worst_sampled);
      EXPECT_GT(covered, 200u) << host_name(r->host());
      EXPECT_LT(worst, m == &white ? 0.01 : 0.03) << host_name(r->host()) << ", " << brdf_name(m->kind);
    }
  }
}

// Pre-convolved shading on both hosts agrees, and stays near the sampled
// pass (1024 samples) on a glossy and a rough material under the sky: what
// the lookup approximates (the lobe as one SG about the mirror direction)
// costs a few percent per pixel (5% here, the sampled pass's noise
// included) and about 1% on the whole, not a different picture.
TEST_F(ForwardOnBothHosts, PreconvolvedAgreesOnBothHostsAndNearTheSampledPass) {
  const Environment sky = test::sky(128, 64, false);
  const auto pre = std::make_shared<const PreconvolvedEnvironment>(preconvolve_environment(sky));
  for (float roughness : {0.1f, 0.4f}) {
    Material ggx;
    ggx.kind = BrdfKind::Ggx;
    ggx.diffuse = glm::vec3(0.5f);
    ggx.f0 = glm::vec3(0.9f, 0.6f, 0.3f);
    ggx.roughness = roughness;
    RenderSettings s = settings(sky, ggx, 1024);
    const Frame sampled = renderers_[0]->render(s);
    s.shading.preconvolved = pre;
    const Frame a = renderers_[0]->render(s);
    const Frame b = renderers_[1]->render(s);
    ASSERT_EQ(a.colour.size(), b.colour.size());
    double hosts = 0, near = 0, bias = 0, sum = 0;
    for (size_t i = 0; i < a.colour.size(); ++i) {
      if (!(sampled.colour[i].a > 0.99f)) continue;
      for (int k = 0; k < 3; ++k) {
        hosts += std::abs(double(a.colour[i][k]) - double(b.colour[i][k]));
        near += std::abs(double(a.colour[i][k]) - double(sampled.colour[i][k]));
        bias += double(a.colour[i][k]) - double(sampled.colour[i][k]);
        sum += std::abs(double(sampled.colour[i][k]));
      }
    }
    std::printf("roughness %.1f: hosts differ by %.2e, pre-convolved from sampled by %.4f (relative L1), bias %.4f\n",
                roughness, hosts / sum, near / sum, bias / sum);
    ASSERT_GT(sum, 0);
    EXPECT_LT(hosts / sum, 1e-3) << "roughness " << roughness;
    EXPECT_LT(near / sum, 0.1) << "roughness " << roughness;
    EXPECT_LT(std::abs(bias / sum), 0.03) << "roughness " << roughness;
    test::save_for_inspection(a, "forward_preconvolved_" + std::to_string(int(roughness * 10)));
    test::save_for_inspection(sampled, "forward_sampled_" + std::to_string(int(roughness * 10)));
  }
}

// A measured BRDF against the pre-convolved map (Bagher et al. 2013, Eq.
// 10): sampled from the BRDF alone, each sample reading the map
// pre-convolved at the BRDF's sharpest lobe. In the furnace every lookup is
// exact, so it converges to what sampling the map as it is gives; under 64
// stripes (2.8 degrees each, the lobe about 8 degrees wide) it is much less
// noisy than sampling the map as it is from the BRDF (the paper's
// mechanism: the frequencies the BRDF removes are gone from the
// integrand); the hosts agree.
TEST_F(ForwardOnBothHosts, PreconvolvedMeasuredBrdfReadsTheFilteredMap) {
  const Material merl = test::sg_merl_material(200.0, 8.0, 0.1);
  const Environment furnace = constant_environment(glm::vec3(1.0f));
  RenderSettings s = settings(furnace, merl, 1024);
  const Frame raw = renderers_[0]->render(s);
  s.shading.preconvolved = std::make_shared<const PreconvolvedEnvironment>(preconvolve_environment(furnace));
  s.shading.spp = 64;
  for (auto& r : renderers_) {
    const Frame f = r->render(s);
    double l1 = 0, bias = 0, sum = 0;
    for (size_t i = 0; i < f.colour.size(); ++i) {
      if (!(raw.colour[i].a > 0.99f)) continue;
      l1 += std::abs(double(f.colour[i].g) - double(raw.colour[i].g));
      bias += double(f.colour[i].g) - double(raw.colour[i].g);
      sum += double(raw.colour[i].g);
    }
    std::printf("%s: furnace, pre-convolved against the map: relative L1 %.4f, bias %.4f\n", host_name(r->host()),
                l1 / sum, bias / sum);
    ASSERT_GT(sum, 0);
    EXPECT_LT(l1 / sum, 0.05) << host_name(r->host());
    EXPECT_LT(std::abs(bias / sum), 0.01) << host_name(r->host());
  }

  const Environment lines = test::stripes(64);
  s = settings(lines, merl, 4);
  s.shading.brdf_sampling = true;
  // The noise of a frame: two seeds' squared difference over the signal.
  auto noise = [&](Renderer& r, const RenderSettings& t) {
    RenderSettings u = t;
    const Frame a = r.render(u);
    u.shading.seed = 7;
    const Frame b = r.render(u);
    double diff = 0, sum = 0;
    for (size_t i = 0; i < a.colour.size(); ++i) {
      if (!(a.colour[i].a > 0.99f)) continue;
      const glm::vec3 d = glm::vec3(a.colour[i]) - glm::vec3(b.colour[i]);
      diff += glm::dot(d, d);
      sum += glm::dot(glm::vec3(a.colour[i]), glm::vec3(a.colour[i]));
    }
    return diff / std::max(sum, 1e-30);
  };
  RenderSettings pre = s;
  pre.shading.preconvolved = std::make_shared<const PreconvolvedEnvironment>(preconvolve_environment(lines));
  const double raw_noise = noise(*renderers_[0], s), pre_noise = noise(*renderers_[0], pre);
  std::printf("stripes, 4 spp from the BRDF: noise %.4f against the map, %.4f pre-convolved\n", raw_noise, pre_noise);
  EXPECT_LT(pre_noise, 0.25 * raw_noise);
  const Frame a = renderers_[0]->render(pre), b = renderers_[1]->render(pre);
  double hosts = 0, sum = 0;
  for (size_t i = 0; i < a.colour.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      hosts += std::abs(double(a.colour[i][k]) - double(b.colour[i][k]));
      sum += std::abs(double(a.colour[i][k]));
    }
  ASSERT_GT(sum, 0);
  EXPECT_LT(hosts / sum, 0.01);
  test::save_for_inspection(a, "forward_preconvolved_merl_stripes");
}

// A scene with five materials (its own, carried by the octree): both hosts
// look up the same materials into the G-buffer and shade each pixel with
// its own.
// The irradiance at the foot of the normal from the centre of a square of
// side `side` at height h, parallel to the plane, of radiance 1: pi times
// the form factor, four times the corner's (Howell's catalogue, C-11).
double square_irradiance(double side, double h) {
  const double a = 0.5 * side / h;
  const double r = std::sqrt(1 + a * a);
  return 4 * 0.5 * (2 * a / r * std::atan(a / r));
}

// An area light (Bagher et al. 2013, Fig. 17) sampled directly: a Lambert
// plane under a white square light parallel to it reflects albedo x L x
// the form factor at the foot of the light's normal, on both hosts; turned
// away, it lights nothing; a texture's texels are its radiance.
TEST(ForwardAreaLight, ALambertPlaneReflectsTheSquaresFormFactor) {
  test::HalfSpaceScene half({glm::vec3(-1.0f), glm::vec3(1.0f)});  // the face x = 0, colour 0.6
  const octree::Octree tree = test::voxelize(half, 64);
  vk::ContextOptions options;
  options.device = "llvmpipe";
  options.validation = true;
  vk::Context context(options);
  std::vector<std::unique_ptr<Renderer>> renderers;
  renderers.push_back(std::make_unique<NativeRenderer>(tree));
  renderers.push_back(std::make_unique<GpuRenderer>(context, tree));
  for (auto& r : renderers) r->add_pass(make_pass("forward"));
  Material white;
  white.kind = BrdfKind::Lambert;
  white.diffuse = glm::vec3(1.0f / 0.6f);  // times the plane's abar 0.6: albedo 1
  const float side = 0.4f, h = 0.3f, radiance = 2.0f;
  RenderSettings s;
  s.width = s.height = 16;
  s.camera = test::looking_at_origin({1.2f, 0.25f, 0.35f}, 10.0f);
  s.lights.clear();
  s.ambient = glm::vec3(0);
  s.shading.material = std::make_shared<const Material>(white);
  s.shading.spp = 1024;
  auto light = [&](glm::vec3 aim, std::vector<float> rgb, uint32_t w) {
    const auto rows = uint32_t(rgb.size() / 3 / w);
    return std::make_shared<const AreaLight>(AreaLight::placed({h, 0.0f, 0.0f}, aim, side, w, rows, rgb, "test"));
  };
  const double expected = radiance * square_irradiance(side, h) / M_PI;  // albedo 1: E / pi
  std::vector<glm::vec4> centre(2);
  for (size_t host = 0; host < 2; ++host) {
    Renderer& r = *renderers[host];
    s.shading.area_light = light({0.0f, 0.0f, 0.0f}, {radiance, radiance, radiance}, 1);
    const Frame f = r.render(s);
    // The four pixels about the frame's centre see the foot of the normal,
    // where the irradiance is flat.
    glm::vec4 c(0);
    for (uint32_t y = 7; y <= 8; ++y)
      for (uint32_t x = 7; x <= 8; ++x) c += 0.25f * f.colour[y * 16 + x];
    centre[host] = c;
    std::printf("%s: %.5f at the foot, closed form %.5f\n", host_name(r.host()), double(c.g), expected);
    EXPECT_NEAR(c.g, expected, 0.02 * expected) << host_name(r.host());
    // Turned away from the plane: nothing.
    s.shading.area_light = light({1.0f, 0.0f, 0.0f}, {radiance, radiance, radiance}, 1);
    const Frame away = r.render(s);
    float most = 0;
    for (const auto& p : away.colour) most = std::max(most, p.r + p.g + p.b);
    EXPECT_EQ(most, 0.0f) << host_name(r.host());
    // A 2 x 2 checker of radiances 2L and 0: at the foot each quadrant
    // gives a quarter of the square's light, so two of them at 2L give the
    // same; the importance sampling never draws the black ones.
    const float l2 = 2 * radiance;
    s.shading.area_light = light({0.0f, 0.0f, 0.0f}, {l2, l2, l2, 0, 0, 0, 0, 0, 0, l2, l2, l2}, 2);
    const Frame half_lit = r.render(s);
    glm::vec4 hc(0);
    for (uint32_t y = 7; y <= 8; ++y)
      for (uint32_t x = 7; x <= 8; ++x) hc += 0.25f * half_lit.colour[y * 16 + x];
    EXPECT_NEAR(hc.g, expected, 0.02 * expected) << host_name(r.host()) << ": the quadrants' sum by symmetry";
  }
  EXPECT_NEAR(centre[0].g, centre[1].g, 1e-3 * expected);
  // Refused: a light without area, a black one, with the pre-convolved map.
  AreaLight flat;
  flat.edge_v = flat.edge_u;
  EXPECT_THROW(validate_area_light(flat), std::invalid_argument);
  AreaLight black;
  black.rgb = {0, 0, 0};
  EXPECT_THROW(validate_area_light(black), std::invalid_argument);
  EXPECT_THROW(AreaLight::placed({0, 1, 0}, {0, 1, 0}, 1.0f, 1, 1, {1, 1, 1}, "test"), std::invalid_argument);
}

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
