// The bandwidth-adaptive pass (render::AdaptivePass, shaders/common/
// bandwidth.glsl; Bagher et al. 2013, issue 17) on both hosts: forced to
// the finest level it is forward shading, pixel for pixel; a flat diffuse
// plane under a constant sky shades at the coarsest level, a mirror-like
// sphere under a map of fine stripes at the finest, with more samples per
// pixel than the plane; a measured BRDF against the pre-convolved map asks
// for fewer samples than against the map as it is; the hosts agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "../render/test_lighting.h"
#include "../render/test_scenes.h"
#include "common/shared_math.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/shading.h"

namespace svo::render {
namespace {

using test::stripes;

struct Hosts {
  std::unique_ptr<vk::Context> context;
  std::vector<std::unique_ptr<Renderer>> renderers;
  std::vector<AdaptivePass*> passes;

  explicit Hosts(const octree::Octree& tree) {
    vk::ContextOptions options;
    options.device = "llvmpipe";
    options.validation = true;
    context = std::make_unique<vk::Context>(options);
    renderers.push_back(std::make_unique<NativeRenderer>(tree));
    renderers.push_back(std::make_unique<GpuRenderer>(*context, tree));
    for (auto& r : renderers) {
      auto pass = std::make_unique<AdaptivePass>();
      passes.push_back(pass.get());
      r->add_pass(std::move(pass));
    }
  }
};

RenderSettings settings(const Camera& camera, const Environment& env, const Material& material, uint32_t spp) {
  RenderSettings s;
  s.width = 64;
  s.height = 64;
  s.camera = camera;
  s.lights.clear();
  s.ambient = glm::vec3(0);
  s.shading.environment = std::make_shared<const Environment>(env);
  s.shading.material = std::make_shared<const Material>(material);
  s.shading.spp = spp;
  return s;
}

// Level 0 of the bandwidth buffer, and the G-buffer's coverage.
struct Buffer {
  std::vector<glm::vec4> bandwidth;
  std::vector<float> coverage;
};

Buffer read_buffer(Renderer& r) {
  Buffer b;
  FrameImages& images = r.images();
  const auto bw = images.texels<glm::vec4>(images.read(AdaptivePass::bandwidth_image()));
  const auto g = images.texels<glm::vec4>(images.read(gbuffer_image()));
  const size_t n = size_t(images.width()) * images.height();
  b.bandwidth.assign(bw.begin(), bw.begin() + n);
  for (size_t i = 0; i < n; ++i) b.coverage.push_back(g[kGBufferVec4s * i + 1].w);
  return b;
}

TEST(AdaptivePass, AtTheFinestLevelItIsForwardShading) {
  test::SphereScene sphere(0.5f);
  const octree::Octree tree = test::voxelize(sphere, 64);
  Material glossy;
  glossy.kind = BrdfKind::Ggx;
  glossy.roughness = 0.2f;
  RenderSettings s = settings(test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f), test::sky(), glossy, 8);
  s.adaptive.finest = true;
  for (bool vulkan : {false, true}) {
    Hosts hosts(tree);
    auto& adaptive = *hosts.renderers[vulkan ? 1 : 0];
    std::unique_ptr<Renderer> forward;
    if (vulkan) {
      forward = std::make_unique<GpuRenderer>(*hosts.context, tree);
    } else {
      forward = std::make_unique<NativeRenderer>(tree);
    }
    forward->add_pass(make_pass("forward"));
    const Frame a = adaptive.render(s), f = forward->render(s);
    ASSERT_EQ(a.colour.size(), f.colour.size());
    double worst = 0;
    for (size_t i = 0; i < a.colour.size(); ++i)
      worst = std::max(worst, double(glm::length(a.colour[i] - f.colour[i])));
    std::printf("%s: finest adaptive against forward, largest difference %g\n", vulkan ? "vulkan" : "native", worst);
    // The same kernels, sample for sample: identical up to the device's
    // rounding of the same operations.
    EXPECT_LE(worst, vulkan ? 1e-4 : 0.0) << (vulkan ? "vulkan" : "native");
    const AdaptivePass::Stats& st = hosts.passes[vulkan ? 1 : 0]->stats();
    EXPECT_EQ(st.shaded, st.covered);
    EXPECT_EQ(st.samples, 8 * st.covered);
    EXPECT_TRUE(adaptive.validation_messages().empty());
  }
}

TEST(AdaptivePass, PlaneAtTheCoarsestLevelMirrorAtTheFinest) {
  Material lambert;
  lambert.kind = BrdfKind::Lambert;
  Material mirror;
  mirror.kind = BrdfKind::Ggx;
  mirror.roughness = 0.02f;
  mirror.f0 = glm::vec3(0.9f);
  // The face x = 0 of a half-space, head on, filling the frame.
  test::HalfSpaceScene half({glm::vec3(-1.0f), glm::vec3(1.0f)});
  const octree::Octree plane_tree = test::voxelize(half, 64);
  RenderSettings ps =
      settings(test::looking_at_origin({2.5f, 0.05f, 0.1f}, 30.0f), constant_environment(glm::vec3(1)), lambert, 16);
  test::SphereScene sphere(0.5f);
  const octree::Octree sphere_tree = test::voxelize(sphere, 64);
  RenderSettings ss = settings(test::looking_at_origin({0.0f, 0.2f, 1.3f}, 50.0f), stripes(64), mirror, 16);
  // Eq. 9's bound is conservative: a tau that keeps both under the cap of 256.
  ps.adaptive.tau = ss.adaptive.tau = 100.0f;
  for (size_t host = 0; host < 2; ++host) {
    Hosts planes(plane_tree), spheres(sphere_tree);
    planes.renderers[host]->render(ps);
    spheres.renderers[host]->render(ss);
    const Buffer p = read_buffer(*planes.renderers[host]);
    const Buffer m = read_buffer(*spheres.renderers[host]);
    // The pass's coarsest level for a 64 x 64 frame: min(7, bit_width(64) - 1) = 6.
    const float top = 6.0f;
    uint32_t plane_pixels = 0, plane_top = 0, sphere_pixels = 0, sphere_finest = 0;
    std::vector<float> plane_spp, sphere_spp;
    for (size_t i = 0; i < p.bandwidth.size(); ++i) {
      if (p.coverage[i] >= 0.999f) {
        ++plane_pixels;
        plane_top += std::floor(p.bandwidth[i].x) == top ? 1 : 0;
        plane_spp.push_back(p.bandwidth[i].y);
      }
      if (m.coverage[i] >= 0.999f) {
        ++sphere_pixels;
        sphere_finest += std::floor(m.bandwidth[i].x) == 0.0f ? 1 : 0;
        sphere_spp.push_back(m.bandwidth[i].y);
      }
    }
    ASSERT_GT(plane_pixels, 3000u);
    ASSERT_GT(sphere_pixels, 800u);
    std::sort(plane_spp.begin(), plane_spp.end());
    std::sort(sphere_spp.begin(), sphere_spp.end());
    const float plane_median = plane_spp[plane_spp.size() / 2], sphere_median = sphere_spp[sphere_spp.size() / 2];
    const AdaptivePass::Stats& pst = planes.passes[host]->stats();
    std::printf(
        "%s: plane %u/%u pixels at level %g (median N_p %g, %llu texels shaded); mirror sphere %u/%u at "
        "level 0 (median N_p %g)\n",
        host_name(planes.renderers[host]->host()), plane_top, plane_pixels, top, plane_median,
        (unsigned long long)pst.shaded, sphere_finest, sphere_pixels, sphere_median);
    EXPECT_GE(plane_top, 0.9 * plane_pixels);
    EXPECT_LT(pst.shaded, plane_pixels / 16);
    EXPECT_GE(sphere_finest, 0.9 * sphere_pixels);
    EXPECT_LT(plane_median, sphere_median);
  }
}

// Adaptive sampling for pre-convolved shading (Eq. 10): under 64 stripes a
// measured glossy BRDF sampled from itself needs many samples per pixel;
// against the map pre-convolved at its lobe the integrand keeps only the
// frequencies the BRDF passes, and both the measured variance and Eq. 10's
// bound (the light's band limited to the kernel's) ask for fewer.
TEST(AdaptivePass, PreconvolvedMeasuredBrdfAsksForFewerSamples) {
  test::SphereScene sphere(0.5f);
  const octree::Octree tree = test::voxelize(sphere, 64);
  const Environment env = stripes(64);
  const auto pre = std::make_shared<const PreconvolvedEnvironment>(preconvolve_environment(env));
  RenderSettings s =
      settings(test::looking_at_origin({0.0f, 0.2f, 1.3f}, 50.0f), env, test::sg_merl_material(200.0, 8.0, 0.1), 16);
  s.shading.brdf_sampling = true;  // the paper's sampling of the map as it is
  s.adaptive.max_spp = 64;         // the map as it is reaches the cap: a cheaper test, the same verdict
  Hosts hosts(tree);
  for (size_t host = 0; host < 2; ++host) {
    Renderer& r = *hosts.renderers[host];
    // Medians over fully covered pixels of N_p (measured) and of Eq. 9/10's
    // relative variance bound (z).
    auto medians = [&](bool measured, bool preconvolved) {
      RenderSettings t = s;
      t.adaptive.measured_variance = measured;
      t.adaptive.tau = measured ? 0.003f : 100.0f;
      if (preconvolved) t.shading.preconvolved = pre;
      r.render(t);
      const Buffer b = read_buffer(r);
      std::vector<float> np, bound;
      for (size_t i = 0; i < b.bandwidth.size(); ++i) {
        if (!(b.coverage[i] >= 0.999f)) continue;
        np.push_back(b.bandwidth[i].y);
        bound.push_back(b.bandwidth[i].z);
      }
      EXPECT_GT(np.size(), 800u);
      std::sort(np.begin(), np.end());
      std::sort(bound.begin(), bound.end());
      return glm::vec2(np[np.size() / 2], bound[bound.size() / 2]);
    };
    const glm::vec2 raw_measured = medians(true, false), pre_measured = medians(true, true);
    const glm::vec2 raw_bound = medians(false, false), pre_bound = medians(false, true);
    std::printf("%s: median N_p (measured) %g against the map, %g pre-convolved; Eq. 9 bound %g, Eq. 10 %g\n",
                host_name(r.host()), raw_measured.x, pre_measured.x, raw_bound.y, pre_bound.y);
    EXPECT_LT(pre_measured.x, 0.5f * raw_measured.x) << host_name(r.host());
    EXPECT_LT(pre_bound.y, raw_bound.y) << host_name(r.host());
  }
}

// Adaptive multisample anti-aliasing (section 4.3, Fig. 19): at 4x4
// samples per pixel forward shading shades every sample, 16 times the
// pixels; the adaptive pass shades the smooth surface at coarser levels
// and the samples at the finest only where the bandwidth asks (the
// silhouette), far fewer than 16 times its shaded texels at 1 sample (under 5 times:
// cost growing as samples^0.58 at most; the paper measures 0.7).
TEST(AdaptivePass, MultisamplingShadesFewSamplesAtTheFinestLevel) {
  test::SphereScene sphere(0.5f);
  const octree::Octree tree = test::voxelize(sphere, 64);
  Material diffuse;
  diffuse.kind = BrdfKind::Lambert;
  RenderSettings s = settings(test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f), test::sky(64, 32, false), diffuse, 4);
  s.width = s.height = 32;
  s.adaptive.measured_variance = true;
  s.adaptive.tau = 0.05f;
  Hosts hosts(tree);
  for (size_t host = 0; host < 2; ++host) {
    Renderer& r = *hosts.renderers[host];
    r.render(s);
    const AdaptivePass::Stats one = hosts.passes[host]->stats();
    RenderSettings m = s;
    m.msaa = 4;
    const Frame f = r.render(m);
    const AdaptivePass::Stats sixteen = hosts.passes[host]->stats();
    std::printf("%s: %llu texels shaded at 1 sample per pixel, %llu at 16 (%llu samples covered)\n",
                host_name(r.host()), (unsigned long long)one.shaded, (unsigned long long)sixteen.shaded,
                (unsigned long long)sixteen.covered);
    ASSERT_GT(one.shaded, 0u);
    EXPECT_EQ(f.colour.size(), size_t(32 * 32));
    EXPECT_GT(sixteen.covered, 15 * one.covered);
    EXPECT_LT(sixteen.shaded, 5 * one.shaded) << host_name(r.host());
  }
}

// Area lights (section 4.3, Fig. 17): the light's spatial bandwidth
// enters by transport from the light. Under a checkered light a glossy
// plane asks for finer levels than under a white light of the same mean
// radiance, whose texture has frequencies only at its outline; on both
// hosts, which agree.
TEST(AdaptivePass, ACheckeredAreaLightAsksForFinerLevelsThanAWhiteOne) {
  test::HalfSpaceScene half({glm::vec3(-1.0f), glm::vec3(1.0f)});
  const octree::Octree tree = test::voxelize(half, 64);
  Material glossy;
  glossy.kind = BrdfKind::Ggx;
  glossy.roughness = 0.1f;
  glossy.f0 = glm::vec3(0.5f);
  RenderSettings s =
      settings(test::looking_at_origin({1.6f, 0.4f, 0.5f}, 40.0f), constant_environment(glm::vec3(1)), glossy, 16);
  s.shading.environment = nullptr;
  const uint32_t n = 16;
  std::vector<float> checker(size_t(n) * n * 3), white(size_t(n) * n * 3, 2.0f);
  for (uint32_t i = 0; i < n * n; ++i)
    for (uint32_t c = 0; c < 3; ++c) checker[3 * i + c] = ((i % n) / 2 + (i / n) / 2) % 2 == 0 ? 4.0f : 0.0f;
  auto light = [&](std::vector<float> rgb) {
    return std::make_shared<const AreaLight>(
        AreaLight::placed({0.5f, 0.3f, 0.0f}, {0.0f, 0.0f, 0.0f}, 0.6f, n, n, std::move(rgb), "test"));
  };
  std::vector<double> medians[2];
  for (size_t host = 0; host < 2; ++host) {
    Hosts hosts(tree);
    for (bool checkered : {false, true}) {
      s.shading.area_light = light(checkered ? checker : white);
      hosts.renderers[host]->render(s);
      const Buffer b = read_buffer(*hosts.renderers[host]);
      std::vector<float> levels;
      for (size_t i = 0; i < b.bandwidth.size(); ++i)
        if (b.coverage[i] >= 0.999f) levels.push_back(b.bandwidth[i].x);
      ASSERT_GT(levels.size(), 1000u);
      std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
      medians[host].push_back(levels[levels.size() / 2]);
    }
    std::printf("%s: median level %.2f under the white light, %.2f under the checkered one\n",
                host == 0 ? "native" : "vulkan", medians[host][0], medians[host][1]);
    EXPECT_LT(medians[host][1], medians[host][0] - 0.5) << (host == 0 ? "native" : "vulkan");
  }
  EXPECT_NEAR(medians[0][0], medians[1][0], 0.05);
  EXPECT_NEAR(medians[0][1], medians[1][1], 0.05);
}

TEST(AdaptivePass, HostsAgree) {
  test::SphereScene sphere(0.5f);
  const octree::Octree tree = test::voxelize(sphere, 64);
  Material glossy;
  glossy.kind = BrdfKind::Beckmann;
  glossy.roughness = 0.15f;
  RenderSettings s = settings(test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f), test::sky(64, 32, false), glossy, 16);
  s.adaptive.tau = 0.5f;
  Hosts hosts(tree);
  const Frame n = hosts.renderers[0]->render(s);
  const Frame v = hosts.renderers[1]->render(s);
  const Buffer bn = read_buffer(*hosts.renderers[0]), bv = read_buffer(*hosts.renderers[1]);
  uint32_t covered = 0, same_level = 0;
  double sq = 0, ref = 0;
  for (size_t i = 0; i < n.colour.size(); ++i) {
    const glm::vec3 d = glm::vec3(n.colour[i]) - glm::vec3(v.colour[i]);
    sq += glm::dot(d, d);
    ref += glm::dot(glm::vec3(n.colour[i]), glm::vec3(n.colour[i]));
    if (bn.coverage[i] > 0) {
      ++covered;
      same_level += std::floor(bn.bandwidth[i].x) == std::floor(bv.bandwidth[i].x) ? 1 : 0;
    }
  }
  const double rel = std::sqrt(sq / std::max(ref, 1e-30));
  std::printf("hosts: relative RMS difference %g, %u/%u pixels at the same level; shaded %llu and %llu texels\n", rel,
              same_level, covered, (unsigned long long)hosts.passes[0]->stats().shaded,
              (unsigned long long)hosts.passes[1]->stats().shaded);
  EXPECT_GT(covered, 500u);
  EXPECT_GE(same_level, 0.98 * covered);
  EXPECT_LT(rel, 0.02);
  EXPECT_TRUE(hosts.renderers[1]->validation_messages().empty());
}

}  // namespace
}  // namespace svo::render
