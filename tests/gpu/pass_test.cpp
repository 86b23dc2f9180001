// The frame as a chain of passes (render/pass.h): the display pass against
// the CPU encoding, a pass added after the tracer that reads the G-buffer,
// and a chain that reads an image nobody writes refused.
#include <gtest/gtest.h>

#include "../render/test_scenes.h"
#include "svo/render/pass.h"
#include "svo/render/renderer.h"

namespace svo::render {
namespace {

// A host-side pass (the buffers are host-visible): colour = (coverage from
// the G-buffer, 0, 0), coverage kept.
class CoverageToRed : public Pass {
 public:
  std::string name() const override { return "coverage-to-red"; }
  std::vector<std::string> reads() const override { return {"gbuffer"}; }
  std::vector<std::string> writes() const override { return {"colour"}; }
  double run(FrameImages& images, const RenderSettings&) override {
    auto g = images.existing("gbuffer").as<glm::vec4>();
    auto c = images.image("colour", sizeof(glm::vec4)).as<glm::vec4>();
    for (size_t i = 0; i < size_t(images.width()) * images.height(); ++i) c[i] = glm::vec4(g[3 * i + 2].w, 0, 0, g[3 * i + 2].w);
    return 0;
  }
};

class ReadsNothingWritten : public CoverageToRed {
 public:
  std::vector<std::string> reads() const override { return {"environment"}; }
};

uint32_t srgb_byte(float linear) { return uint32_t(linear_to_srgb(std::clamp(linear, 0.0f, 1.0f)) * 255.0f + 0.5f); }

TEST(Passes, DisplayPassEncodesTheColourImageAndAddedPassesRunInOrder) {
  test::SphereScene sphere(0.5f);
  octree::Octree tree = test::voxelize(sphere, 64);
  vk::ContextOptions options;
  options.validation = true;
  vk::Context context(options);
  GpuRenderer gpu(context, tree);
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.camera = test::looking_at_origin({0.5f, 0.5f, 2.5f}, 35.0f);
  s.display = true;
  s.gbuffer = true;
  Frame f = gpu.render(s);
  ASSERT_EQ(f.display.size(), f.colour.size());
  int off = 0;
  for (size_t i = 0; i < f.colour.size(); ++i) {
    const glm::vec4 c = f.colour[i];
    const uint32_t expect[4] = {srgb_byte(c.r), srgb_byte(c.g), srgb_byte(c.b),
                                uint32_t(std::clamp(c.a, 0.0f, 1.0f) * 255.0f + 0.5f)};
    for (int k = 0; k < 4; ++k) {
      int got = int((f.display[i] >> (8 * k)) & 255u);
      off += std::abs(got - int(expect[k])) > 1 ? 1 : 0;
    }
  }
  EXPECT_EQ(off, 0) << "display bytes more than 1 away from the CPU encoding";

  EXPECT_THROW(gpu.add_pass(std::make_unique<ReadsNothingWritten>()), std::invalid_argument);
  gpu.add_pass(std::make_unique<CoverageToRed>());
  Frame red = gpu.render(s);
  for (size_t i = 0; i < red.colour.size(); ++i) {
    ASSERT_EQ(red.colour[i], glm::vec4(f.colour[i].a, 0, 0, f.colour[i].a)) << "pixel " << i;
    // The display pass runs last, on the added pass's output.
    EXPECT_EQ((red.display[i] >> 8) & 0xFFFFu, 0u) << "pixel " << i;
  }
  auto messages = context.validation_messages();
  EXPECT_TRUE(messages.empty()) << messages.front();
}

}  // namespace
}  // namespace svo::render
