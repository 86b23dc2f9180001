// The shading tables of a pass that shades with RenderSettings::shading
// (the forward pass, the lobe-aware filter): built from the frame's options
// and the octree's own materials, rebuilt only when they change, and on a
// Vulkan host uploaded into device buffers.
#pragma once

#include <memory>
#include <vector>

#include "svo/octree/octree.h"
#include "svo/render/pass.h"
#include "svo/render/shading.h"

namespace svo::render {

class ShadingCache {
 public:
  // The tables of this frame's shading options; the parameters that change
  // without new tables (environment rotation and scale, samples, seed,
  // shadow flags) are set on every call.
  ShadingTables& update(const PassContext& ctx);
  // On a Vulkan host, after update(): the parameter block (SvoShadeParams)
  // and the tables as device buffers, uploaded.
  const vk::Buffer* params_buffer(vk::Context& context);
  const vk::Buffer* tables_buffer(vk::Context& context);
  // After update(): the materials in the order the tables index them
  // (svo_scene_material): the options' one, the scene's, or the built-in one.
  std::vector<const Material*> materials() const;
  // Counts the tables built so far: a pass caching what it derives from
  // them rebuilds when this changes.
  uint64_t generation() const { return generation_; }

 private:
  // What the tables were built from, held so that a new object cannot
  // take a freed one's address and pass for it.
  std::shared_ptr<const Environment> environment_;
  std::shared_ptr<const PreconvolvedEnvironment> preconvolved_;
  std::shared_ptr<const AreaLight> area_light_;
  std::shared_ptr<const Material> material_;
  Material default_material_;
  const octree::Octree* scene_ = nullptr;  // whose materials scene_materials_ holds
  std::vector<std::shared_ptr<const Material>> scene_materials_;
  std::vector<std::shared_ptr<const Material>> given_scene_;  // the options' own, when the tables were built
  bool valid_ = false;
  uint64_t generation_ = 0;
  ShadingTables tables_;
  std::unique_ptr<vk::Buffer> params_, floats_;
};

}  // namespace svo::render
