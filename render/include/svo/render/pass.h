// The renderer as a chain of passes over named frame images (DESIGN section
// 8: later shading modules plug in as passes). The cone tracer is the first
// pass; it writes "colour" (vec4: linear RGB, coverage), "gbuffer" (3 vec4
// per texel: depth and position; normal and slope variance; abar and
// coverage) and "steps" (uint). A pass names what it reads and writes; the
// renderer refuses a chain in which a pass reads an image no earlier pass
// writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "svo/render/vk_compute.h"

namespace svo::render {

struct RenderSettings;

// The images of one frame: device buffers of width x height texels, by name.
class FrameImages {
 public:
  explicit FrameImages(vk::Context& context) : context_(context) {}

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // Starts a frame of this size; images keep their buffers when the size does not change.
  void resize(uint32_t width, uint32_t height);

  // The buffer of image `name` with `texel_bytes` per texel, created on first use.
  vk::Buffer& image(const std::string& name, std::size_t texel_bytes);
  // The buffer of an image that must already exist (throws std::invalid_argument naming it).
  vk::Buffer& existing(const std::string& name);
  bool has(const std::string& name) const { return images_.count(name) > 0; }

 private:
  vk::Context& context_;
  uint32_t width_ = 0, height_ = 0;
  std::map<std::string, vk::Buffer> images_;
};

class Pass {
 public:
  virtual ~Pass() = default;
  virtual std::string name() const = 0;
  virtual std::vector<std::string> reads() const = 0;
  virtual std::vector<std::string> writes() const = 0;
  // Runs the pass on the frame's images; returns its GPU time in ms, or a
  // negative value when the device has no timestamps.
  virtual double run(FrameImages& images, const RenderSettings& settings) = 0;
};

// Linear RGB to display: reads "colour", writes "display" (one uint per
// texel: 8-bit sRGB R, G, B and coverage in A, little-endian RGBA).
class DisplayPass : public Pass {
 public:
  explicit DisplayPass(vk::Context& context);
  std::string name() const override { return "display"; }
  std::vector<std::string> reads() const override { return {"colour"}; }
  std::vector<std::string> writes() const override { return {"display"}; }
  double run(FrameImages& images, const RenderSettings& settings) override;

 private:
  vk::ComputeKernel kernel_;
};

}  // namespace svo::render
