// The chain of passes both hosts share (pass.h, renderer.h): typed frame
// images, the chain's checks, per-pass times, the display pass on either
// host, and the choice of host.
#include "svo/render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/shared_math.h"
#include "display.comp.spv.h"
#include "trace_setup.h"

namespace svo::render {

static_assert(kGBufferVec4s == svo::math::SVO_GBUFFER_VEC4S);

GBufferTexel unpack_gbuffer(const glm::vec4* t) {
  const auto g = gbuffer_at(t);
  return {g.depth,     g.position, g.normal, g.coverage, g.tangent,   g.sigma_rho2,
          g.slope_cov, g.abar,     g.a_s,    g.material, g.material2, g.material_mix};
}

const char* host_name(Host host) { return host == Host::Native ? "native" : "vulkan"; }

const char* texel_format_name(TexelFormat format) {
  switch (format) {
    case TexelFormat::Rgba32f:
      return "rgba32f";
    case TexelFormat::R32u:
      return "r32u";
    case TexelFormat::Rgba8:
      return "rgba8";
    case TexelFormat::GBuffer:
      return "gbuffer";
  }
  return "unknown";
}

std::size_t texel_bytes(TexelFormat format) {
  switch (format) {
    case TexelFormat::Rgba32f:
      return 16;
    case TexelFormat::R32u:
    case TexelFormat::Rgba8:
      return 4;
    case TexelFormat::GBuffer:
      return 16 * svo::math::SVO_GBUFFER_VEC4S;
  }
  return 0;
}

uint32_t ImageDesc::width(uint32_t frame_width, uint32_t level) const {
  return std::max(1u, ((frame_width + scale - 1) / scale + (1u << level) - 1) >> level);
}

uint32_t ImageDesc::height(uint32_t frame_height, uint32_t level) const {
  return std::max(1u, ((frame_height + scale - 1) / scale + (1u << level) - 1) >> level);
}

std::size_t ImageDesc::texels(uint32_t frame_width, uint32_t frame_height) const {
  std::size_t n = 0;
  for (uint32_t l = 0; l < levels; ++l) n += std::size_t(width(frame_width, l)) * height(frame_height, l);
  return n;
}

std::string ImageDesc::describe() const {
  return name + " (" + texel_format_name(format) + ", 1/" + std::to_string(scale) + ", " + std::to_string(levels) +
         (levels == 1 ? " level)" : " levels)");
}

ImageDesc colour_image() { return {"colour", TexelFormat::Rgba32f}; }
ImageDesc background_image() { return {"background", TexelFormat::Rgba32f}; }
ImageDesc gbuffer_image() { return {"gbuffer", TexelFormat::GBuffer}; }
ImageDesc steps_image() { return {"steps", TexelFormat::R32u}; }
std::vector<ImageDesc> trace_images() { return {colour_image(), background_image(), gbuffer_image(), steps_image()}; }

void FrameImages::begin_frame(uint32_t width, uint32_t height) {
  if (width != width_ || height != height_) images_.clear();
  width_ = width;
  height_ = height;
  written_.clear();
}

ImageMemory& FrameImages::write(const ImageDesc& desc) {
  if (desc.scale < 1 || desc.levels < 1 || desc.levels > 16) {
    throw std::invalid_argument("image " + desc.describe() +
                                ": scale and levels must be at least 1, levels at most 16");
  }
  const std::size_t bytes = std::max<std::size_t>(4, desc.texels(width_, height_) * texel_bytes(desc.format));
  auto it = images_.find(desc.name);
  if (it == images_.end() || !it->second.desc.same_type(desc) || it->second.memory->bytes() != bytes) {
    if (it != images_.end()) images_.erase(it);
    it = images_.emplace(desc.name, Entry{desc, allocate_(bytes)}).first;
  }
  written_.insert(desc.name);
  return *it->second.memory;
}

ImageMemory& FrameImages::read(const ImageDesc& desc) {
  auto it = images_.find(desc.name);
  if (it == images_.end() || written_.count(desc.name) == 0) {
    throw std::invalid_argument("frame image '" + desc.name + "' was not written this frame");
  }
  if (!it->second.desc.same_type(desc)) {
    throw std::invalid_argument("frame image " + it->second.desc.describe() + " is read as " + desc.describe());
  }
  return *it->second.memory;
}

const ImageDesc& FrameImages::desc(const std::string& name) const {
  auto it = images_.find(name);
  if (it == images_.end() || written_.count(name) == 0) {
    std::string names;
    for (const auto& n : written_) names += (names.empty() ? "" : ", ") + n;
    throw std::invalid_argument("frame image '" + name + "' was not written this frame (images: " + names + ")");
  }
  return it->second.desc;
}

std::vector<std::string> FrameImages::written() const { return {written_.begin(), written_.end()}; }

DisplayPass::DisplayPass() = default;
DisplayPass::~DisplayPass() = default;

ImageDesc DisplayPass::display_image() { return {"display", TexelFormat::Rgba8}; }

double DisplayPass::run(PassContext& ctx) {
  ImageMemory& in = ctx.images.read(colour_image());
  ImageMemory& out = ctx.images.write(display_image());
  const uint32_t count = ctx.images.width() * ctx.images.height();
  if (ctx.host == Host::Vulkan) {
    if (!kernel_) kernel_ = std::make_unique<vk::ComputeKernel>(*ctx.vulkan, svo_spv_display_comp, 2, sizeof(uint32_t));
    const vk::Buffer* bound[] = {in.buffer(), out.buffer()};
    return kernel_->dispatch(bound, &count, (count + 63) / 64);
  }
  auto start = std::chrono::steady_clock::now();
  const auto* colour = static_cast<const glm::vec4*>(in.data());
  auto* display = static_cast<uint32_t*>(out.data());
  tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 4096), [&](const tbb::blocked_range<uint32_t>& r) {
    for (uint32_t i = r.begin(); i != r.end(); ++i) display[i] = svo::math::svo_display_texel(colour[i]);
  });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

namespace {

// Host memory for the native host's images.
class HostMemory : public ImageMemory {
 public:
  // Not zeroed: a pass writes every texel it declares.
  explicit HostMemory(std::size_t bytes) : data_(new uint8_t[bytes]), bytes_(bytes) {}
  void* data() override { return data_.get(); }
  std::size_t bytes() const override { return bytes_; }

 private:
  std::unique_ptr<uint8_t[]> data_;
  std::size_t bytes_;
};

// A host-visible device buffer for the Vulkan host's images, in host-cached
// memory where the device has it: the frame and the passes' statistics are
// read back by the CPU every frame.
class DeviceMemory : public ImageMemory {
 public:
  DeviceMemory(vk::Context& context, std::size_t bytes) : buffer_(context, bytes, false, vk::Residence::Readback) {}
  void* data() override { return buffer_.data(); }
  std::size_t bytes() const override { return buffer_.size(); }
  vk::Buffer* buffer() override { return &buffer_; }

 private:
  vk::Buffer buffer_;
};

FrameImages::Allocator allocator(vk::Context* context) {
  if (!context) return [](std::size_t bytes) { return std::make_unique<HostMemory>(bytes); };
  return [context](std::size_t bytes) { return std::make_unique<DeviceMemory>(*context, bytes); };
}

}  // namespace

Renderer::Renderer(Host host, vk::Context* context, std::unique_ptr<vk::Context> owned)
    : owned_context_(std::move(owned)),
      context_(owned_context_ ? owned_context_.get() : context),
      host_(host),
      device_name_(context_ ? context_->info().name : "native (" + std::to_string(native_threads()) + " threads)"),
      device_type_(context_ ? context_->info().type : "native"),
      images_(allocator(context_)) {}

Renderer::~Renderer() = default;

void Renderer::set_trace(std::unique_ptr<Pass> trace) { add_pass(std::move(trace)); }

void Renderer::add_pass(std::unique_ptr<Pass> pass) {
  for (const auto& r : pass->reads()) {
    auto it = written_.find(r.name);
    if (it == written_.end()) {
      throw std::invalid_argument("pass '" + pass->name() + "' reads image '" + r.name +
                                  "' that no earlier pass writes");
    }
    if (!it->second.same_type(r)) {
      throw std::invalid_argument("pass '" + pass->name() + "' reads image " + r.describe() + " but it is written as " +
                                  it->second.describe());
    }
  }
  for (const auto& w : pass->writes()) {
    auto it = written_.find(w.name);
    if (it != written_.end() && !it->second.same_type(w)) {
      throw std::invalid_argument("pass '" + pass->name() + "' writes image " + w.describe() +
                                  " but an earlier pass writes it as " + it->second.describe());
    }
  }
  for (const auto& w : pass->writes()) written_[w.name] = w;
  for (const auto& r : pass->reads()) gbuffer_read_ = gbuffer_read_ || r.name == gbuffer_image().name;
  passes_.push_back(std::move(pass));
}

FrameImages& Renderer::images() { return images_; }

std::vector<std::string> Renderer::image_names() const {
  std::vector<std::string> names;
  for (const auto& [name, desc] : written_) names.push_back(name);
  names.push_back(DisplayPass::display_image().name);
  return names;
}

std::vector<std::string> Renderer::validation_messages() const {
  return context_ ? context_->validation_messages() : std::vector<std::string>{};
}

namespace {

// The frame of `fine` (msaa x msaa samples per pixel) at the pixels' size:
// colour the mean of each pixel's samples, steps their sum, times as they
// are.
Frame box_filtered(const Frame& fine, uint32_t msaa, uint32_t width, uint32_t height) {
  Frame f;
  f.width = width;
  f.height = height;
  f.colour.assign(size_t(width) * height, glm::vec4(0));
  f.steps.assign(size_t(width) * height, 0);
  const float weight = 1.0f / float(msaa * msaa);
  for (uint32_t y = 0; y < fine.height; ++y) {
    for (uint32_t x = 0; x < fine.width; ++x) {
      const size_t from = size_t(y) * fine.width + x, to = size_t(y / msaa) * width + x / msaa;
      f.colour[to] += weight * fine.colour[from];
      f.steps[to] += fine.steps[from];
    }
  }
  f.passes = fine.passes;
  f.ms = fine.ms;
  f.gpu_ms = fine.gpu_ms;
  f.wall_ms = fine.wall_ms;
  finish_frame_stats(f);
  return f;
}

}  // namespace

Frame Renderer::render(const RenderSettings& requested) {
  if (requested.msaa != 1) {
    if (requested.msaa != 2 && requested.msaa != 4)
      throw std::invalid_argument("msaa " + std::to_string(requested.msaa) + ": 1, 2 or 4 samples per pixel side");
    if (requested.gbuffer || requested.display)
      throw std::invalid_argument(
          "msaa: the G-buffer and the display image would be at the samples' size; ask for "
          "them without multisampling");
    if (requested.width > UINT32_MAX / requested.msaa || requested.height > UINT32_MAX / requested.msaa)
      throw std::invalid_argument("msaa: the frame's samples overflow");
    RenderSettings fine = requested;
    fine.msaa = 1;
    fine.width *= requested.msaa;
    fine.height *= requested.msaa;
    return box_filtered(render(fine), requested.msaa, requested.width, requested.height);
  }
  auto start = std::chrono::steady_clock::now();
  RenderSettings settings = requested;
  settings.gbuffer = settings.gbuffer || gbuffer_read_;
  images_.begin_frame(settings.width, settings.height);
  PassContext ctx{host_, images_, settings, context_, *octree_};
  Frame frame;
  frame.width = settings.width;
  frame.height = settings.height;
  frame.ms = 0;
  auto run = [&](Pass& pass) {
    const double ms = pass.run(ctx);
    frame.passes.push_back({pass.name(), ms});
    frame.ms = ms < 0 || frame.ms < 0 ? -1 : frame.ms + ms;
  };
  for (auto& pass : passes_) run(*pass);
  if (settings.display) run(display_);
  frame.gpu_ms = host_ == Host::Vulkan ? frame.ms : -1;
  const std::size_t pixels = std::size_t(settings.width) * settings.height;
  auto colours = images_.texels<const glm::vec4>(images_.read(colour_image()));
  frame.colour.assign(colours.begin(), colours.begin() + std::ptrdiff_t(pixels));
  auto counts = images_.texels<const uint32_t>(images_.read(steps_image()));
  frame.steps.assign(counts.begin(), counts.begin() + std::ptrdiff_t(pixels));
  if (requested.gbuffer) {
    auto v = images_.texels<const glm::vec4>(images_.read(gbuffer_image()));
    frame.gbuffer.resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) frame.gbuffer[i] = unpack_gbuffer(&v[kGBufferVec4s * i]);
  }
  if (settings.display) {
    auto d = images_.texels<const uint32_t>(images_.read(DisplayPass::display_image()));
    frame.display.assign(d.begin(), d.begin() + std::ptrdiff_t(pixels));
  }
  finish_frame_stats(frame);
  frame.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

std::string resolve_device(const std::string& device) {
  if (device == "native") return "native";
  std::vector<vk::DeviceInfo> devices;
  try {
    devices = vk::list_devices();
  } catch (const vk::Error&) {
    if (device.empty()) return "native";  // no Vulkan driver: the native host
    throw;
  }
  if (device.empty()) {
    for (const char* type : {"discrete", "integrated"}) {
      for (const auto& d : devices) {
        if (d.type == type) return std::to_string(d.index);
      }
    }
    return "native";
  }
  try {
    return std::to_string(devices[vk::select_device(devices, device)].index);
  } catch (const vk::Error& e) {
    throw vk::Error(std::string(e.what()) + "; or native (the CPU without Vulkan)");
  }
}

std::unique_ptr<Renderer> make_renderer(const octree::Octree& tree, const DeviceOptions& options) {
  // Validation is Vulkan's: it asks for a Vulkan device (by default the best
  // there is, lavapipe included).
  if (options.validation && options.device == "native") {
    throw std::invalid_argument("validation (--validate) needs a Vulkan device, not native");
  }
  std::string device;
  if (options.validation && options.device.empty()) {
    const std::vector<vk::DeviceInfo> devices = vk::list_devices();
    device = std::to_string(devices[vk::select_device(devices, "")].index);
  } else {
    device = resolve_device(options.device);
  }
  if (device == "native") return std::make_unique<NativeRenderer>(tree);
  return std::make_unique<GpuRenderer>(std::make_unique<vk::Context>(vk::ContextOptions{device, options.validation}),
                                       tree, options.gpu);
}

Frame render_cpu(const octree::Octree& tree, const RenderSettings& settings) {
  return NativeRenderer(tree).render(settings);
}

}  // namespace svo::render
