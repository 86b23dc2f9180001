// Passes a command adds after the tracer by name (`svo render --pass NAME`),
// each a per-texel kernel of shaders/common run by both hosts.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "svo/render/pass.h"
#include "svo/render/shading.h"

namespace svo::render {

// The visible fraction of each light seen from every G-buffer point, by a
// visibility cone through the octree (shaders/common/visibility_pass.glsl):
// reads "gbuffer", writes "visibility" (Rgba32f: lights 1 to 4; 1 where a
// light is absent or the pixel has no surface).
class VisibilityPass : public Pass {
 public:
  VisibilityPass();
  ~VisibilityPass() override;
  std::string name() const override { return "visibility"; }
  std::vector<ImageDesc> reads() const override { return {gbuffer_image()}; }
  std::vector<ImageDesc> writes() const override { return {visibility_image()}; }
  double run(PassContext& context) override;
  static ImageDesc visibility_image() { return {"visibility", TexelFormat::Rgba32f}; }

 private:
  std::unique_ptr<vk::ComputeKernel> kernel_;  // made at the first run on a Vulkan host
};

// Forward shading (DESIGN 10.2, shaders/common/forward.glsl): every covered
// pixel shaded with RenderSettings::shading's environment, material and
// samples per pixel (multiple importance sampling of the BRDF and the
// environment) plus the lights, over the background or the environment seen
// through the pixel: reads "gbuffer" and "background", writes "colour" (the
// frame's colour from then on).
class ForwardPass : public Pass {
 public:
  ForwardPass();
  ~ForwardPass() override;
  std::string name() const override { return "forward"; }
  std::vector<ImageDesc> reads() const override { return {gbuffer_image(), background_image()}; }
  std::vector<ImageDesc> writes() const override { return {colour_image()}; }
  double run(PassContext& context) override;

 private:
  struct Cache;
  std::unique_ptr<Cache> cache_;  // the shading tables of the last options, and the Vulkan kernel and buffers
};

// The names make_pass knows, in the order --help lists them.
std::vector<std::string> pass_names();

// A new pass by name. Throws std::invalid_argument naming the passes there are.
std::unique_ptr<Pass> make_pass(const std::string& name);

}  // namespace svo::render
