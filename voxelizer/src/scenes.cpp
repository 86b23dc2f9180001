#include "svo/voxelizer/scenes.h"

#include "svo/voxelizer/sine_bumps.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <random>
#include <stdexcept>

#include "common/shared_math.h"

namespace svo::voxelizer {

glm::dvec3 Lattice::position(glm::ivec3 index) const { return origin + glm::dvec3(index) * voxel; }

namespace {

float height_sigmoid(float h, float sigma_h) { return svo::math::svo_height_sigmoid(h, sigma_h); }

// d/dh erf(h / (sqrt(2) sigma)) at h = 0, times sigma.
constexpr float kSigmoidSlope = 0.797884561f;  // sqrt(2 / pi)

}  // namespace

double AnalyticScene::surface_area() const {
  glm::dvec3 e = glm::dvec3(bounds().hi) - glm::dvec3(bounds().lo);
  return 1.5 * 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x);
}

glm::dvec2 AnalyticScene::distance_bound(glm::vec3 p) const {
  double f = distance(p);
  return {f, std::abs(f) / std::max(1.0, double(lipschitz()))};
}

glm::vec4 AnalyticScene::distance_gradient(glm::vec3 p) const {
  const float e = 1e-4f;
  glm::vec3 g(distance(p + glm::vec3(e, 0, 0)) - distance(p - glm::vec3(e, 0, 0)),
              distance(p + glm::vec3(0, e, 0)) - distance(p - glm::vec3(0, e, 0)),
              distance(p + glm::vec3(0, 0, e)) - distance(p - glm::vec3(0, 0, e)));
  return glm::vec4(g / (2 * e), distance(p));
}

glm::vec3 AnalyticScene::normal(glm::vec3 p) const {
  glm::vec3 g(distance_gradient(p));
  float len = glm::length(g);
  return len > 0 ? g / len : glm::vec3(0, 0, 1);
}

glm::vec3 AnalyticScene::project(glm::vec3 p) const {
  glm::vec3 y = p;
  for (int i = 0; i < 16; ++i) {
    glm::vec4 fg = distance_gradient(y);
    glm::vec3 g(fg);
    float g2 = glm::dot(g, g);
    if (!(g2 > 1e-12f)) break;
    glm::vec3 step = fg.w * g / g2;
    y -= step;
    if (glm::dot(step, step) < 1e-14f) break;
  }
  return y;
}

std::vector<glm::ivec3> AnalyticScene::candidate_bricks(uint32_t brick_size) const {
  // Lipschitz culling, coarse to fine: a cube of side s centred at c holds no
  // surface when |f(c)| > L s sqrt(3)/2 (plus one voxel of margin for the
  // half-voxel sample band).
  std::vector<glm::ivec3> out;
  const int bricks = int(lattice_.resolution / brick_size);
  struct Cell {
    glm::ivec3 lo;
    int span;  // in bricks
  };
  std::vector<Cell> stack{{glm::ivec3(0), bricks}};
  while (!stack.empty()) {
    Cell cell = stack.back();
    stack.pop_back();
    double side = double(cell.span) * brick_size * lattice_.voxel;
    glm::dvec3 centre = lattice_.position(cell.lo * int(brick_size)) + glm::dvec3(side / 2);
    double reach = lipschitz() * (side * std::sqrt(3.0) / 2 + 2 * lattice_.voxel);
    if (std::abs(double(distance(glm::vec3(centre)))) > reach) continue;
    if (cell.span == 1) {
      out.push_back(cell.lo);
      continue;
    }
    int half = cell.span / 2;
    for (int i = 0; i < 8; ++i) {
      stack.push_back({cell.lo + glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1) * half, half});
    }
  }
  return out;
}

void AnalyticScene::evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const {
  out.clear();
  const float band = std::min(kBandVoxels * float(lattice_.voxel), near_within);
  for (int z = lo.z; z <= hi.z; ++z) {
    for (int y = lo.y; y <= hi.y; ++y) {
      for (int x = lo.x; x <= hi.x; ++x) {
        glm::vec3 p(lattice_.position({x, y, z}));
        glm::vec4 fg = distance_gradient(p);
        float f = fg.w;
        FinePoint point;
        // First-order distance f / |grad f| decides whether to project.
        float estimate = std::abs(f) / std::max(glm::length(glm::vec3(fg)), 1e-6f);
        if (estimate < 2 * band) {
          glm::vec3 c = project(p);
          float d = glm::length(p - c);
          if (d < band) {
            point.near = true;
            point.distance = f < 0 ? -d : d;
            point.closest = c;
            point.normal = normal(c);
            point.colour = colour(c);
            point.material = material(c);
            out.push_back(point);
            continue;
          }
        }
        float magnitude = std::max(std::abs(f) / lipschitz(), band);
        point.distance = f < 0 ? -magnitude : magnitude;
        out.push_back(point);
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Height field (paper Fig. 9).

HeightfieldScene::HeightfieldScene(int waves, float min_wavelength, float max_wavelength, float sigma_h, unsigned seed,
                                   glm::vec3 abar, glm::vec3 a_s)
    : abar_(abar), a_s_(a_s) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float amplitude = sigma_h * std::sqrt(2.0f / float(waves));
  float max_slope = 0;
  for (int i = 0; i < waves; ++i) {
    float wavelength = min_wavelength * std::pow(max_wavelength / min_wavelength, u(rng));
    float k = 2.0f * float(M_PI) / wavelength;
    float angle = 2.0f * float(M_PI) * u(rng);
    Cosine c{amplitude, k * std::cos(angle), k * std::sin(angle), 2.0f * float(M_PI) * u(rng)};
    waves_.push_back(c);
    height_variance_ += 0.5f * amplitude * amplitude;
    slope_variance_ += 0.5f * amplitude * amplitude * glm::vec2(c.kx * c.kx, c.ky * c.ky);
    max_slope += amplitude * k;
  }
  lipschitz_ = std::sqrt(1.0f + max_slope * max_slope);
}

float HeightfieldScene::height(float x, float y) const {
  float h = 0;
  for (const Cosine& c : waves_) h += c.amplitude * std::cos(c.kx * x + c.ky * y + c.phase);
  return h;
}

glm::vec2 HeightfieldScene::gradient(float x, float y) const {
  glm::vec2 g(0, 0);
  for (const Cosine& c : waves_) g -= c.amplitude * std::sin(c.kx * x + c.ky * y + c.phase) * glm::vec2(c.kx, c.ky);
  return g;
}

float HeightfieldScene::sigma_h() const { return std::sqrt(height_variance_); }

// max(z - H(x, y), sides, bottom): Lipschitz with sqrt(1 + max |grad H|^2);
// evaluate() turns it into a Euclidean distance near the surface.
float HeightfieldScene::distance(glm::vec3 p) const { return distance_gradient(p).w; }

glm::vec4 HeightfieldScene::distance_gradient(glm::vec3 p) const {
  float h = 0;
  glm::vec2 g(0, 0);
  for (const Cosine& c : waves_) {
    float phase = c.kx * p.x + c.ky * p.y + c.phase;
    h += c.amplitude * std::cos(phase);
    g -= c.amplitude * std::sin(phase) * glm::vec2(c.kx, c.ky);
  }
  glm::vec4 best(-g.x, -g.y, 1.0f, p.z - h);
  float side_x = std::abs(p.x) - 1.0f, side_y = std::abs(p.y) - 1.0f, bottom = kBottom - p.z;
  if (side_x > best.w) best = glm::vec4(p.x < 0 ? -1.0f : 1.0f, 0, 0, side_x);
  if (side_y > best.w) best = glm::vec4(0, p.y < 0 ? -1.0f : 1.0f, 0, side_y);
  if (bottom > best.w) best = glm::vec4(0, 0, -1.0f, bottom);
  return best;
}

glm::vec3 HeightfieldScene::colour(glm::vec3 q) const {
  return abar_ + a_s_ * height_sigmoid(height(q.x, q.y), sigma_h());
}

glm::vec3 HeightfieldScene::colour_height_slope() const { return a_s_ * kSigmoidSlope / sigma_h(); }

Box HeightfieldScene::bounds() const {
  // Symmetric about z = 0 (the mean surface), so that lattice points of
  // every depth fall on it.
  float top = std::max(-kBottom, 5.0f * sigma_h());
  return {glm::vec3(-1.0f, -1.0f, -top), glm::vec3(1.0f, 1.0f, top)};
}

namespace {

// A sphere of radius 0.7 carrying bumps b(u) = sum_k A_k sin(f_k w_k . u + phi_k)
// of deviation 0.012 (paper Fig. 11); colour follows the bump height.
class BumpySphere : public AnalyticScene {
 public:
  BumpySphere() : bumps_(kSigma, 24, 11u, [](float u) { return 25.0f + 35.0f * u; }) {
    // |grad b| / r for r >= 0.5.
    lipschitz_ = std::sqrt(1.0f + bumps_.max_slope() * bumps_.max_slope() / (0.5f * 0.5f));
  }
  float bump(glm::vec3 dir) const { return bumps_.height(dir); }
  float distance(glm::vec3 p) const override { return bumps_.sphere_distance(p, kRadius); }
  glm::vec4 distance_gradient(glm::vec3 p) const override { return bumps_.sphere_distance_gradient(p, kRadius); }
  float lipschitz() const override { return lipschitz_; }
  glm::vec3 colour(glm::vec3 q) const override {
    float h = bump(glm::normalize(q));
    return glm::vec3(0.5f, 0.32f, 0.22f) + kColourSlope * height_sigmoid(h, kSigma);
  }
  glm::vec3 colour_height_slope() const override { return kColourSlope * kSigmoidSlope / kSigma; }
  Box bounds() const override {
    float r = kRadius + 5 * kSigma;
    return {glm::vec3(-r), glm::vec3(r)};
  }
  std::string name() const override { return "bumpy-sphere"; }

 private:
  static constexpr float kRadius = 0.7f;
  static constexpr float kSigma = 0.012f;
  static constexpr glm::vec3 kColourSlope{0.35f, 0.3f, -0.12f};
  SineBumps bumps_;
  float lipschitz_ = 1;
};

// A capped cylinder along y whose radius varies with the angle only:
// r(theta) = 0.5 + A sin(48 theta), grooves along the axis, so its slopes are
// strongly anisotropic (paper Fig. 5); colour follows the groove height.
class GroovedCylinder : public AnalyticScene {
 public:
  float groove(glm::vec3 p) const { return kAmplitude * std::sin(kGrooves * std::atan2(p.z, p.x)); }
  float distance(glm::vec3 p) const override {
    float rho = std::sqrt(p.x * p.x + p.z * p.z);
    float slope = kAmplitude * kGrooves / std::max(rho, 0.1f);
    float side = (rho - kRadius - groove(p)) / std::sqrt(1.0f + slope * slope * 0.5f);
    return std::max(side, std::abs(p.y) - kHalfHeight);
  }
  float lipschitz() const override { return 2.5f; }
  glm::vec3 colour(glm::vec3 q) const override {
    return glm::vec3(0.3f, 0.55f, 0.3f) + kColourSlope * height_sigmoid(groove(q), kSigma);
  }
  glm::vec3 colour_height_slope() const override { return kColourSlope * kSigmoidSlope / kSigma; }
  Box bounds() const override {
    float r = kRadius + kAmplitude;
    return {glm::vec3(-r, -kHalfHeight, -r), glm::vec3(r, kHalfHeight, r)};
  }
  std::string name() const override { return "grooved-cylinder"; }

 private:
  static constexpr float kRadius = 0.5f;
  static constexpr float kAmplitude = 0.015f;
  static constexpr float kGrooves = 48.0f;
  static constexpr float kHalfHeight = 0.6f;
  static constexpr float kSigma = kAmplitude / 1.41421356f;
  static constexpr glm::vec3 kColourSlope{-0.2f, 0.3f, -0.15f};
};

}  // namespace

// ---------------------------------------------------------------------------
// Detail octaves.

namespace {

svo::math::SvoDetail shared_detail(const octree::Detail& d) {
  svo::math::SvoDetail s;
  s.octaves = d.octaves;
  s.seed = d.seed;
  s.amplitude = d.amplitude;
  s.wavelength = d.wavelength;
  s.gain = d.gain;
  return s;
}

}  // namespace

DetailedScene::DetailedScene(std::unique_ptr<AnalyticScene> base, const octree::Detail& detail, bool all_octaves)
    : base_(std::move(base)), detail_(detail), all_(all_octaves) {
  set_sigma_rho2(base_->sigma_rho2());
  float slope = 0;
  for (uint32_t k = 0; k < detail_.octaves; ++k) {
    slope += detail_.amplitude * std::pow(detail_.gain, float(k)) / (detail_.wavelength * std::exp2(-float(k)));
  }
  float amplitude = 0;
  for (uint32_t k = 0; k < detail_.octaves; ++k) amplitude += detail_.amplitude * std::pow(detail_.gain, float(k));
  amplitude *= svo::math::SVO_NOISE_MAX;
  // |grad (|grad f| D)| <= L |grad D| + |D| |grad |grad f||; the second term,
  // the displacement times the base's curvature, is taken as at most 1 (the
  // bumpy sphere's: 0.004 times at most 70, the largest |grad |grad f|| of
  // 2 million points near its surface, where |grad f| reached 2.5).
  const float steepest = base_->lipschitz();
  lipschitz_ = steepest * (1.0f + slope * svo::math::SVO_NOISE_MAX_GRADIENT) + 1.0f;
  reach_ = amplitude;
  reach_f_ = amplitude * steepest;
}

glm::dvec2 DetailedScene::distance_bound(glm::vec3 p) const {
  glm::dvec2 base = base_->distance_bound(p);
  const double margin = std::abs(base.x) - reach_f_;
  if (margin > 0) {
    // On the displaced surface f = |grad f| D, so |f| <= reach_f_ there: a
    // sphere of base radius * (margin / |f|) is clear.
    return {base.x, base.y * margin / std::abs(base.x)};
  }
  double f = distance(p);
  return {f, std::abs(f) / std::max(1.0, double(lipschitz_))};
}

void DetailedScene::prepare(const Lattice& lattice) {
  AnalyticScene::prepare(lattice);
  base_->prepare(lattice);
  drawn_radius_ = all_ ? 0.0f : float(lattice.voxel / std::sqrt(2.0));
}

glm::vec4 DetailedScene::displacement(glm::vec3 p) const {
  return svo::math::svo_detail_displacement(shared_detail(detail_), p, drawn_radius_, 3.0e38f);
}

float DetailedScene::distance(glm::vec3 p) const {
  const glm::vec4 f = base_->distance_gradient(p);
  return f.w - glm::length(glm::vec3(f)) * displacement(p).w;
}

// The normal moved as the renderer moves it: the base's unit normal tilted
// by grad D (svo_detail_tilt), scaled by |grad f| (the term D grad |grad f|
// is left out: the displacement times the base's curvature).
glm::vec4 DetailedScene::distance_gradient(glm::vec3 p) const {
  const glm::vec4 f = base_->distance_gradient(p);
  const float norm = glm::length(glm::vec3(f));
  return glm::vec4(f) - norm * displacement(p);
}

glm::vec3 DetailedScene::colour(glm::vec3 q) const {
  return base_->colour(q) + detail_.colour_slope * displacement(q).w;
}

Box DetailedScene::bounds() const {
  Box b = base_->bounds();
  return {b.lo - reach_, b.hi + reach_};
}

glm::vec2 detail_folded_variance(const octree::Detail& detail, double voxel) {
  return svo::math::svo_detail_moved_variance(shared_detail(detail), 0.0f, float(voxel / std::sqrt(2.0)));
}

octree::Detail make_detail(const AnalyticScene& scene, uint32_t octaves, float amplitude, float wavelength,
                           uint32_t seed) {
  octree::Detail d;
  d.octaves = octaves;
  d.seed = seed;
  d.amplitude = amplitude;
  d.wavelength = wavelength;
  d.gain = 0.5f;
  d.colour_slope = scene.colour_height_slope();
  return d;
}

namespace {

// Three spheres on a floor, each its own material, the floor's tiles
// alternating between a glossy and a rough GGX (a glossiness map): the
// scene of the module papers' figures, with an exact distance (the union of
// a box's and three spheres' exact distances).
class MaterialSpheres : public AnalyticScene {
 public:
  float box(glm::vec3 p) const {
    glm::vec3 q = glm::abs(p - kFloorCentre) - kFloorHalf;
    return glm::length(glm::max(q, glm::vec3(0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0f);
  }
  float sphere(glm::vec3 p, int i) const { return glm::length(p - centre(i)) - kRadius; }
  static glm::vec3 centre(int i) { return glm::vec3(0.75f * float(i - 1), kRadius - kSink, 0.0f); }
  float distance(glm::vec3 p) const override {
    float d = box(p);
    for (int i = 0; i < 3; ++i) d = std::min(d, sphere(p, i));
    return d;
  }
  // The part nearest to q: the floor (-1) or sphere i.
  int part(glm::vec3 q) const {
    int best = -1;
    float d = std::abs(box(q));
    for (int i = 0; i < 3; ++i) {
      float s = std::abs(sphere(q, i));
      if (s < d) d = s, best = i;
    }
    return best;
  }
  uint32_t material(glm::vec3 q) const override {
    int i = part(q);
    if (i >= 0) return uint32_t(2 + i);
    // The glossiness map: tiles of kTile, glossy and rough in turn.
    int tile = int(std::floor(q.x / kTile)) + int(std::floor(q.z / kTile));
    return uint32_t(tile & 1);
  }
  glm::vec3 colour(glm::vec3 q) const override {
    static constexpr glm::vec3 kColours[3] = {{1.0f, 1.0f, 1.0f}, {0.75f, 0.12f, 0.1f}, {0.35f, 0.55f, 0.8f}};
    int i = part(q);
    return i < 0 ? glm::vec3(0.6f, 0.58f, 0.55f) : kColours[i];
  }
  std::vector<std::string> materials() const override {
    return {R"({"name": "floor-glossy", "brdf": "ggx", "roughness": 0.05, "f0": [0.04, 0.04, 0.04], "diffuse": 0.8})",
            R"({"name": "floor-rough", "brdf": "ggx", "roughness": 0.45, "f0": [0.04, 0.04, 0.04], "diffuse": 0.8})",
            R"({"name": "gold", "brdf": "ggx", "roughness": 0.2, "f0": [1.0, 0.78, 0.34], "diffuse": 0})",
            R"({"name": "plastic", "brdf": "phong", "exponent": 200, "f0": [0.05, 0.05, 0.05], "diffuse": 0.9})",
            R"({"name": "clay", "brdf": "lambert", "diffuse": 0.9})"};
  }
  Box bounds() const override {
    return {kFloorCentre - kFloorHalf, glm::vec3(kFloorHalf.x, 2 * kRadius - kSink, kFloorHalf.z)};
  }
  double surface_area() const override {
    const glm::dvec3 h(kFloorHalf);
    return 8.0 * (h.x * h.y + h.y * h.z + h.z * h.x) + 3 * 4 * 3.14159265 * kRadius * kRadius;
  }
  std::string name() const override { return "material-spheres"; }

 private:
  static constexpr float kRadius = 0.3f;
  static constexpr float kSink = 0.03f;  // the spheres sink into the floor: no tangent contact
  static constexpr float kTile = 0.25f;
  static constexpr glm::vec3 kFloorCentre{0.0f, -0.05f, 0.0f};
  static constexpr glm::vec3 kFloorHalf{1.2f, 0.05f, 0.7f};
};

}  // namespace

std::vector<std::string> scene_names() {
  return {"bumpy-sphere", "heightfield", "grooved-cylinder", "material-spheres"};
}

std::unique_ptr<AnalyticScene> make_scene(const std::string& name) {
  if (name == "bumpy-sphere") return std::make_unique<BumpySphere>();
  if (name == "grooved-cylinder") return std::make_unique<GroovedCylinder>();
  if (name == "material-spheres") return std::make_unique<MaterialSpheres>();
  if (name == "heightfield") {
    return std::make_unique<HeightfieldScene>(64, 0.08f, 0.25f, 0.02f, 5, glm::vec3(0.45f, 0.4f, 0.3f),
                                              glm::vec3(0.3f, 0.2f, 0.15f));
  }
  std::string names;
  for (const auto& n : scene_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown scene '" + name + "' (scenes: " + names + ")");
}

}  // namespace svo::voxelizer
