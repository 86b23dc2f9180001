// Small analytic scenes for the tracer tests, voxelized in-process.
#pragma once

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cstdlib>
#include <string>

#include "svo/octree/octree.h"
#include "svo/render/image_io.h"
#include "svo/render/renderer.h"
#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"

namespace svo::test {

// A sphere of radius r at the origin, one colour.
class SphereScene : public voxelizer::AnalyticScene {
 public:
  explicit SphereScene(float r) : r_(r) { set_sigma_rho2(0.01f); }
  float distance(glm::vec3 p) const override { return glm::length(p) - r_; }
  glm::vec3 colour(glm::vec3) const override { return {0.5f, 0.5f, 0.5f}; }
  std::string name() const override { return "test-sphere"; }
  voxelizer::Box bounds() const override { return {glm::vec3(-r_), glm::vec3(r_)}; }

 private:
  float r_;
};

// The box [lo, hi], one colour.
class BoxScene : public voxelizer::AnalyticScene {
 public:
  BoxScene(glm::vec3 lo, glm::vec3 hi) : lo_(lo), hi_(hi) {}
  float distance(glm::vec3 p) const override {
    glm::vec3 c = 0.5f * (lo_ + hi_), e = 0.5f * (hi_ - lo_);
    glm::vec3 q = glm::abs(p - c) - e;
    return glm::length(glm::max(q, glm::vec3(0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
  }
  glm::vec3 colour(glm::vec3) const override { return {0.6f, 0.6f, 0.6f}; }
  std::string name() const override { return "test-box"; }
  voxelizer::Box bounds() const override { return {lo_, hi_}; }

 private:
  glm::vec3 lo_, hi_;
};

// The half-space x <= 0, cut by the octree's domain around `bounds`: its
// face x = 0 has no front edge.
class HalfSpaceScene : public voxelizer::AnalyticScene {
 public:
  explicit HalfSpaceScene(voxelizer::Box bounds) : bounds_(bounds) {}
  float distance(glm::vec3 p) const override { return p.x; }
  glm::vec3 colour(glm::vec3) const override { return {0.6f, 0.6f, 0.6f}; }
  std::string name() const override { return "test-half-space"; }
  voxelizer::Box bounds() const override { return bounds_; }

 private:
  voxelizer::Box bounds_;
};

inline octree::Octree voxelize(voxelizer::SurfaceSource& source, uint32_t resolution) {
  voxelizer::VoxelizeOptions options;
  options.resolution = resolution;
  return voxelizer::voxelize(source, options);
}

// A camera at `eye` looking at the origin with +y up.
inline render::Camera looking_at_origin(glm::vec3 eye, float fov_deg) {
  render::Camera c;
  c.eye = eye;
  c.target = glm::vec3(0);
  c.up = glm::vec3(0, 1, 0);
  c.fov_deg = fov_deg;
  return c;
}

// With SVO_TEST_IMAGES=DIR set, tests save what they render there to be looked at.
inline void save_for_inspection(const render::Frame& frame, const std::string& name) {
  if (const char* dir = std::getenv("SVO_TEST_IMAGES")) render::write_colour(std::string(dir) + "/" + name + ".png", frame);
}

}  // namespace svo::test
