// The frame as a chain of passes over typed images (DESIGN section 10.1).
// The cone tracer is the first pass; it writes "colour" (Rgba32f: linear
// RGB, the background's share included; A = coverage), "background"
// (Rgba32f: that share, and 1 - coverage), "gbuffer" (GBuffer:
// shaders/common/gbuffer.glsl) and "steps" (R32u: cone elements per pixel).
// A pass declares the images it reads and writes; the renderer refuses a
// chain in which a pass reads an image no earlier pass writes, or reads it
// as another type, and a pass can only read an image written during this
// frame. Each pass runs on the host of the renderer it belongs to: natively
// (per-texel kernels of shaders/common compiled as C++, parallel with TBB)
// or on a Vulkan device (the same kernels as compute shaders).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "svo/render/vk_compute.h"

namespace svo::render {

struct RenderSettings;
class OctreeAccess;

enum class Host { Native, Vulkan };
const char* host_name(Host host);  // "native", "vulkan"

// Values are stable: tests and files name them.
enum class TexelFormat : uint32_t {
  Rgba32f = 0,  // vec4
  R32u = 1,     // uint
  Rgba8 = 2,    // 8-bit RGBA in one uint, R lowest
  GBuffer = 3,  // SVO_GBUFFER_VEC4S vec4s (shaders/common/gbuffer.glsl)
};
const char* texel_format_name(TexelFormat format);  // "rgba32f", ...
std::size_t texel_bytes(TexelFormat format);

// An image of a frame: its name, texel format, a scale divisor (a pass may
// work at 1/2, 1/4 of the frame's size: ceil(size / scale) texels a side)
// and mip levels (each level half the previous one, rounded up, stored after
// it). The chain compares all four.
struct ImageDesc {
  std::string name;
  TexelFormat format = TexelFormat::Rgba32f;
  uint32_t scale = 1;   // >= 1
  uint32_t levels = 1;  // >= 1

  uint32_t width(uint32_t frame_width, uint32_t level = 0) const;
  uint32_t height(uint32_t frame_height, uint32_t level = 0) const;
  // Texels of every level together.
  std::size_t texels(uint32_t frame_width, uint32_t frame_height) const;
  // "gbuffer (gbuffer, 1/1, 1 level)"
  std::string describe() const;
  bool same_type(const ImageDesc& other) const {
    return format == other.format && scale == other.scale && levels == other.levels;
  }
};

// The images the cone tracer writes.
ImageDesc colour_image();
ImageDesc background_image();
ImageDesc gbuffer_image();
ImageDesc steps_image();
// All four, as either host's trace pass declares them.
std::vector<ImageDesc> trace_images();

// Host memory of one image: a plain allocation on the native host, a
// host-visible device buffer on the Vulkan host (buffer() is then set).
class ImageMemory {
 public:
  virtual ~ImageMemory() = default;
  virtual void* data() = 0;
  virtual std::size_t bytes() const = 0;
  virtual vk::Buffer* buffer() { return nullptr; }
};

// The images of one frame by name. Images keep their memory from frame to
// frame while their size and type do not change; a reader sees only what was
// written during the current frame.
class FrameImages {
 public:
  using Allocator = std::function<std::unique_ptr<ImageMemory>(std::size_t bytes)>;
  explicit FrameImages(Allocator allocate) : allocate_(std::move(allocate)) {}

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // Starts a frame of this size: nothing is written yet.
  void begin_frame(uint32_t width, uint32_t height);

  // The memory a pass writes `desc` to, created (or retyped) as needed;
  // from now on the image counts as written this frame.
  ImageMemory& write(const ImageDesc& desc);
  // The memory of an image written this frame with exactly this type.
  // @throw std::invalid_argument naming the image and what is wrong.
  ImageMemory& read(const ImageDesc& desc);
  // The same by name alone, whatever its type (for files and tests).
  const ImageDesc& desc(const std::string& name) const;
  ImageMemory& read(const std::string& name) { return read(desc(name)); }
  // Names of the images written this frame.
  std::vector<std::string> written() const;

  template <class T>
  std::span<T> texels(ImageMemory& memory) {
    return {static_cast<T*>(memory.data()), memory.bytes() / sizeof(T)};
  }

 private:
  struct Entry {
    ImageDesc desc;
    std::unique_ptr<ImageMemory> memory;
  };
  Allocator allocate_;
  uint32_t width_ = 0, height_ = 0;
  std::map<std::string, Entry> images_;
  std::set<std::string> written_;
};

// What a pass runs with.
struct PassContext {
  Host host;
  FrameImages& images;
  const RenderSettings& settings;  // as the frame runs them (the G-buffer on when a pass reads it)
  vk::Context* vulkan = nullptr;   // the device on the Vulkan host, null on the native host
  const OctreeAccess& octree;      // the octree, for passes that trace cones through it
};

class Pass {
 public:
  virtual ~Pass() = default;
  virtual std::string name() const = 0;
  virtual std::vector<ImageDesc> reads() const = 0;
  virtual std::vector<ImageDesc> writes() const = 0;
  // Runs the pass on the frame's images; returns its time in ms (device
  // timestamps on Vulkan, wall clock natively), negative when unknown.
  virtual double run(PassContext& context) = 0;
};

// Linear RGB to display (shaders/common/display.glsl): reads "colour",
// writes "display" (Rgba8: sRGB R, G, B and coverage in A).
class DisplayPass : public Pass {
 public:
  DisplayPass();
  ~DisplayPass() override;
  std::string name() const override { return "display"; }
  std::vector<ImageDesc> reads() const override { return {colour_image()}; }
  std::vector<ImageDesc> writes() const override { return {display_image()}; }
  double run(PassContext& context) override;
  static ImageDesc display_image();

 private:
  std::unique_ptr<vk::ComputeKernel> kernel_;  // made at the first run on a Vulkan host
};

}  // namespace svo::render
