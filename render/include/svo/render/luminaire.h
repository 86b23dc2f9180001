// Light-field luminaires (Lu et al. 2015, DESIGN 10.4): a two-plane light
// field of M = W x H images C_m on plane S, each with a basis function Phi_m
// on plane U, its file (.lfl, docs/luminaire.md), procedural emitters whose
// light field is known, and the import of IES TM-25 ray files.
//
// The model, in the luminaire's own frame (metres, or the file's units):
// plane U is z = 0, plane S is z = delta, and light leaves through S towards
// +z. The radiance along the ray from u on U through s on S is
//   L(u -> s) = sum_m C_m(s) Phi_m(u)                               (Eq. 1)
// (the canned-light-source reconstruction, Psi_m = Phi_m), with C_m
// piecewise constant over the image's texels (radiance, W m^-2 sr^-1 in the
// file's units) and Phi_m = phi((u - c_m.x) / h) phi((v - c_m.y) / h), the
// centres c_m on a regular W x H grid of spacing h centred on the axis.
#pragma once

#include <cstdint>
#include <filesystem>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <string>
#include <vector>

namespace svo::render {

// The 1D profile phi of the basis functions on U (values are the file's).
enum class LuminaireBasis : uint32_t {
  // The quadratic B-spline: support 3 cells ([-1.5, 1.5] in units of h), a
  // partition of unity (Lu et al.'s car data).
  BSpline = 0,
  // A piecewise quadratic of support 2 cells, 1 - x^2 on [-1, 1]: not a
  // partition of unity (its sum ripples between 1 and 1.5), standing for
  // Goesele et al.'s functions (the bike data).
  Quadratic = 1,
};
const char* luminaire_basis_name(LuminaireBasis basis);  // "bspline", "quadratic"
// The support of phi in cells: 3 for BSpline, 2 for Quadratic (n in section 6.2).
uint32_t luminaire_basis_cells(LuminaireBasis basis);
// phi(x), x in units of the grid spacing.
float luminaire_basis_phi(LuminaireBasis basis, float x);

// Where a luminaire stands in a scene: the centre of plane S, the point its
// axis (+z of its frame) looks at, and the size of plane S across (the
// larger of its two extents) in scene units; size <= 0 keeps the file's own
// size in its units.
struct LuminairePlacement {
  glm::vec3 at{0.0f, 2.0f, 0.0f};
  glm::vec3 aim{0.0f};
  float size = 0.0f;
};

struct LightField {
  static constexpr uint32_t kVersion = 1;
  // Limits the loader enforces before it allocates (and that make/import keep).
  static constexpr uint32_t kMaxImageSide = 1024;
  static constexpr uint32_t kMaxGridSide = 16;
  static constexpr uint64_t kMaxTexels = 64ull << 20;  // over all images

  float delta = 0.05f;              // distance between U and S, > 0
  glm::vec2 extent{0.1f, 0.1f};     // plane S's size in x and y, > 0, centred on the axis
  uint32_t width = 0, height = 0;   // each image's texels in x and y, 1 to kMaxImageSide
  uint32_t grid_w = 0, grid_h = 0;  // W x H basis functions, 1 to kMaxGridSide each
  float spacing = 0.01f;            // h, the basis grid's spacing on U, > 0
  LuminaireBasis basis = LuminaireBasis::BSpline;
  std::string units = "m";       // the length unit of delta, extent and spacing ("m", "mm", ...)
  float metres_per_unit = 1.0f;  // > 0
  LuminairePlacement pose;       // the file's default placement (its own frame: at the origin)
  std::string source;            // what made it (a description; at most 255 bytes in the file)
  // M = grid_w * grid_h images, image m = j * grid_w + i for basis (i, j),
  // each width * height RGB radiances, row 0 at -y, texel (x, y) at
  // images[m][3 * (y * width + x) + c]; every value finite and >= 0.
  std::vector<std::vector<float>> images;

  uint32_t image_count() const { return grid_w * grid_h; }
  // The centre of basis m on U (z = 0).
  glm::vec2 basis_centre(uint32_t m) const;
  // Phi_m(u).
  float basis_value(uint32_t m, glm::vec2 u) const;
  // The axis-aligned support of Phi_m on U: [lo, hi].
  void basis_support(uint32_t m, glm::vec2& lo, glm::vec2& hi) const;
  // The radiance of the ray from u (on U) through s (on S), RGB; 0 outside S.
  glm::vec3 radiance(glm::vec2 u, glm::vec2 s) const;
};

// Checks every count, size and value of a light field made in memory.
// @throw std::runtime_error "luminaire: SOURCE: why" (one line)
void validate_light_field(const LightField& field);

// Writes a .lfl file (docs/luminaire.md) to a temporary name in the same
// folder and renames it over `path`; refuses a field validate_light_field
// refuses before it writes anything.
// @throw std::runtime_error "luminaire: PATH: why" (one line)
void save_light_field(const LightField& field, const std::filesystem::path& path);

// Reads a .lfl file, checking the magic, version, every count and size
// against the limits and the file's length before it allocates, the
// checksum, and every value.
// @throw std::runtime_error "luminaire: PATH: why" (one line)
LightField load_light_field(const std::filesystem::path& path);
// The same from bytes in memory (the fuzz target); `name` stands for the path.
LightField parse_light_field(const uint8_t* data, size_t size, const std::string& name);
std::vector<uint8_t> encode_light_field(const LightField& field);

// Procedural emitters whose light field is known in closed form.
// A textured panel: plane S is a Lambertian emitter of radiance
// `radiance` x a checker texture of `checks` x `checks` squares alternating
// between (1, 0.95, 0.85) and (0.25, 0.3, 0.4) (every image the same:
// L(u -> s) = C(s) sum_m Phi_m(u), constant in u where the basis is a
// partition of unity).
LightField make_panel_luminaire(uint32_t resolution, uint32_t grid, float radiance, uint32_t checks = 4);
// A headlight-like emitter: a bright reflector spot whose beam is narrow and
// aimed: image m holds a Gaussian spot of width `beam` (in units of S's
// extent) centred where the ray from basis centre m through the point at
// distance `focus` on the axis crosses S, so that the light converges to a
// hot spot ahead and each position on U lights a different part of S.
LightField make_headlight_luminaire(uint32_t resolution, uint32_t grid, float radiance, float beam = 0.08f,
                                    float focus = 0.5f);

// An LED headlight: a leds x leds array of small dies whose beams converge
// to foci spread across the road `focus` ahead: image m holds one sharp spot
// of width `die` (in units of S's extent) per die, where the ray from basis
// centre m to that die's focus crosses S. Its images are mostly dark, so
// that where the samples of S go matters (the restricted CDFs' case).
LightField make_led_luminaire(uint32_t resolution, uint32_t grid, float radiance, uint32_t leds = 3, float die = 0.015f,
                              float focus = 0.12f);

// Reads an IES TM-25 ray file and bins its rays into a light field of
// grid x grid basis functions and resolution x resolution images (flux
// conserved; docs/luminaire.md, "Importing TM-25 ray files").
// @throw std::runtime_error "tm25: PATH: why" (one line)
LightField import_tm25(const std::filesystem::path& path, uint32_t grid, uint32_t resolution);

// The flux leaving plane S towards +z, in watts (or the images' unit times
// area): the integral of L cos^4(theta) / delta^2 over U x S, by quadrature.
double light_field_flux(const LightField& field, uint32_t samples_per_texel = 2);

// ---- Rendering (shaders/common/luminaire.glsl, render::LuminairePass) ----

// How each G-buffer point draws its samples of plane S (values are the
// kernel's SVO_LUM_SAMPLER_*).
enum class LuminaireSampler : uint32_t {
  Restricted = 0,  // the paper's: image CDFs restricted to the projected support (Eq. 7-8), balanced by A_m (Eq. 12)
  Uniform = 1,     // the same box sampled uniformly, the same share of samples for every image (Fig. 12)
  Global = 2,      // precomputed global CDFs: images by their total energy, texels over the whole image (Fig. 11)
  Box = 3,         // as Restricted, the marginal over columns taken from the box's own rows (summed-area
                   // table), so that the density is exactly C_m / A_m (Eq. 10); Eq. 8's is not (docs/luminaire.md)
};
// The inversion of the CDFs (Fig. 5): the paper's modified secant (false
// position), halving (the chord's root in the interval a limited depth
// leaves), the Illinois variant of the secant (ours), or the classical
// binary search (halving; a limited depth returns the interval's midpoint).
enum class LuminaireSearch : uint32_t { Secant = 0, Binary = 1, Illinois = 2, Classic = 3 };
// The visibility of the luminaire from the shaded point, by cones through
// the octree (section 6.2 with cones for shadow maps): one per basis cell
// towards its reference position on S (the paper's), one per sample, or one
// per basis cell along the line to the cell on U (ours: per point).
enum class LuminaireVisibility : uint32_t { None = 0, Cells = 1, Samples = 2, CellsOnU = 3 };
// The sample sequence (Fig. 8): Halton, or independent uniform numbers (a
// PCG hash per sample, standing for the paper's Mersenne twister).
enum class LuminaireSequence : uint32_t { Halton = 0, Random = 1 };

const char* luminaire_sampler_name(LuminaireSampler s);        // "restricted", "uniform", "global", "box"
const char* luminaire_search_name(LuminaireSearch s);          // "secant", "binary", "illinois", "classic"
const char* luminaire_visibility_name(LuminaireVisibility v);  // "none", "cells", "samples"
const char* luminaire_sequence_name(LuminaireSequence s);      // "halton", "random"
// @throw std::invalid_argument naming the values there are
LuminaireSampler parse_luminaire_sampler(const std::string& name);
LuminaireSearch parse_luminaire_search(const std::string& name);
LuminaireVisibility parse_luminaire_visibility(const std::string& name);
LuminaireSequence parse_luminaire_sequence(const std::string& name);

struct PlacedLuminaire {
  std::shared_ptr<const LightField> field;
  LuminairePlacement placement;
};

// What the luminaire pass shades with (RenderSettings::luminaire).
struct LuminaireOptions {
  std::vector<PlacedLuminaire> luminaires;  // at most kMaxLuminaires
  static constexpr uint32_t kMaxLuminaires = 8;
  LuminaireSampler sampler = LuminaireSampler::Restricted;
  LuminaireSearch search = LuminaireSearch::Secant;
  // Ours by default: at the paper's cost, and right where S is wide (docs/luminaire.md).
  LuminaireVisibility visibility = LuminaireVisibility::CellsOnU;
  LuminaireSequence sequence = LuminaireSequence::Halton;
  uint32_t spp = 200;         // K, samples per pixel over all images of a luminaire, >= 1
  uint32_t kmax = 0;          // K_max, the cap on K_m(p) (Fig. 9); 0: none
  uint32_t search_depth = 0;  // steps of the CDF inversion before it interpolates (Fig. 5); 0: until exact
  uint32_t seed = 1;
  // > 0: instead of sampling, dense quadrature of the same integral with
  // quadrature^2 points per texel of S and no visibility (the ground truth
  // of one G-buffer for the tests and `svo bench luminaire`; native host only).
  uint32_t quadrature = 0;
};

// The tables luminaire.glsl reads (its header comment gives the layout):
// every luminaire's frame in scene units, its images' CDFs, colours and
// summed-area tables, and the cells' reference positions.
std::vector<float> build_luminaire_tables(const LuminaireOptions& options);

// The scene-unit frame of a placed luminaire: plane S's centre, its axes
// (x, y across S; z the axis, away from U) and the scale from the file's
// units to scene units.
struct LuminaireFrame {
  glm::vec3 centre, x, y, z;
  float scale;
};
// @throw std::invalid_argument when `aim` equals `at`
LuminaireFrame luminaire_frame(const LightField& field, const LuminairePlacement& placement);

}  // namespace svo::render
