// Built-in procedural scenes with analytic distance functions (DESIGN
// section 11): exact ground truth for the rest of the engine, and surfaces
// whose statistics are known in closed form for the tests.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <string>
#include <vector>

#include "svo/voxelizer/source.h"

namespace svo::voxelizer {

// A surface given by a signed distance function. Subclasses define the
// function; projection onto the surface, normals and the lattice queries
// come from here.
class AnalyticScene : public SurfaceSource {
 public:
  // Signed distance (negative inside), or a function whose gradient has norm
  // close to 1 near the surface and at most lipschitz() everywhere.
  virtual float distance(glm::vec3 p) const = 0;
  // (gradient of distance(), distance()) at p; central differences unless a
  // scene knows it in closed form.
  virtual glm::vec4 distance_gradient(glm::vec3 p) const;
  virtual float lipschitz() const { return 1.0f; }
  // (distance(p), a radius around p that holds no surface point) for sphere
  // tracing: |distance| / max(1, lipschitz()) unless a scene knows better.
  virtual glm::dvec2 distance_bound(glm::vec3 p) const;
  // Attribute (linear RGB) at a surface point.
  virtual glm::vec3 colour(glm::vec3 surface_point) const = 0;
  // Material at a surface point: an index into materials() (0 for a scene
  // with one material or none).
  virtual uint32_t material(glm::vec3 /*surface_point*/) const { return 0; }
  // Scene name as given to --scene.
  virtual std::string name() const = 0;
  // d(colour) / d(height) where the scene's colour follows its height, at
  // the mean height: detail octaves continue this relation (linear RGB per
  // scene unit). Zero for a scene whose colour does not follow height.
  virtual glm::vec3 colour_height_slope() const { return glm::vec3(0); }

  float sigma_rho2() const override { return sigma_rho2_; }
  // Default: 1.5 times the area of the bounding box (bumps add area).
  double surface_area() const override;
  void set_sigma_rho2(float v) { sigma_rho2_ = v; }

  // Unit normal: normalised central-difference gradient of distance().
  glm::vec3 normal(glm::vec3 p) const;
  // Closest surface point by Newton steps along the gradient.
  glm::vec3 project(glm::vec3 p) const;

  void prepare(const Lattice& lattice) override { lattice_ = lattice; }
  std::vector<glm::ivec3> candidate_bricks(uint32_t brick_size) const override;
  using SurfaceSource::evaluate;
  void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const override;

 protected:
  Lattice lattice_;
  float sigma_rho2_ = 0.01f;
};

// A scene with procedural detail octaves (octree::Detail, the math in
// shaders/common/detail.glsl): the surface moved by D(p) along the base's
// normal, distance(p) = f(p) - |grad f(p)| D(p) for the base's f (whose
// gradient need not be unit: the bumpy sphere's is up to 1.4 long on its
// bumps' slopes, and f - D alone would move the surface by D / |grad f|
// there), and colour + colour_slope D, D the octaves' displacement. With `all_octaves`
// (the reference) D holds every octave. Otherwise (the voxelizer) D holds
// only what the lattice given to prepare() can draw, the fraction
// e_k(voxel / sqrt(2)) of each octave, as the renderer does at the finest
// level; detail() then tells the voxelizer to fold the rest into the
// statistics.
class DetailedScene : public AnalyticScene {
 public:
  DetailedScene(std::unique_ptr<AnalyticScene> base, const octree::Detail& detail, bool all_octaves);
  float distance(glm::vec3 p) const override;
  glm::vec4 distance_gradient(glm::vec3 p) const override;
  float lipschitz() const override { return lipschitz_; }
  // Outside the shell the octaves can reach, the base's own bound less the
  // reach, without evaluating the octaves.
  glm::dvec2 distance_bound(glm::vec3 p) const override;
  glm::vec3 colour(glm::vec3 surface_point) const override;
  uint32_t material(glm::vec3 surface_point) const override { return base_->material(surface_point); }
  std::vector<std::string> materials() const override { return base_->materials(); }
  glm::vec3 colour_height_slope() const override { return base_->colour_height_slope(); }
  std::string name() const override { return base_->name(); }
  Box bounds() const override;
  double surface_area() const override { return 2.0 * base_->surface_area(); }
  octree::Detail detail() const override { return all_ ? octree::Detail{} : detail_; }
  void prepare(const Lattice& lattice) override;
  const AnalyticScene& base() const { return *base_; }
  // (gradient, value) of the displacement drawn.
  glm::vec4 displacement(glm::vec3 p) const;

 private:
  std::unique_ptr<AnalyticScene> base_;
  octree::Detail detail_;
  bool all_;
  float drawn_radius_ = 0;  // footprint radius whose octaves are drawn (0: all)
  float lipschitz_ = 1;
  float reach_ = 0;    // largest |displacement|: how far the surface moves
  float reach_f_ = 0;  // the same in units of the base's f (times its largest |grad f|)
};

// Detail octaves with the defaults of the command line: octave 0 of
// wavelength `wavelength` and amplitude `amplitude`, gain 1/2, the colour
// following height as the scene's does.
octree::Detail make_detail(const AnalyticScene& scene, uint32_t octaves, float amplitude, float wavelength,
                           uint32_t seed);

// (height variance, per-axis slope variance) of the detail a lattice of
// spacing `voxel` cannot draw: what the voxelizer folds into the statistics.
glm::vec2 detail_folded_variance(const octree::Detail& detail, double voxel);

// Names accepted by make_scene.
std::vector<std::string> scene_names();

// "bumpy-sphere" (paper Fig. 11), "heightfield" (Fig. 9), "grooved-cylinder"
// (Fig. 5); colour correlated with height as a(h) = abar + a_s s(h).
// "material-spheres": three spheres of different materials (gold GGX,
// Phong plastic, Lambert clay) on a floor tiled by a glossiness map (GGX
// tiles of roughness 0.05 and 0.45), five materials (materials()).
// Throws std::invalid_argument naming the valid names for anything else.
std::unique_ptr<AnalyticScene> make_scene(const std::string& name);

// A Gaussian random height field z = sum_k A_k cos(k . (x, y) + phi_k) over
// [-1, 1]^2, closed below into a slab; its height and slope variances are
// known in closed form. Colour a(h) = abar + a_s erf(h / (sqrt(2) sigma_h)).
class HeightfieldScene : public AnalyticScene {
 public:
  // `waves` cosines with wavelengths between min_wavelength and
  // max_wavelength, amplitudes giving height deviation sigma_h.
  HeightfieldScene(int waves, float min_wavelength, float max_wavelength, float sigma_h, unsigned seed, glm::vec3 abar,
                   glm::vec3 a_s);
  float height(float x, float y) const;
  glm::vec2 gradient(float x, float y) const;
  float height_variance() const { return height_variance_; }
  glm::vec2 slope_variance() const { return slope_variance_; }
  float sigma_h() const;
  glm::vec3 abar() const { return abar_; }
  glm::vec3 a_s() const { return a_s_; }

  float distance(glm::vec3 p) const override;
  glm::vec4 distance_gradient(glm::vec3 p) const override;
  float lipschitz() const override { return lipschitz_; }
  glm::vec3 colour(glm::vec3 surface_point) const override;
  glm::vec3 colour_height_slope() const override;
  Box bounds() const override;
  std::string name() const override { return "heightfield"; }

 private:
  struct Cosine {
    float amplitude, kx, ky, phase;
  };
  static constexpr float kBottom = -0.6f;  // the slab's floor, out of the way of the top's statistics
  std::vector<Cosine> waves_;
  float height_variance_ = 0;
  glm::vec2 slope_variance_{0, 0};
  float lipschitz_ = 1;
  glm::vec3 abar_, a_s_;
};

}  // namespace svo::voxelizer
