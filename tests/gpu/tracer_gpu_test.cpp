// The Vulkan tracer against the CPU one (the same tracer.glsl), with the
// validation layer on and required silent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "../render/test_scenes.h"
#include "../voxelizer/grid_mesh.h"
#include "svo/render/renderer.h"
#include "svo/render/vk_context.h"

namespace svo::render {
namespace {

struct Difference {
  double mean = 0;     // mean absolute difference over RGBA
  double above = 0;    // fraction of pixels with a channel differing by more than `bound`
  double max = 0;
};

Difference compare(const Frame& a, const Frame& b, float bound) {
  Difference d;
  size_t over = 0;
  for (size_t i = 0; i < a.colour.size(); ++i) {
    glm::vec4 e = glm::abs(a.colour[i] - b.colour[i]);
    float m = std::max(std::max(e.x, e.y), std::max(e.z, e.w));
    d.mean += double(e.x + e.y + e.z + e.w) / 4;
    d.max = std::max(d.max, double(m));
    over += m > bound ? 1 : 0;
  }
  d.mean /= double(a.colour.size());
  d.above = double(over) / double(a.colour.size());
  return d;
}

// The hosts agree (`hosts`: Vulkan against the CPU) and a feature changed
// the CPU's image (`feature`: with it against without) on more than
// `share` of the pixels by 0.02, by 0.05 at most somewhere (or the
// feature's code was not reached).
void expect_agree_and_changed(const char* what, const Difference& hosts, const Difference& feature, double share) {
  std::printf("%s changed %.2f%% of the pixels by 0.02, max %.3f; mean |gpu - cpu| %.2e, max %.3f\n", what,
              100 * feature.above, feature.max, hosts.mean, hosts.max);
  EXPECT_GT(feature.above, share) << what;
  EXPECT_GT(feature.max, 0.05) << what;
  EXPECT_LT(hosts.mean, 2e-3) << what;
  EXPECT_LT(hosts.above, 0.01) << what;
}

class TracerGpu : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    auto scene = voxelizer::make_scene("bumpy-sphere");
    tree_ = new octree::Octree(test::voxelize(*scene, 128));
  }
  static void TearDownTestSuite() { delete tree_; }
  static vk::ContextOptions validated() {
    vk::ContextOptions options;
    options.validation = true;
    return options;
  }
  // The bumpy sphere from above and aside, `size` pixels square.
  static RenderSettings view(uint32_t size) {
    RenderSettings s;
    s.width = s.height = size;
    s.camera = test::looking_at_origin({1.2f, 0.9f, 1.8f}, 40.0f);
    return s;
  }
  static void expect_silent(const vk::Context& context) {
    auto messages = context.validation_messages();
    EXPECT_TRUE(messages.empty()) << messages.front();
  }
  static octree::Octree* tree_;
};
octree::Octree* TracerGpu::tree_ = nullptr;

// Agreement within an explicit tolerance: the two sides differ only in
// float rounding (Vulkan allows a few ulp in division, sqrt, exp), which can
// move a mask lookup to the neighbouring table cell (1/128 of coverage) or
// a level blend by a hair.
TEST_F(TracerGpu, AgreesWithTheCpuTracerInEveryMode) {
  vk::Context context(validated());
  GpuRenderer gpu(context, *tree_);
  RenderSettings s = view(48);
  s.gbuffer = true;
  for (Mode mode : {Mode::Prefiltered, Mode::Nearest, Mode::Alpha, Mode::Mip}) {
    s.mode = mode;
    s.shadows = mode == Mode::Prefiltered;
    Frame g = gpu.render(s), c = render_cpu(*tree_, s);
    ASSERT_EQ(g.colour.size(), c.colour.size());
    Difference d = compare(g, c, 0.02f);
    std::printf("%s: mean |gpu - cpu| %.2e, max %.3f, pixels above 0.02: %.2f%%, gpu %.1f ms\n", mode_name(mode),
                d.mean, d.max, 100 * d.above, g.gpu_ms);
    EXPECT_LT(d.mean, 2e-3) << mode_name(mode);
    EXPECT_LT(d.above, 0.01) << mode_name(mode);
    EXPECT_GT(g.covered_pixels, s.width * s.height / 4) << mode_name(mode);
    EXPECT_NEAR(double(g.covered_pixels), double(c.covered_pixels), 0.01 * s.width * s.height) << mode_name(mode);
    // The G-buffer: same surface depth where both are fully covered.
    int compared = 0, depth_off = 0;
    for (size_t i = 0; i < g.gbuffer.size(); ++i) {
      if (g.gbuffer[i].coverage < 1 || c.gbuffer[i].coverage < 1) continue;
      ++compared;
      depth_off += std::abs(g.gbuffer[i].depth - c.gbuffer[i].depth) > 0.01f ? 1 : 0;
    }
    EXPECT_GT(compared, 100);
    EXPECT_LT(depth_off, compared / 100 + 1) << mode_name(mode);
  }
  expect_silent(context);
}

// Creases split into two halves (svo_shade) on both hosts alike: a box
// seen from afar, about 1.5 pixels a finest voxel, its edges drawn with
// one lobe and with the halves. The halves must change the image (or the
// split was not reached; measured: 1.4% of the pixels by more than 0.02,
// at most by 0.124) and agree across the hosts.
TEST_F(TracerGpu, CreasesSplitAsOnTheCpu) {
  voxelizer::MeshArrays box;
  test::add_box(box, glm::dvec3(-0.5), glm::dvec3(0.5), 2);
  const octree::Octree tree = test::voxelize_mesh(voxelizer::make_triangle_mesh("box", std::move(box)), 64);
  vk::Context context(validated());
  GpuRenderer gpu(context, tree);
  RenderSettings s;
  s.width = s.height = 96;
  s.camera = test::looking_at_origin({1.75f, 1.35f, 2.15f}, 20.0f);
  RenderSettings one_lobe = s;
  one_lobe.crease_split = false;
  const Frame g = gpu.render(s), c = render_cpu(tree, s), u = render_cpu(tree, one_lobe);
  expect_agree_and_changed("box edges: the split", compare(g, c, 0.02f), compare(c, u, 0.02f), 0.005);
  expect_silent(context);
}

// An open sheet's rims: shading reads the shading_normal channel (the
// face's normal on the caps, the masks keep the gradient) on both hosts
// alike. Without the channel the rims must look different (or it was not
// read), and the hosts must agree with it.
TEST_F(TracerGpu, ShadingNormalsOfOpenEdgesAsOnTheCpu) {
  voxelizer::MeshArrays sheet;
  test::add_grid(sheet, {-0.6, -0.1, -0.5}, {1.2, 0.2, 0}, {0, 0, 1}, 4);
  const octree::Octree tree = test::voxelize_mesh(voxelizer::make_triangle_mesh("sheet", std::move(sheet)), 64);
  const int c = tree.channel_index(octree::Channel::ShadingNormal);
  ASSERT_GE(c, 0);
  octree::Octree without = tree;
  without.channels.erase(without.channels.begin() + c);
  without.brick_data.erase(without.brick_data.begin() + c);
  vk::Context context(validated());
  GpuRenderer gpu(context, tree);
  RenderSettings s;
  s.width = s.height = 96;
  s.camera = test::looking_at_origin({0.9f, 1.3f, 1.6f}, 40.0f);
  const Frame g = gpu.render(s), cpu = render_cpu(tree, s), gradient = render_cpu(without, s);
  expect_agree_and_changed("open sheet: the shading normals", compare(g, cpu, 0.02f), compare(cpu, gradient, 0.02f),
                           0.002);
  expect_silent(context);
}

// Many rays per pixel: lavapipe ends all loops of an invocation after 65,535
// iterations in total, which broke 64-ray pixels into wrong 8 x 8 blocks
// before the renderer split them over several dispatches.
TEST_F(TracerGpu, RayMarchingWithManyRaysAgreesWithTheCpuTracer) {
  vk::Context context(validated());
  GpuRenderer gpu(context, *tree_);
  RenderSettings s = view(32);
  s.mode = Mode::RayMarch;
  s.spp = 144;
  s.gbuffer = true;
  Frame g = gpu.render(s), c = render_cpu(*tree_, s);
  Difference d = compare(g, c, 0.02f);
  std::printf("raymarch 144 rays: mean |gpu - cpu| %.2e, max %.3f\n", d.mean, d.max);
  EXPECT_LT(d.mean, 2e-4);
  EXPECT_EQ(d.above, 0.0);
  for (size_t i = 0; i < g.gbuffer.size(); ++i) {
    EXPECT_NEAR(g.gbuffer[i].coverage, c.gbuffer[i].coverage, 0.02f) << "pixel " << i;
    if (g.gbuffer[i].coverage > 0.5f) {
      EXPECT_NEAR(g.gbuffer[i].depth, c.gbuffer[i].depth, 0.01f) << "pixel " << i;
    }
  }
  expect_silent(context);
}

// A lens in 8 x 8 parts, a cone each: 64 cones of a pixel in one dispatch
// ran into the same limit (the elephant's strong blur drew 34.7 dB away from
// the native host), so the renderer splits them as it splits rays.
TEST_F(TracerGpu, ALensInManyPartsAgreesWithTheCpuTracer) {
  vk::Context context(validated());
  GpuRenderer gpu(context, *tree_);
  RenderSettings s = view(16);
  const float distance = glm::length(s.camera.eye - s.camera.target);
  s.camera.aperture = 0.02f * distance;
  s.camera.focus = 1.2f * distance;
  s.lens_parts = 8;
  s.gbuffer = true;
  ASSERT_EQ(lens_parts(*tree_, s), 8u);
  Frame g = gpu.render(s), c = render_cpu(*tree_, s);
  Difference d = compare(g, c, 0.02f);
  std::printf("a lens in 8 x 8 parts: mean |gpu - cpu| %.2e, max %.3f, %.0f steps per pixel\n", d.mean, d.max,
              c.steps_per_pixel);
  EXPECT_LT(d.mean, 2e-4);
  EXPECT_EQ(d.above, 0.0);
  for (size_t i = 0; i < g.gbuffer.size(); ++i) {
    EXPECT_NEAR(g.gbuffer[i].coverage, c.gbuffer[i].coverage, 0.02f) << "pixel " << i;
  }
  expect_silent(context);
}

// Detail octaves drawn below the finest level (detail.glsl): the noise, the
// shell test and the unfolded statistics agree between the two hosts. A
// close view of the bumpy sphere at 64^3 with 6 octaves, whose footprint is
// a tenth of the finest voxel.
TEST_F(TracerGpu, DetailOctavesAgreeWithTheCpuTracer) {
  auto base = voxelizer::make_scene("bumpy-sphere");
  octree::Detail detail = voxelizer::make_detail(*base, 6, 0.004f, 0.04f, 3);
  voxelizer::DetailedScene scene(std::move(base), detail, false);
  octree::Octree tree = test::voxelize(scene, 64);
  ASSERT_EQ(tree.detail.octaves, 6u);
  vk::Context context(validated());
  GpuRenderer gpu(context, tree);
  RenderSettings s;
  s.width = s.height = 40;
  s.camera = test::looking_at_origin({0.25f, 0.2f, 0.85f}, 20.0f);
  s.camera.target = glm::vec3(0.2f, 0.15f, 0.65f);
  s.gbuffer = true;
  for (Mode mode : {Mode::Prefiltered, Mode::Mip}) {
    s.mode = mode;
    Frame g = gpu.render(s), c = render_cpu(tree, s);
    Difference d = compare(g, c, 0.02f);
    std::printf("detail, %s: mean |gpu - cpu| %.2e, max %.3f, pixels above 0.02: %.2f%%\n", mode_name(mode), d.mean,
                d.max, 100 * d.above);
    EXPECT_LT(d.mean, 2e-3) << mode_name(mode);
    EXPECT_LT(d.above, 0.01) << mode_name(mode);
    EXPECT_EQ(c.covered_pixels, s.width * s.height) << mode_name(mode);
  }
  // The view does draw detail: without it the picture differs.
  octree::Octree plain = tree;
  plain.detail = {};
  s.mode = Mode::Prefiltered;
  Difference drawn = compare(render_cpu(tree, s), render_cpu(plain, s), 0.02f);
  EXPECT_GT(drawn.above, 0.2);
  expect_silent(context);
}

// Bricks split across several buffers render the same image, whether the
// tracer reads them through device addresses or through separate storage
// buffers; more buffers than the tracer binds are refused, naming the limit.
TEST_F(TracerGpu, PoolsSplitAcrossBuffersRenderTheSameImage) {
  vk::Context context(validated());
  GpuRenderer whole(context, *tree_);
  EXPECT_STREQ(whole.pool_access(), "single");
  RenderSettings s = view(32);
  Frame a = whole.render(s);
  // The device pools: (B + 1)^3 samples per brick (the file stores B^3),
  // plus the nodes and the mask table, which are small beside them.
  const uint64_t brick_bytes = whole.pool_bytes();
  for (bool address : {true, false}) {
    if (address && !context.info().buffer_device_address) continue;
    GpuRenderer split(context, *tree_, {brick_bytes / 5, address});
    EXPECT_STREQ(split.pool_access(), address ? "address" : "switch");
    EXPECT_GE(split.pool_buffers(), 5u);
    Frame b = split.render(s);
    EXPECT_EQ(compare(a, b, 0.0f).max, 0.0) << split.pool_access();
    EXPECT_THROW(GpuRenderer(context, *tree_, {brick_bytes / 9, address}), vk::Error);
  }
  expect_silent(context);
}

// The Vulkan host traces only the pixels whose cones may meet the domain
// and writes the background elsewhere: a small, off-centre domain after a
// frame that covered the whole image, then a frame looking away, each the
// CPU tracer's picture, G-buffer included (no pixel kept from the frame
// before), in a frame of each mode.
TEST_F(TracerGpu, PixelsAwayFromTheDomainAreThisFramesBackground) {
  vk::Context context(validated());
  GpuRenderer gpu(context, *tree_);
  RenderSettings close = view(40);
  close.camera = test::looking_at_origin({0.2f, 0.1f, 0.9f}, 60.0f);
  close.gbuffer = true;
  close.background = glm::vec3(0.2f, 0.3f, 0.4f);
  RenderSettings aside = close;
  aside.camera = test::looking_at_origin({2.5f, 1.5f, 4.0f}, 30.0f);
  aside.camera.target = glm::vec3(0.6f, -0.5f, 0.0f);
  RenderSettings away = close;
  away.camera.target = 2.0f * close.camera.eye;
  for (Mode mode : {Mode::Prefiltered, Mode::RayMarch}) {
    for (RenderSettings* s : {&close, &aside, &away}) {
      s->mode = mode;
      s->spp = mode == Mode::RayMarch ? 4 : 1;
    }
    Frame first = gpu.render(close);
    EXPECT_EQ(first.covered_pixels, close.width * close.height) << mode_name(mode);
    for (const RenderSettings* s : {&aside, &away}) {
      Frame g = gpu.render(*s), c = render_cpu(*tree_, *s);
      Difference d = compare(g, c, 0.02f);
      EXPECT_LT(d.mean, 2e-3) << mode_name(mode);
      EXPECT_LT(d.above, 0.01) << mode_name(mode);
      size_t background = 0;
      for (size_t i = 0; i < g.colour.size(); ++i) {
        if (c.colour[i].a > 0) continue;
        ++background;
        EXPECT_EQ(g.colour[i], glm::vec4(s->background, 0.0f)) << mode_name(mode) << " pixel " << i;
        EXPECT_EQ(g.gbuffer[i].coverage, 0.0f) << mode_name(mode) << " pixel " << i;
        EXPECT_EQ(g.steps[i], c.steps[i]) << mode_name(mode) << " pixel " << i;
      }
      EXPECT_GT(background, g.colour.size() / 2) << mode_name(mode);
    }
    EXPECT_EQ(gpu.render(away).covered_pixels, 0u) << mode_name(mode);
  }
  expect_silent(context);
}

}  // namespace
}  // namespace svo::render
