#include "shading_cache.h"

#include <cstring>

#include "svo/render/octree_access.h"
#include "svo/render/renderer.h"

namespace svo::render {

ShadingTables& ShadingCache::update(const PassContext& ctx) {
  const OctreeAccess& octree = ctx.octree;
  ShadingOptions options = ctx.settings.shading;
  // Without --material: the octree's own materials, parsed once per octree.
  if (scene_ != &octree.tree()) {
    scene_materials_ = parse_scene_materials(octree.tree().materials, "the octree");
    scene_ = &octree.tree();
    valid_ = false;
  }
  if (options.scene_materials.empty()) options.scene_materials = scene_materials_;
  // Nothing at all: the built-in one, the Beckmann lobe of --specular
  // with the file's (or --roughness's) micro-BRDF slope variance.
  const Material fallback = builtin_material(ctx.settings.specular, octree.params(ctx.settings).material.x);
  const bool same = valid_ && environment_ == options.environment && preconvolved_ == options.preconvolved &&
                    area_light_ == options.area_light && material_ == options.material &&
                    (options.material || !scene_materials_.empty() ||
                     (default_material_.f0 == fallback.f0 && default_material_.roughness == fallback.roughness));
  // Scene materials given in the options (not the octree's) are compared by identity too.
  if (!same || ctx.settings.shading.scene_materials != given_scene_) {
    tables_ = build_shading_tables(options, fallback, ctx.settings.shadows);
    environment_ = options.environment;
    preconvolved_ = options.preconvolved;
    area_light_ = options.area_light;
    material_ = options.material;
    default_material_ = fallback;
    given_scene_ = ctx.settings.shading.scene_materials;
    valid_ = true;
    ++generation_;
    floats_.reset();
  }
  ShadingTables& t = tables_;
  t.params.env_xform.x = glm::radians(options.env_rotate_deg);
  t.params.env_xform.y = options.env_scale;
  t.params.sampling = glm::uvec4(std::max(options.spp, 1u), options.seed, shade_flags(options, ctx.settings.shadows),
                                 t.params.sampling.w);
  return t;
}

std::vector<const Material*> ShadingCache::materials() const {
  if (material_) return {material_.get()};
  const auto& scene = given_scene_.empty() ? scene_materials_ : given_scene_;
  if (scene.empty()) return {&default_material_};
  std::vector<const Material*> all;
  for (const auto& m : scene) all.push_back(m.get());
  return all;
}

const vk::Buffer* ShadingCache::params_buffer(vk::Context& context) {
  if (!params_) params_ = std::make_unique<vk::Buffer>(context, sizeof(svo::math::SvoShadeParams));
  std::memcpy(params_->data(), &tables_.params, sizeof(tables_.params));
  return params_.get();
}

const vk::Buffer* ShadingCache::tables_buffer(vk::Context& context) {
  if (!floats_) {
    floats_ = std::make_unique<vk::Buffer>(context, tables_.floats.size() * sizeof(float));
    std::memcpy(floats_->data(), tables_.floats.data(), tables_.floats.size() * sizeof(float));
  }
  return floats_.get();
}

}  // namespace svo::render
