// The frame as a chain of passes over typed images (render/pass.h) on both
// hosts: the same chains on the native host and on lavapipe agree, the
// chain refuses reads of images nobody writes and reads of another type, a
// pass sees this frame's G-buffer, and image sizes follow scale and levels.
#include "svo/render/pass.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../render/test_scenes.h"
#include "svo/render/image_io.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"

namespace svo::render {
namespace {

// A pass written once for both hosts (it works on the images' host memory,
// which both hosts map): colour = (coverage read from the G-buffer, 0, 0).
class CoverageToRed : public Pass {
 public:
  std::string name() const override { return "coverage-to-red"; }
  std::vector<ImageDesc> reads() const override { return {gbuffer_image()}; }
  std::vector<ImageDesc> writes() const override { return {colour_image()}; }
  double run(PassContext& ctx) override {
    auto g = ctx.images.texels<const glm::vec4>(ctx.images.read(gbuffer_image()));
    auto c = ctx.images.texels<glm::vec4>(ctx.images.write(colour_image()));
    const size_t n = size_t(ctx.images.width()) * ctx.images.height();
    for (size_t i = 0; i < n; ++i) {
      const float coverage = unpack_gbuffer(&g[kGBufferVec4s * i]).coverage;
      c[i] = glm::vec4(coverage, 0, 0, coverage);
    }
    return 0;
  }
};

class Reads : public CoverageToRed {
 public:
  explicit Reads(ImageDesc image) : image_(std::move(image)) {}
  std::vector<ImageDesc> reads() const override { return {image_}; }

 private:
  ImageDesc image_;
};

class PassesOnBothHosts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    test::SphereScene sphere(0.5f);
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
  }

  void TearDown() override {
    renderers_.clear();
    auto messages = context_->validation_messages();
    EXPECT_TRUE(messages.empty()) << messages.front();
  }

  static RenderSettings settings(glm::vec3 eye) {
    RenderSettings s;
    s.width = 40;
    s.height = 30;
    s.camera = test::looking_at_origin(eye, 35.0f);
    return s;
  }

  static octree::Octree* tree_;
  std::unique_ptr<vk::Context> context_;
  std::vector<std::unique_ptr<Renderer>> renderers_;  // native, Vulkan
};
octree::Octree* PassesOnBothHosts::tree_ = nullptr;

TEST_F(PassesOnBothHosts, TheSameChainAgreesOnBothHosts) {
  RenderSettings s = settings({0.5f, 0.5f, 2.5f});
  s.gbuffer = s.display = true;
  s.shadows = true;
  Frame native = renderers_[0]->render(s), vulkan = renderers_[1]->render(s);
  EXPECT_EQ(renderers_[0]->host(), Host::Native);
  EXPECT_EQ(renderers_[0]->device_type(), "native");
  EXPECT_EQ(renderers_[1]->host(), Host::Vulkan);
  ASSERT_EQ(native.colour.size(), vulkan.colour.size());
  ASSERT_EQ(native.gbuffer.size(), vulkan.gbuffer.size());
  // Tolerances: the two compilers may contract and order float operations
  // differently; a few pixels on the silhouette may pick another mask cell.
  int colour_off = 0, gbuffer_off = 0, display_off = 0;
  for (size_t i = 0; i < native.colour.size(); ++i) {
    colour_off += glm::length(native.colour[i] - vulkan.colour[i]) > 1e-3f ? 1 : 0;
    const GBufferTexel &a = native.gbuffer[i], &b = vulkan.gbuffer[i];
    const float d = std::abs(a.depth - b.depth) + glm::length(a.position - b.position) +
                    glm::length(a.normal - b.normal) + glm::length(a.tangent - b.tangent) +
                    glm::length(a.slope_cov - b.slope_cov) + glm::length(a.abar - b.abar) + glm::length(a.a_s - b.a_s) +
                    std::abs(a.coverage - b.coverage) + std::abs(a.sigma_rho2 - b.sigma_rho2);
    gbuffer_off += d > 1e-3f ? 1 : 0;
    for (int k = 0; k < 4; ++k) {
      display_off +=
          std::abs(int((native.display[i] >> (8 * k)) & 255u) - int((vulkan.display[i] >> (8 * k)) & 255u)) > 1;
    }
  }
  const int pixels = int(native.colour.size());
  EXPECT_LE(colour_off, pixels / 100) << "colour pixels apart by more than 1e-3";
  EXPECT_LE(gbuffer_off, pixels / 100) << "G-buffer texels apart by more than 1e-3";
  EXPECT_LE(display_off, pixels / 100) << "display bytes apart by more than 1";
  // Both hosts time each pass: trace, then display.
  for (const Frame* f : {&native, &vulkan}) {
    ASSERT_EQ(f->passes.size(), 2u);
    EXPECT_EQ(f->passes[0].name, "trace");
    EXPECT_EQ(f->passes[1].name, "display");
    EXPECT_GE(f->passes[0].ms, 0.0);
  }
  // The background's share is its own image: colour less it is the surface's.
  for (auto& r : renderers_) {
    FrameImages& images = r->images();
    auto c = images.texels<const glm::vec4>(images.read(colour_image()));
    auto bg = images.texels<const glm::vec4>(images.read(background_image()));
    for (size_t i = 0; i < native.colour.size(); ++i) {
      ASSERT_NEAR(bg[i].a, 1.0f - c[i].a, 1e-6f) << host_name(r->host()) << " pixel " << i;
      ASSERT_NEAR(bg[i].r, (1.0f - c[i].a) * s.background.r, 1e-6f) << host_name(r->host()) << " pixel " << i;
    }
  }
}

// Multisampling (RenderSettings::msaa): on both hosts the frame is the box
// filter of the same chain at 2x2 (4x4) samples per pixel, each a cone as
// narrow as the sample; a silhouette pixel's coverage is then the mean of
// its samples'. Other sample counts, and the G-buffer or display images
// with multisampling, are refused.
TEST_F(PassesOnBothHosts, MultisamplingIsTheBoxFilterOfTheSamples) {
  for (auto& r : renderers_) {
    for (uint32_t m : {2u, 4u}) {
      RenderSettings s = settings({0.5f, 0.5f, 2.5f});
      s.width = 20;
      s.height = 16;
      RenderSettings fine = s;
      fine.width *= m;
      fine.height *= m;
      s.msaa = m;
      const Frame f = r->render(s), samples = r->render(fine);
      ASSERT_EQ(f.width, 20u);
      ASSERT_EQ(f.colour.size(), size_t(20 * 16));
      // The chain's images are at the samples' size.
      EXPECT_EQ(r->images().width(), 20u * m);
      double worst = 0;
      uint32_t partial = 0;
      for (uint32_t y = 0; y < f.height; ++y)
        for (uint32_t x = 0; x < f.width; ++x) {
          glm::vec4 mean(0);
          for (uint32_t j = 0; j < m; ++j)
            for (uint32_t i = 0; i < m; ++i) mean += samples.colour[size_t(y * m + j) * fine.width + x * m + i];
          mean /= float(m * m);
          const glm::vec4 c = f.colour[size_t(y) * f.width + x];
          worst = std::max(worst, double(glm::length(c - mean)));
          partial += c.a > 0.01f && c.a < 0.99f ? 1 : 0;
        }
      EXPECT_LT(worst, 1e-6) << host_name(r->host()) << ", msaa " << m;
      EXPECT_GT(partial, 10u) << host_name(r->host()) << ": a silhouette of partly covered pixels";
    }
    RenderSettings bad = settings({0.5f, 0.5f, 2.5f});
    bad.msaa = 3;
    EXPECT_THROW(r->render(bad), std::invalid_argument);
    bad.msaa = 2;
    bad.gbuffer = true;
    EXPECT_THROW(r->render(bad), std::invalid_argument);
  }
}

TEST_F(PassesOnBothHosts, AnAddedPassRunsOnBothHostsAfterTheTracerAndBeforeTheDisplay) {
  RenderSettings s = settings({0.5f, 0.5f, 2.5f});
  s.display = true;
  for (auto& r : renderers_) r->add_pass(std::make_unique<CoverageToRed>());
  Frame native = renderers_[0]->render(s), vulkan = renderers_[1]->render(s);
  int off = 0, covered = 0;
  for (size_t i = 0; i < native.colour.size(); ++i) {
    off += std::abs(native.colour[i].r - vulkan.colour[i].r) > 0.02f ? 1 : 0;
    covered += native.colour[i].r > 0.5f ? 1 : 0;
    EXPECT_EQ((native.display[i] >> 8) & 0xFFFFu, 0u) << "the display pass ran before the added pass, pixel " << i;
  }
  EXPECT_GT(covered, 100);
  EXPECT_LE(off, int(native.colour.size()) / 100);
  EXPECT_EQ(native.passes.size(), 3u);
  EXPECT_EQ(native.passes[1].name, "coverage-to-red");
}

TEST_F(PassesOnBothHosts, APassReadsThisFramesGBufferEvenWhenTheSettingsDoNotAskForIt) {
  for (auto& r : renderers_) {
    // Frame 1 fills the G-buffer from one camera; frame 2 moves the camera
    // and does not ask for the G-buffer, but a pass reads it.
    RenderSettings first = settings({0.5f, 0.5f, 2.5f});
    first.gbuffer = true;
    r->render(first);
    RenderSettings second = settings({-2.0f, 0.3f, 0.2f});
    second.camera.fov_deg = 20;  // the sphere fills most of the frame
    Frame truth = r->render([&] {
      RenderSettings g = second;
      g.gbuffer = true;
      return g;
    }());
    r->add_pass(std::make_unique<CoverageToRed>());
    Frame seen = r->render(second);
    EXPECT_TRUE(seen.gbuffer.empty()) << "not asked for";
    for (size_t i = 0; i < seen.colour.size(); ++i) {
      ASSERT_NEAR(seen.colour[i].r, truth.gbuffer[i].coverage, 1e-6f) << host_name(r->host()) << " pixel " << i;
    }
  }
}

TEST_F(PassesOnBothHosts, ChainsThatReadWhatNobodyWritesOrAnotherTypeAreRefused) {
  for (auto& r : renderers_) {
    try {
      r->add_pass(std::make_unique<Reads>(ImageDesc{"environment", TexelFormat::Rgba32f}));
      ADD_FAILURE() << "a read of an image nobody writes was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'coverage-to-red'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("'environment'"), std::string::npos) << e.what();
    }
    for (const ImageDesc& wrong :
         {ImageDesc{"steps", TexelFormat::Rgba32f}, ImageDesc{"colour", TexelFormat::Rgba32f, 2},
          ImageDesc{"colour", TexelFormat::Rgba32f, 1, 3}}) {
      try {
        r->add_pass(std::make_unique<Reads>(wrong));
        ADD_FAILURE() << "a read of " << wrong.describe() << " was accepted";
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(wrong.describe()), std::string::npos) << what;                   // the type asked for
        EXPECT_NE(what.find("written as " + wrong.name + " ("), std::string::npos) << what;  // and the one written
      }
    }
    // Reading an image that exists but was not written this frame.
    Frame f = r->render(settings({0.5f, 0.5f, 2.5f}));
    EXPECT_THROW(r->images().read(gbuffer_image()), std::invalid_argument);
    EXPECT_NO_THROW(r->images().read(steps_image()));
  }
}

TEST_F(PassesOnBothHosts, AnAovFileHoldsTheNamedImage) {
  const std::string dir = ::testing::TempDir();
  RenderSettings s = settings({0.5f, 0.5f, 2.5f});
  s.gbuffer = true;
  for (auto& r : renderers_) {
    Frame f = r->render(s);
    const std::string g = dir + "/aov_gbuffer.exr", st = dir + "/aov_steps.exr";
    write_aov(g, *r, "gbuffer");
    write_aov(st, *r, "steps");
    Image gi = read_image(g), si = read_image(st);
    // OpenEXR stores channels sorted by layer: compare the sets.
    std::vector<std::string> names = gi.channels, expected(kGBufferChannels.begin(), kGBufferChannels.end());
    std::sort(names.begin(), names.end());
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(names, expected);
    ASSERT_EQ(si.channels, std::vector<std::string>{"steps"});
    const int depth = gi.channel("depth"), cov = gi.channel("coverage"), ty = gi.channel("T.y"),
              as = gi.channel("a_s.B");
    for (uint32_t y = 0; y < s.height; ++y) {
      for (uint32_t x = 0; x < s.width; ++x) {
        const GBufferTexel& t = f.gbuffer[y * s.width + x];
        ASSERT_EQ(gi.at(int(x), int(y), depth), t.depth);
        ASSERT_EQ(gi.at(int(x), int(y), cov), t.coverage);
        ASSERT_EQ(gi.at(int(x), int(y), ty), t.tangent.y);
        ASSERT_EQ(gi.at(int(x), int(y), as), t.a_s.z);
        ASSERT_EQ(si.at(int(x), int(y), 0), float(f.steps[y * s.width + x]));
      }
    }
    EXPECT_THROW(write_aov(dir + "/nope.exr", *r, "nope"), std::invalid_argument);
    EXPECT_THROW(write_aov(dir + "/g.png", *r, "gbuffer"), ImageError);
  }
}

// A pass that traces cones through the octree from G-buffer points: the
// sphere's lit side sees the light, its far side is shadowed by the sphere
// itself, on both hosts alike.
TEST_F(PassesOnBothHosts, TheVisibilityPassTracesConesFromGBufferPointsOnBothHosts) {
  RenderSettings s = settings({2.5f, 0.0f, 0.3f});
  s.lights = {Light{false, {0, 0, 1}, {3, 3, 3}, 0.02f}};  // from +z: the camera sees the terminator
  std::vector<std::vector<glm::vec4>> seen;
  Frame f;
  for (auto& r : renderers_) {
    r->add_pass(make_pass("visibility"));
    RenderSettings g = s;
    g.gbuffer = true;
    f = r->render(g);
    ASSERT_EQ(f.passes.size(), 2u);
    EXPECT_EQ(f.passes[1].name, "visibility");
    auto v = r->images().texels<const glm::vec4>(r->images().read(VisibilityPass::visibility_image()));
    seen.emplace_back(v.begin(), v.begin() + std::ptrdiff_t(f.colour.size()));
  }
  int lit = 0, lit_visible = 0, dark = 0, dark_hidden = 0, apart = 0;
  for (size_t i = 0; i < f.colour.size(); ++i) {
    apart += std::abs(seen[0][i].x - seen[1][i].x) > 0.02f ? 1 : 0;
    EXPECT_EQ(glm::vec3(seen[0][i].y, seen[0][i].z, seen[0][i].w), glm::vec3(1.0f)) << "absent lights, pixel " << i;
    const GBufferTexel& t = f.gbuffer[i];
    if (t.coverage < 1) continue;
    const float ndl = glm::normalize(t.normal).z;
    if (ndl > 0.3f) lit += 1, lit_visible += seen[0][i].x > 0.9f ? 1 : 0;
    if (ndl < -0.3f) dark += 1, dark_hidden += seen[0][i].x < 0.1f ? 1 : 0;
  }
  EXPECT_LE(apart, int(f.colour.size()) / 100) << "the hosts disagree";
  ASSERT_GT(lit, 30);
  ASSERT_GT(dark, 30);
  EXPECT_GE(lit_visible, lit * 95 / 100);
  EXPECT_GE(dark_hidden, dark * 95 / 100);
  EXPECT_THROW(make_pass("nope"), std::invalid_argument);
}

TEST(ImageDesc, ScaleAndLevelsGiveTheSizes) {
  ImageDesc half{"half", TexelFormat::Rgba32f, 2, 3};
  EXPECT_EQ(half.width(41), 21u);
  EXPECT_EQ(half.height(30), 15u);
  EXPECT_EQ(half.width(41, 1), 11u);
  EXPECT_EQ(half.height(30, 2), 4u);
  EXPECT_EQ(half.texels(41, 30), size_t(21 * 15 + 11 * 8 + 6 * 4));
  EXPECT_EQ(half.describe(), "half (rgba32f, 1/2, 3 levels)");
  EXPECT_EQ(texel_bytes(TexelFormat::GBuffer), 16 * kGBufferVec4s);
  ImageDesc one{"one", TexelFormat::R32u};
  EXPECT_EQ(one.width(1, 5), 1u);
}

TEST(Devices, NativeIsTheDefaultWithoutADiscreteOrIntegratedGpu) {
  bool gpu = false;
  for (const auto& d : vk::list_devices()) gpu = gpu || d.type == "discrete" || d.type == "integrated";
  EXPECT_EQ(resolve_device("") == "native", !gpu);
  EXPECT_EQ(resolve_device("native"), "native");
  EXPECT_NE(resolve_device("llvmpipe"), "native");
  try {
    resolve_device("no-such-device");
    ADD_FAILURE() << "no-such-device resolved";
  } catch (const vk::Error& e) {
    EXPECT_NE(std::string(e.what()).find("native"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace svo::render
