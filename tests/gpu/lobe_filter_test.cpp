// Specular lobe-aware filtering and upsampling (Tokuyoshi 2015;
// render::LobeFilterPass, shaders/common/lobe_filter.glsl) on both hosts
// (the native kernels and lavapipe, validation on): the hosts agree for
// every weight and scale, a noise-free image stays as it is and a noisy
// one never leaves the range of its input, filtering a noisy glossy frame
// brings it closer to a converged one, adaptive recomputation shades again
// exactly the pixels under the threshold (and then gives the full-size
// forward frame), and the chain refuses a filter without the forward
// pass's split images at its scale.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../render/test_lighting.h"
#include "../render/test_scenes.h"
#include "svo/render/passes.h"
#include "svo/render/renderer.h"
#include "svo/render/shading.h"

namespace svo::render {
namespace {

constexpr FilterWeight kWeights[] = {FilterWeight::None, FilterWeight::Normal, FilterWeight::Lobe,
                                     FilterWeight::Mixture, FilterWeight::Asg};

// How far two images are apart, per texel the largest difference of R, G
// and B: root mean square, 99th percentile and largest over the texels.
struct Apart {
  double rmse = 0, p99 = 0, max = 0;
};

Apart apart(const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
  std::vector<double> d;
  double sum = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    double e = 0;
    for (int k = 0; k < 3; ++k) e = std::max(e, std::abs(double(a[i][k]) - double(b[i][k])));
    d.push_back(e);
    sum += e * e;
  }
  Apart r;
  if (d.empty()) return r;
  std::sort(d.begin(), d.end());
  r.rmse = std::sqrt(sum / double(d.size()));
  r.p99 = d[size_t(0.99 * double(d.size() - 1))];
  r.max = d.back();
  return r;
}

// The mean squared error of `a` against `truth` (per channel) over the pixels `truth` covers.
double covered_mse(const Frame& a, const Frame& truth) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < truth.colour.size(); ++i) {
    if (!(truth.colour[i].a > 0)) continue;
    for (int k = 0; k < 3; ++k) sum += std::pow(double(a.colour[i][k]) - double(truth.colour[i][k]), 2);
    ++n;
  }
  return n ? sum / double(3 * n) : 0;
}

size_t covered_pixels(const Frame& f) {
  return size_t(std::count_if(f.colour.begin(), f.colour.end(), [](const glm::vec4& c) { return c.a > 0; }));
}

// A copy of the last frame's image `desc` (its texels at its own scale).
std::vector<glm::vec4> image_copy(Renderer& r, const ImageDesc& desc) {
  auto t = r.images().texels<const glm::vec4>(r.images().read(desc));
  const size_t n = size_t(desc.width(r.images().width())) * desc.height(r.images().height());
  return {t.begin(), t.begin() + std::ptrdiff_t(n)};
}

std::vector<glm::vec4> filter_weights(Renderer& r) { return image_copy(r, LobeFilterPass::weight_image()); }

// Between the forward pass and the filter: replaces the split images with
// the texels given (when given), so that the filter on the Vulkan host
// reads what the native host's forward pass wrote and the hosts' filters
// can be compared without the forward pass's own differences.
class InjectSplit : public Pass {
 public:
  explicit InjectSplit(uint32_t scale) : scale_(scale) {}
  std::string name() const override { return "inject-split"; }
  std::vector<ImageDesc> reads() const override { return {diffuse_image(scale_), specular_image(scale_)}; }
  std::vector<ImageDesc> writes() const override { return reads(); }
  double run(PassContext& ctx) override {
    if (diffuse.empty()) return 0;
    for (auto [desc, from] :
         {std::pair{diffuse_image(scale_), &diffuse}, std::pair{specular_image(scale_), &specular}}) {
      auto to = ctx.images.texels<glm::vec4>(ctx.images.write(desc));
      if (to.size() < from->size()) throw std::logic_error("inject-split: the image is smaller than the texels given");
      std::copy(from->begin(), from->end(), to.begin());
    }
    return 0;
  }
  std::vector<glm::vec4> diffuse, specular;  // empty: leave the images as they are

 private:
  uint32_t scale_;
};

// Whether the frame ran a pass of this name.
bool has_pass(const Frame& f, const std::string& name) {
  return std::any_of(f.passes.begin(), f.passes.end(), [&](const PassTime& p) { return p.name == name; });
}

// Two frames of the filter from the same input, over the covered pixels
// neither shaded again (filter_weight.z 0 in both; every covered pixel
// when the weights are not given): the largest difference on the fully
// covered pixels relative to max(1, |colour|), and on all of them.
struct SameInput {
  size_t covered = 0, full = 0;
  double full_relative = 0, any = 0;
};

SameInput same_input(const Frame& a, const Frame& b, const std::vector<glm::vec4>* wa = nullptr,
                     const std::vector<glm::vec4>* wb = nullptr) {
  SameInput r;
  for (size_t i = 0; i < a.colour.size(); ++i) {
    if (!(a.colour[i].a > 0)) continue;
    if (wa && wb && ((*wa)[i].z != 0.0f || (*wb)[i].z != 0.0f)) continue;
    ++r.covered;
    const bool full = a.colour[i].a >= 0.999f;
    r.full += full;
    for (int k = 0; k < 3; ++k) {
      const double e = std::abs(double(a.colour[i][k]) - double(b.colour[i][k]));
      r.any = std::max(r.any, e);
      if (full) r.full_relative = std::max(r.full_relative, e / std::max(1.0, std::abs(double(a.colour[i][k]))));
    }
  }
  return r;
}

// A voxelized sphere (64^3, colour 0.5) in a 48x40 frame. The renderers
// live as long as the suite: each Vulkan chain compiles its kernels on
// lavapipe at its first frame (seconds), once.
class LobeFilterOnBothHosts : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    test::SphereScene sphere(0.5f);
    tree_ = new octree::Octree(test::voxelize(sphere, 64));
    vk::ContextOptions options;
    options.device = "llvmpipe";
    options.validation = true;
    context_ = new vk::Context(options);
  }
  static void TearDownTestSuite() {
    chains_.clear();
    kept_environments_.clear();
    kept_materials_.clear();
    delete context_;
    delete tree_;
  }

  // No validation message during the test.
  void SetUp() override { messages_before_ = context_->validation_messages().size(); }
  void TearDown() override {
    const auto messages = context_->validation_messages();
    EXPECT_EQ(messages.size(), messages_before_) << messages.back();
  }

  // A native and a Vulkan renderer with the same chain.
  struct Hosts {
    std::unique_ptr<Renderer> native, vulkan;
    InjectSplit* inject = nullptr;  // the Vulkan chain's, between the forward pass and the filter
  };
  // The renderer of host k (0: native, 1: Vulkan) whose chain is, for
  // scale 0, the forward pass alone (unsplit, full size); for 1, 2, 4, the
  // forward pass split at 1/scale and the lobe-aware filter at that scale
  // (on the Vulkan host with an InjectSplit pass between them, idle unless
  // a test gives it texels). Made at its first use.
  static Renderer& renderer(uint32_t scale, int k) {
    Hosts& h = chains_[scale];
    std::unique_ptr<Renderer>& r = k == 0 ? h.native : h.vulkan;
    if (r) return *r;
    if (k == 0) {
      r = std::make_unique<NativeRenderer>(*tree_);
    } else {
      r = std::make_unique<GpuRenderer>(*context_, *tree_);
    }
    if (scale == 0) {
      r->add_pass(std::make_unique<ForwardPass>());
      return *r;
    }
    r->add_pass(std::make_unique<ForwardPass>(ForwardOutput{true, scale}));
    if (k == 1) {
      auto inject = std::make_unique<InjectSplit>(scale);
      h.inject = inject.get();
      r->add_pass(std::move(inject));
    }
    r->add_pass(std::make_unique<LobeFilterPass>(scale));
    return *r;
  }
  static Hosts& chain(uint32_t scale) {
    renderer(scale, 0);
    renderer(scale, 1);
    return chains_[scale];
  }

  // The environment and the material are kept alive for the suite: the
  // renderers' shading caches take a new object at a freed one's address
  // for the old one (the bug NewShadingOptionsAtAFreedOnesAddressAreNotTakenForThem
  // shows), which would let one test's options leak into the next.
  static RenderSettings settings(std::shared_ptr<const Environment> env, const Material& material, uint32_t spp) {
    RenderSettings s;
    s.width = 48;
    s.height = 40;
    s.camera = test::looking_at_origin({0.4f, 0.3f, 1.6f}, 45.0f);
    s.lights.clear();
    s.ambient = glm::vec3(0);
    s.shading.environment = std::move(env);
    s.shading.material = std::make_shared<const Material>(material);
    s.shading.spp = spp;
    kept_environments_.push_back(s.shading.environment);
    kept_materials_.push_back(s.shading.material);
    return s;
  }

  // Glossy: Beckmann, alpha 0.2, a coloured metal-like f0 over a diffuse part.
  static Material glossy() {
    Material m;
    m.kind = BrdfKind::Beckmann;
    m.diffuse = glm::vec3(0.6f);
    m.f0 = glm::vec3(0.9f, 0.7f, 0.4f);
    m.roughness = 0.2f;
    return m;
  }

  // Lambert of albedo 1 (2 times the sphere's abar 0.5).
  static Material white() {
    Material m;
    m.kind = BrdfKind::Lambert;
    m.diffuse = glm::vec3(2.0f);
    return m;
  }

  static octree::Octree* tree_;
  static vk::Context* context_;
  static std::map<uint32_t, Hosts> chains_;
  static std::vector<std::shared_ptr<const Environment>> kept_environments_;
  static std::vector<std::shared_ptr<const Material>> kept_materials_;
  size_t messages_before_ = 0;
};

octree::Octree* LobeFilterOnBothHosts::tree_ = nullptr;
vk::Context* LobeFilterOnBothHosts::context_ = nullptr;
std::map<uint32_t, LobeFilterOnBothHosts::Hosts> LobeFilterOnBothHosts::chains_;
std::vector<std::shared_ptr<const Environment>> LobeFilterOnBothHosts::kept_environments_;
std::vector<std::shared_ptr<const Material>> LobeFilterOnBothHosts::kept_materials_;

// Filtering (scale 1) with each weight, and lobe-aware upsampling from 1/2
// and 1/4: the same frame on both hosts.
//
// Twice: as the chain runs, and with the Vulkan filter reading the native
// forward pass's split images (InjectSplit).
//
// As it runs: the forward pass alone already differs between the hosts by
// float rounding: at 16 spp here its colours are within 2e-6 on 99% of the
// pixels, but a few pixels differ by up to 4e-2 (a sample that lands on the
// other side of a step of the environment's CDF: the sun patch of radiance
// 40 is then seen or missed). The filter spreads each such pixel over its
// neighbours with its weights, so after filtering the 99th percentile rises
// to about 6e-4 (measured: RMSE 1.3e-4 to 6.1e-4, p99 1.7e-4 to 6.4e-4,
// largest 1.6e-3 to 2.6e-2; upsampling: RMSE 9.9e-4, p99 1.4e-4, largest
// 4.4e-2, the forward pass's own difference on a pixel shaded again). The
// largest is not bounded for that reason; RMSE and p99 are bounded at 3e-3,
// a few times what was measured and well under what a wrong weight on one
// host gives (1e-2 and more on most of the surface).
//
// The same input: what is left is the hosts' rounding in the G-buffer, the
// lobes, the weights and the weighted sums. On the fully covered pixels not
// shaded again: within 5e-5 relative to max(1, |colour|) (measured 1.1e-7
// to 4.2e-6, the largest with the ASG weight). Partly covered pixels add
// the background's share, the environment seen through the pixel, whose
// lookup the hosts round apart by up to 1.4e-4 where the sky meets the
// ground (uncovered pixels show the same): 3e-4 on all covered pixels
// (measured 1.8e-5 to 1.4e-4). The filter's total weights, which do not
// depend on the forward pass's samples, must agree within 1e-4 everywhere
// (measured largest 1e-5).
TEST_F(LobeFilterOnBothHosts, BothHostsAgreeForEveryWeightAndScale) {
  RenderSettings s = settings(std::make_shared<const Environment>(test::sky()), glossy(), 16);
  s.shading.env_rotate_deg = 30;
  struct Case {
    uint32_t scale;
    FilterWeight weight;
  };
  std::vector<Case> cases;
  for (FilterWeight w : kWeights) cases.push_back({1, w});
  cases.push_back({2, FilterWeight::Lobe});
  cases.push_back({4, FilterWeight::Lobe});
  std::map<std::string, std::vector<glm::vec4>> native_frames;
  for (const Case& c : cases) {
    Hosts& h = chain(c.scale);
    s.filter.weight = c.weight;
    const std::string label = "1/" + std::to_string(c.scale) + " " + filter_weight_name(c.weight);
    const Frame a = h.native->render(s);
    const Frame b = h.vulkan->render(s);
    ASSERT_EQ(a.colour.size(), b.colour.size());
    for (const Frame* f : {&a, &b}) {
      EXPECT_TRUE(has_pass(*f, "forward-split")) << label;
      ASSERT_FALSE(f->passes.empty());
      EXPECT_EQ(f->passes.back().name, c.scale == 1 ? "lobe-filter" : "lobe-upsample") << label;
    }
    EXPECT_GT(covered_pixels(a), 500u);
    const auto wa = filter_weights(*h.native), wb = filter_weights(*h.vulkan);
    const Apart colour = apart(a.colour, b.colour);
    const Apart weight = apart(wa, wb);
    // The Vulkan filter on the native forward pass's images.
    h.inject->diffuse = image_copy(*h.native, diffuse_image(c.scale));
    h.inject->specular = image_copy(*h.native, specular_image(c.scale));
    const Frame c_frame = h.vulkan->render(s);
    h.inject->diffuse.clear();
    h.inject->specular.clear();
    const auto wc = filter_weights(*h.vulkan);
    const SameInput same = same_input(a, c_frame, &wa, &wc);
    std::printf(
        "%-11s: colours apart by RMSE %.2e, p99 %.2e, largest %.2e; from the same input by %.2e relative on %zu "
        "fully covered pixels, %.2e on %zu covered; total weights by largest %.2e\n",
        label.c_str(), colour.rmse, colour.p99, colour.max, same.full_relative, same.full, same.any, same.covered,
        weight.max);
    EXPECT_LT(colour.rmse, 3e-3) << label;
    EXPECT_LT(colour.p99, 3e-3) << label;
    EXPECT_LT(weight.max, 1e-4) << label;
    EXPECT_GT(same.full, 100u) << label;
    EXPECT_LT(same.full_relative, 5e-5) << label;
    EXPECT_LT(same.any, 3e-4) << label;
    native_frames[label] = a.colour;
  }
  // Each weight reaches the kernels: the frames of none, normal and lobe
  // differ by far more than the hosts do.
  EXPECT_GT(apart(native_frames["1/1 none"], native_frames["1/1 normal"]).rmse, 1e-2);
  EXPECT_GT(apart(native_frames["1/1 normal"], native_frames["1/1 lobe"]).rmse, 1e-2);
}

// The ambient furnace, noise-free: no environment and no lights, ambient 2
// times the sphere's abar 0.5 on a Lambert material, and background 1: every
// covered texel of the forward pass's diffuse image is 1 per unit coverage
// (no samples: no noise), the specular image is 0, and every pixel of the
// filtered or upsampled frame (background share included) is 1, for every
// weight and on both hosts. Measured: within 2.4e-7 (float rounding of the
// weighted sums); bound 1e-5.
TEST_F(LobeFilterOnBothHosts, ANoiseFreeImageStaysAsItIs) {
  RenderSettings s = settings(nullptr, white(), 1);
  s.ambient = glm::vec3(2.0f);
  s.background = glm::vec3(1.0f);
  for (uint32_t scale : {1u, 2u, 4u}) {
    for (FilterWeight w : kWeights) {
      if (scale != 1 && w != FilterWeight::Lobe && w != FilterWeight::Mixture) continue;
      s.filter.weight = w;
      for (int k = 0; k < 2; ++k) {
        Renderer& r = renderer(scale, k);
        const std::string label =
            std::string(host_name(r.host())) + " 1/" + std::to_string(scale) + " " + filter_weight_name(w);
        const Frame f = r.render(s);
        const auto d = image_copy(r, diffuse_image(scale)), sp = image_copy(r, specular_image(scale));
        double in_worst = 0, spec_worst = 0, out_worst = 0;
        size_t covered = 0;
        for (size_t i = 0; i < d.size(); ++i) {
          if (!(d[i].a > 0)) continue;
          ++covered;
          for (int c = 0; c < 3; ++c) {
            in_worst = std::max(in_worst, std::abs(d[i][c] / d[i].a - 1.0));
            spec_worst = std::max(spec_worst, std::abs(double(sp[i][c])));
          }
        }
        for (const glm::vec4& c : f.colour)
          for (int ch = 0; ch < 3; ++ch) out_worst = std::max(out_worst, std::abs(c[ch] - 1.0));
        EXPECT_GT(covered, 400u / (scale * scale)) << label;
        EXPECT_LT(in_worst, 1e-5) << label << ": the forward pass's diffuse image is not 1";
        EXPECT_EQ(spec_worst, 0.0) << label << ": a Lambert material has no specular part";
        EXPECT_LT(out_worst, 1e-5) << label << ": the filter changed a constant image";
      }
    }
  }
}

// The white furnace (a constant white environment, Lambert of albedo 1):
// the forward pass's estimate is 1 in expectation but noisy at 64 spp
// (measured: texels up to 5.1e-2 off at 1/1, 4.1e-2 at 1/2, 2.8e-2 at
// 1/4). The filter takes weighted means per unit coverage, so no pixel may
// leave the range of its input (plus 1e-5 for rounding), and a pixel shaded
// again must equal the full-size forward frame's (1e-5). At 1/1 the
// filter must lower the mean squared distance to 1. Measured at 1/1: the
// worst pixel 0.9e-2 (none) to 1.7e-2 (normal) off. On the native host
// (lavapipe gave the same numbers; the hosts' agreement is
// BothHostsAgreeForEveryWeightAndScale's, and the noise-free furnace runs
// on both).
TEST_F(LobeFilterOnBothHosts, TheWhiteFurnaceStaysWithinItsInputsRange) {
  RenderSettings s = settings(std::make_shared<const Environment>(constant_environment(glm::vec3(1.0f))), white(), 64);
  for (int k : {0}) {
    const Frame full = renderer(0, k).render(s);
    for (uint32_t scale : {1u, 2u, 4u}) {
      for (FilterWeight w : kWeights) {
        if (scale != 1 && w != FilterWeight::Lobe) continue;
        s.filter.weight = w;
        Renderer& r = renderer(scale, k);
        const std::string label =
            std::string(host_name(r.host())) + " 1/" + std::to_string(scale) + " " + filter_weight_name(w);
        const Frame f = r.render(s);
        const auto d = image_copy(r, diffuse_image(scale)), sp = image_copy(r, specular_image(scale));
        const auto weights = filter_weights(r);
        double in_worst = 0, in_sq = 0, out_worst = 0, out_sq = 0, again_worst = 0;
        size_t in_n = 0, out_n = 0;
        for (size_t i = 0; i < d.size(); ++i) {
          if (!(d[i].a > 0)) continue;
          ++in_n;
          for (int c = 0; c < 3; ++c) {
            const double e = d[i][c] / d[i].a - 1.0;
            in_worst = std::max(in_worst, std::abs(e));
            in_sq += e * e;
            ASSERT_EQ(sp[i][c], 0.0f) << label << ": a Lambert material has no specular part";
          }
        }
        for (size_t i = 0; i < f.colour.size(); ++i) {
          for (int c = 0; c < 3; ++c) {
            const double e = f.colour[i][c] - 1.0;
            if (weights[i].z == 1.0f) {
              again_worst = std::max(again_worst, std::abs(double(f.colour[i][c]) - double(full.colour[i][c])));
              continue;
            }
            out_worst = std::max(out_worst, std::abs(e));
            if (f.colour[i].a > 0) out_sq += e * e, out_n += c == 0;
          }
        }
        std::printf("%-18s: input within %.2e of 1, output %.2e, shaded again within %.2e of the full-size frame\n",
                    label.c_str(), in_worst, out_worst, again_worst);
        ASSERT_GT(in_n, 30u) << label;
        EXPECT_LT(in_worst, 0.1) << label << ": the forward pass is not 1 within its noise";
        EXPECT_LE(out_worst, in_worst + 1e-5) << label << ": a pixel left the range of the filter's input";
        EXPECT_LE(again_worst, 1e-5) << label;
        if (scale == 1) {
          EXPECT_LT(out_sq / double(out_n), in_sq / double(in_n)) << label;
        }
      }
    }
  }
}

// A glossy material (Beckmann alpha 0.2) under the tests' sky (a sun patch
// of radiance 40): the forward pass at 4 spp (seed 7) filtered is closer to
// the same pass at 256 spp (seed 1, unfiltered) than the unfiltered 4 spp
// frame, by MSE over the covered pixels, for the lobe-aware weights and the
// normal-aware one. Measured (both hosts alike): unfiltered 0.169; none
// 0.065, normal 0.041, lobe 0.102, mixture 0.101, asg 0.101; upsampled
// from 1/2 0.157 (half its pixels shaded again), from 1/4 0.168. At 4 spp
// the error is mostly the sun's variance, which the wider normal-aware and
// depth-only kernels average away better; at 64 spp the normal-aware
// weight's blur of the glossy reflection dominates and the lobe-aware
// weight keeps it (measured: unfiltered 0.0015, normal 0.0083, lobe
// 0.0014, against 256 spp), which is the paper's point. On the native host
// (lavapipe's numbers are within 0.1% of these).
TEST_F(LobeFilterOnBothHosts, FilteringANoisyGlossyFrameLowersItsError) {
  RenderSettings s = settings(std::make_shared<const Environment>(test::sky()), glossy(), 256);
  s.filter.beta = 20.0f;  // the paper's values, pinned: the figures above were measured with them
  s.filter.sigma_n2 = 0.01f;
  for (int k : {0}) {
    const char* host = host_name(renderer(0, k).host());
    s.shading.spp = 256;
    s.shading.seed = 1;
    const Frame truth = renderer(0, k).render(s);
    ASSERT_GT(covered_pixels(truth), 500u);
    s.shading.seed = 7;
    for (uint32_t spp : {4u, 64u}) {
      s.shading.spp = spp;
      const double unfiltered = covered_mse(renderer(0, k).render(s), truth);
      std::map<FilterWeight, double> mse;
      std::printf("%s, %u spp: MSE unfiltered %.5f", host, spp, unfiltered);
      for (FilterWeight w : kWeights) {
        s.filter.weight = w;
        mse[w] = covered_mse(renderer(1, k).render(s), truth);
        std::printf(", %s %.5f", filter_weight_name(w), mse[w]);
      }
      if (spp == 4) {
        for (uint32_t scale : {2u, 4u}) {
          s.filter.weight = FilterWeight::Lobe;
          std::printf(", lobe from 1/%u %.5f", scale, covered_mse(renderer(scale, k).render(s), truth));
        }
      }
      std::printf("\n");
      if (spp == 4) {
        for (FilterWeight w : {FilterWeight::Normal, FilterWeight::Lobe, FilterWeight::Mixture, FilterWeight::Asg})
          EXPECT_LT(mse[w], 0.8 * unfiltered) << host << " " << filter_weight_name(w);
      } else {
        EXPECT_LT(mse[FilterWeight::Lobe], 0.5 * mse[FilterWeight::Normal])
            << host << ": the lobe-aware weight blurs the glossy reflection as much as the normal-aware one";
      }
    }
  }
}

// --recompute 1: every covered pixel's total weights are below 1 (four
// texels about a pixel of a curved surface are never all identical to it),
// so upsampling shades every covered pixel again at full size, with the
// same samples as the full-size forward pass (the pixel's own sequence):
// the frame is the full-size forward frame within float rounding (measured
// 6e-8 natively, 0 on lavapipe; with environment shadows 1e-6 on lavapipe)
// on both hosts, with and without environment shadows (visibility cones
// from the upsampling kernel).
TEST_F(LobeFilterOnBothHosts, RecomputingEveryPixelGivesTheFullSizeForwardFrame) {
  RenderSettings s = settings(std::make_shared<const Environment>(test::sky()), glossy(), 16);
  s.filter.recompute = 1.0f;
  for (bool shadows : {false, true}) {
    s.shading.env_shadows = shadows;
    for (int k = 0; k < 2; ++k) {
      const Frame full = renderer(0, k).render(s);
      for (uint32_t scale : {2u, 4u}) {
        Renderer& r = renderer(scale, k);
        const std::string label = std::string(host_name(r.host())) + " 1/" + std::to_string(scale) +
                                  (shadows ? " with environment shadows" : "");
        const Frame f = r.render(s);
        const auto w = filter_weights(r);
        size_t covered = 0, again = 0, uncovered_again = 0;
        for (size_t i = 0; i < w.size(); ++i) {
          if (f.colour[i].a > 0) {
            ++covered;
            again += w[i].z == 1.0f;
          } else {
            uncovered_again += w[i].z != 0.0f;
          }
        }
        const Apart d = apart(f.colour, full.colour);
        std::printf("%-40s: %zu of %zu covered pixels shaded again; frame within %.2e of the full-size one\n",
                    label.c_str(), again, covered, d.max);
        EXPECT_GT(covered, 500u) << label;
        EXPECT_EQ(again, covered) << label;
        EXPECT_EQ(uncovered_again, 0u) << label << ": an uncovered pixel was shaded again";
        EXPECT_LT(d.max, 1e-5) << label;
      }
    }
  }
}

// Below 1, a pixel is shaded again exactly when one of its total weights
// (diffuse, specular) is under the threshold (filter_weight.z is 1
// then and only then; such a pixel is the full-size frame's, as
// RecomputingEveryPixelGivesTheFullSizeForwardFrame checks). At 0 none. At the default
// 0.25: 406 of 774 at 1/2, 653 of 774 at 1/4 (the sharp specular lobes'
// totals fall under it on a sphere this curved at this resolution).
TEST_F(LobeFilterOnBothHosts, PixelsUnderTheThresholdAndOnlyThoseAreShadedAgain) {
  RenderSettings s = settings(std::make_shared<const Environment>(test::sky()), glossy(), 16);
  for (int k = 0; k < 2; ++k) {
    for (uint32_t scale : {2u, 4u}) {
      for (float t : {0.25f, 0.0f}) {
        s.filter.recompute = t;
        Renderer& r = renderer(scale, k);
        const std::string label =
            std::string(host_name(r.host())) + " 1/" + std::to_string(scale) + " threshold " + std::to_string(t);
        const Frame f = r.render(s);
        const auto w = filter_weights(r);
        size_t covered = 0, again = 0, wrong = 0, diffuse_under = 0, specular_under = 0;
        for (size_t i = 0; i < w.size(); ++i) {
          if (!(f.colour[i].a > 0)) {
            wrong += w[i].z != 0.0f;
            continue;
          }
          ++covered;
          const bool under_d = t > 0 && !(w[i].x >= t), under_s = t > 0 && !(w[i].y >= t);
          diffuse_under += under_d;
          specular_under += under_s;
          wrong += (w[i].z == 1.0f) != (under_d || under_s);
          wrong += w[i].z != 0.0f && w[i].z != 1.0f;
          again += w[i].z == 1.0f;
        }
        std::printf("%-30s: %zu of %zu covered pixels shaded again (diffuse total under %zu, specular %zu)\n",
                    label.c_str(), again, covered, diffuse_under, specular_under);
        EXPECT_GT(covered, 500u) << label;
        EXPECT_EQ(wrong, 0u) << label << ": filter_weight.z does not follow the threshold";
        if (t == 0.0f) {
          EXPECT_EQ(again, 0u) << label;
        }
      }
    }
  }
}

// A regression test: render/src/shading_cache.cpp, ShadingCache::update,
// which the forward pass and the lobe-aware filter share, once decided
// that its shading tables were still valid by comparing the raw addresses
// of the options' environment and material with those it built them from,
// without holding them. Options made afresh after the old ones were freed
// got the same blocks from malloc (glibc reuses a freed block of the same
// size), and the frame was shaded with the old tables: RMSE 0.88 against a
// fresh renderer here, on both hosts and both chains. The cache now holds
// what it compares, so the new objects cannot take the old addresses.
TEST_F(LobeFilterOnBothHosts, NewShadingOptionsAfterTheOldOnesAreFreedAreShadedWithTheirOwnTables) {
  RenderSettings s = settings(nullptr, white(), 16);
  s.filter.recompute = 1.0f;
  s.shading.environment = std::make_shared<const Environment>(constant_environment(glm::vec3(1.0f)));
  s.shading.material = std::make_shared<const Material>(white());
  for (int k = 0; k < 2; ++k) {
    renderer(0, k).render(s);
    renderer(2, k).render(s);
  }
  // The first options are dropped; the second ones are made afresh, as
  // many times as it takes (up to 64) for one to land where the old one was:
  // the case that broke the cache. Holding the old ones, it never happens.
  const void* old_environment = s.shading.environment.get();
  const void* old_material = s.shading.material.get();
  s.shading.environment.reset();
  s.shading.material.reset();
  const Environment sky = test::sky();
  std::vector<std::shared_ptr<const Environment>> environments;
  std::vector<std::shared_ptr<const Material>> materials;
  for (int i = 0; i < 64; ++i) {
    environments.push_back(std::make_shared<const Environment>(sky));
    if (environments.back().get() == old_environment) break;
  }
  for (int i = 0; i < 64; ++i) {
    materials.push_back(std::make_shared<const Material>(glossy()));
    if (materials.back().get() == old_material) break;
  }
  s.shading.environment = environments.back();
  s.shading.material = materials.back();
  std::printf("the new environment %s the old one's address, the new material %s\n",
              s.shading.environment.get() == old_environment ? "took" : "did not take",
              s.shading.material.get() == old_material ? "took it" : "did not");
  NativeRenderer fresh(*tree_);
  fresh.add_pass(std::make_unique<ForwardPass>());
  const Frame truth = fresh.render(s);
  ASSERT_GT(covered_pixels(truth), 500u);
  for (int k = 0; k < 2; ++k) {
    for (uint32_t scale : {0u, 2u}) {
      Renderer& r = renderer(scale, k);
      const std::string label = std::string(host_name(r.host())) + (scale == 0 ? " forward" : " upsampled from 1/2");
      const Apart d = apart(r.render(s).colour, truth.colour);
      std::printf("%-24s: against a fresh native renderer's frame: RMSE %.2e, p99 %.2e, largest %.2e\n", label.c_str(),
                  d.rmse, d.p99, d.max);
      EXPECT_LT(d.p99, 3e-3) << label << ": shaded with the tables of the options that were there before";
    }
  }
}

// The filter reads the forward pass's split images at its own scale: the
// chain refuses it without them, with unsplit forward shading before it,
// and after a split forward pass at another scale, naming the image.
TEST(LobeFilterChain, RefusesAFilterWithoutTheSplitImagesAtItsScale) {
  test::SphereScene sphere(0.5f);
  const octree::Octree tree = test::voxelize(sphere, 16);
  vk::ContextOptions options;
  options.device = "llvmpipe";
  options.validation = true;
  vk::Context context(options);
  struct Case {
    const char* what;
    std::optional<ForwardOutput> forward;
    uint32_t scale;
  };
  const Case cases[] = {{"no forward pass", std::nullopt, 1},
                        {"unsplit forward pass", ForwardOutput{}, 1},
                        {"split at 1/2, filter at 1/4", ForwardOutput{true, 2}, 4},
                        {"split at 1/1, filter at 1/2", ForwardOutput{true, 1}, 2},
                        {"split at 1/4, filter at 1/1", ForwardOutput{true, 4}, 1}};
  for (const Case& c : cases) {
    NativeRenderer native(tree);
    GpuRenderer vulkan(context, tree);
    for (Renderer* r : {static_cast<Renderer*>(&native), static_cast<Renderer*>(&vulkan)}) {
      const std::string label = std::string(host_name(r->host())) + ", " + c.what;
      if (c.forward) r->add_pass(std::make_unique<ForwardPass>(*c.forward));
      try {
        r->add_pass(std::make_unique<LobeFilterPass>(c.scale));
        ADD_FAILURE() << label << ": the chain accepted the filter";
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("diffuse"), std::string::npos) << label << ": " << what;
        EXPECT_NE(what.find(c.scale == 1 ? "lobe-filter" : "lobe-upsample"), std::string::npos)
            << label << ": " << what;
      }
      // The refused pass is not in the chain: the frame still renders (on
      // the native host: the Vulkan tracer would compile for seconds).
      if (r->host() != Host::Native) continue;
      RenderSettings s;
      s.width = 16;
      s.height = 12;
      s.camera = test::looking_at_origin({0.0f, 0.0f, 2.0f}, 40.0f);
      const Frame f = r->render(s);
      EXPECT_EQ(f.passes.size(), c.forward ? 2u : 1u) << label;
    }
  }
  EXPECT_TRUE(context.validation_messages().empty()) << context.validation_messages().front();
  // Scales other than 1, 2, 4, and a reduced scale without split.
  EXPECT_THROW(LobeFilterPass(3), std::invalid_argument);
  EXPECT_THROW(LobeFilterPass(0), std::invalid_argument);
  EXPECT_THROW(ForwardPass(ForwardOutput{true, 3}), std::invalid_argument);
  EXPECT_THROW(ForwardPass(ForwardOutput{false, 2}), std::invalid_argument);
}

TEST(LobeFilterWeights, ParseAcceptsTheFiveNamesAndRefusesOthers) {
  for (FilterWeight w : kWeights) EXPECT_EQ(parse_filter_weight(filter_weight_name(w)), w);
  EXPECT_EQ(parse_filter_weight("none"), FilterWeight::None);
  EXPECT_EQ(parse_filter_weight("normal"), FilterWeight::Normal);
  EXPECT_EQ(parse_filter_weight("lobe"), FilterWeight::Lobe);
  EXPECT_EQ(parse_filter_weight("mixture"), FilterWeight::Mixture);
  EXPECT_EQ(parse_filter_weight("asg"), FilterWeight::Asg);
  for (const char* bad : {"bogus", "", "Lobe", "lobe ", "eq12", "2"}) {
    try {
      parse_filter_weight(bad);
      ADD_FAILURE() << "'" << bad << "' was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(std::string("'") + bad + "'"), std::string::npos) << what;
      for (FilterWeight w : kWeights) EXPECT_NE(what.find(filter_weight_name(w)), std::string::npos) << what;
    }
  }
}

// A scene with five materials of its own (material-spheres: GGX floors of
// two roughnesses, gold, Phong plastic, clay): where a pixel shows two
// materials, the mixture weight (Eq. 11) compares two-lobe mixtures. Both
// hosts agree for the lobe-aware weights there too, with the tolerances of
// BothHostsAgreeForEveryWeightAndScale and their reasons, but for the p99
// of the frames as they run: here the hosts' forward passes differ on more
// pixels (split images: RMSE 1.4e-3, p99 7e-4, largest 2.9e-2; the
// G-buffers agree), and the filter spreads that (measured after filtering:
// RMSE 6.5e-4 to 6.9e-4, p99 2.3e-3 to 2.7e-3, largest 1.2e-2 to 1.4e-2):
// bounds 3e-3 on the RMSE and 6e-3 on the p99. From the same input
// (InjectSplit): measured 3.9e-7 to 5.1e-6 relative on the fully covered
// pixels, 1.3e-4 on all covered ones.
TEST(LobeFilterMaterials, BothHostsAgreeWhereTwoMaterialsMix) {
  const auto scene = voxelizer::make_scene("material-spheres");
  const octree::Octree tree = test::voxelize(*scene, 64);
  ASSERT_EQ(tree.materials.size(), 5u);
  vk::ContextOptions options;
  options.device = "llvmpipe";
  options.validation = true;
  vk::Context context(options);
  NativeRenderer native(tree);
  GpuRenderer vulkan(context, tree);
  native.add_pass(std::make_unique<ForwardPass>(ForwardOutput{true, 1}));
  native.add_pass(std::make_unique<LobeFilterPass>(1));
  vulkan.add_pass(std::make_unique<ForwardPass>(ForwardOutput{true, 1}));
  auto inject_pass = std::make_unique<InjectSplit>(1);
  InjectSplit& inject = *inject_pass;
  vulkan.add_pass(std::move(inject_pass));
  vulkan.add_pass(std::make_unique<LobeFilterPass>(1));
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
  for (FilterWeight w : {FilterWeight::Lobe, FilterWeight::Mixture, FilterWeight::Asg}) {
    s.filter.weight = w;
    const Frame a = native.render(s), b = vulkan.render(s);
    ASSERT_EQ(a.gbuffer.size(), b.gbuffer.size());
    size_t mixed = 0, gbuffer_apart = 0;
    for (size_t i = 0; i < a.gbuffer.size(); ++i) {
      const GBufferTexel &t = a.gbuffer[i], &u = b.gbuffer[i];
      mixed += t.coverage > 0 && t.material != t.material2 && t.material_mix > 0.05f && t.material_mix < 0.95f;
      gbuffer_apart += t.material != u.material || t.material2 != u.material2 ||
                       std::abs(t.material_mix - u.material_mix) > 1e-3f || std::abs(t.coverage - u.coverage) > 1e-3f;
    }
    const Apart colour = apart(a.colour, b.colour);
    const Apart weight = apart(filter_weights(native), filter_weights(vulkan));
    inject.diffuse = image_copy(native, diffuse_image());
    inject.specular = image_copy(native, specular_image());
    const Frame c = vulkan.render(s);
    inject.diffuse.clear();
    inject.specular.clear();
    const SameInput same = same_input(a, c);
    std::printf(
        "materials %-7s: %zu pixels mix two materials, %zu G-buffer texels apart; colours apart by RMSE %.2e, p99 "
        "%.2e, largest %.2e; from the same input by %.2e relative on %zu fully covered pixels, %.2e on %zu covered; "
        "total "
        "weights by largest %.2e\n",
        filter_weight_name(w), mixed, gbuffer_apart, colour.rmse, colour.p99, colour.max, same.full_relative, same.full,
        same.any, same.covered, weight.max);
    EXPECT_GT(mixed, 20u);
    EXPECT_LT(colour.rmse, 3e-3) << filter_weight_name(w);
    EXPECT_LT(colour.p99, 6e-3) << filter_weight_name(w);
    EXPECT_LT(weight.max, 1e-4) << filter_weight_name(w);
    EXPECT_GT(same.full, 400u);
    EXPECT_LT(same.full_relative, 5e-5) << filter_weight_name(w);
    EXPECT_LT(same.any, 3e-4) << filter_weight_name(w);
  }
  EXPECT_TRUE(context.validation_messages().empty()) << context.validation_messages().front();
}

}  // namespace
}  // namespace svo::render
