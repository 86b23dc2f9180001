#include "svo/voxelizer/build.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "common/shared_math.h"
#include "svo/octree/sampler.h"
#include "svo/voxelizer/scenes.h"
#include "svo/voxelizer/statistics.h"

namespace svo::voxelizer {

namespace {

using Key = uint64_t;
constexpr int kKeyBits = 21;

Key pack(glm::ivec3 p) {
  return uint64_t(uint32_t(p.x)) | (uint64_t(uint32_t(p.y)) << kKeyBits) | (uint64_t(uint32_t(p.z)) << (2 * kKeyBits));
}
glm::ivec3 unpack(Key k) {
  const uint64_t mask = (uint64_t(1) << kKeyBits) - 1;
  return glm::ivec3(int(k & mask), int((k >> kKeyBits) & mask), int((k >> (2 * kKeyBits)) & mask));
}

bool power_of_two(uint32_t v) { return v && !(v & (v - 1)); }

// Per depth: the lattice points whose footprint holds samples, and the bricks to store.
struct Level {
  uint32_t cells = 0;  // lattice cells per axis
  double voxel = 0;
  std::unordered_map<Key, uint32_t> filled;  // lattice key -> index into stats
  std::vector<octree::Voxel> stats;  // one-sided: two_sided() applies where `sheet` says, when bricks are filled
  std::vector<uint8_t> sheet;        // per stats entry: a sheet of an open surface, drawn two-sided
  std::vector<float> offset;         // per stats entry of a sheet: where its shell lies (SurfaceSample::offset)
  std::unordered_set<Key> bricks;
};

// Inserts every brick whose closed lattice range [b B, b B + B] holds p: the
// brick that owns p (stores it) and those that interpolate across it, so that
// a filled point on a stored brick's upper face always has its owner stored
// and the faces rebuilt from neighbours are exact (octree.h).
void add_bricks_holding(glm::ivec3 p, int brick, int bricks_per_axis, std::unordered_set<Key>& out) {
  glm::ivec3 b = p / brick;
  for (int i = 0; i < 8; ++i) {
    glm::ivec3 o(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    glm::ivec3 c = b - o;
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      if (o[a] && p[a] % brick != 0) ok = false;  // only on a face does p belong to the lower brick too
      if (c[a] < 0 || c[a] >= bricks_per_axis) ok = false;
    }
    if (ok) out.insert(pack(c));
  }
}

struct Clock {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); }
};

}  // namespace

Lattice make_lattice(const Box& bounds, uint32_t resolution) {
  glm::dvec3 lo(bounds.lo), hi(bounds.hi);
  double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-6});
  Lattice lattice;
  lattice.resolution = resolution;
  lattice.voxel = extent / (double(resolution) - 8.0);
  double side = lattice.voxel * resolution;
  lattice.origin = (lo + hi) * 0.5 - glm::dvec3(side * 0.5);
  return lattice;
}

double estimate_memory_bytes(const SurfaceSource& source, uint32_t resolution, uint32_t brick_size) {
  const Lattice lattice = make_lattice(source.bounds(), resolution);
  const double samples = source.surface_area() / (lattice.voxel * lattice.voxel);
  // Per sample: the sample itself and its finest key (48), the sort of one
  // level (16), statistics and maps of all coarser levels (~1/3 x 96).
  const double per_sample = 48 + 16 + 32 + source.bytes_per_sample();
  // Finest bricks: about 2.5 per brick_size^2 of surface, coarser levels add a third.
  const double b = brick_size;
  const double bricks = 2.5 * samples / (b * b) * (4.0 / 3.0);
  const double brick_bytes = bricks * b * b * b * 16.0;
  return samples * per_sample + brick_bytes + 64.0 * 1024 * 1024;
}

namespace {

struct BrickJob {
  uint32_t depth;
  glm::ivec3 coords;
};

// One voxelize() call: its stages share the lattice, the samples, the levels
// and the tree under construction.
struct Builder {
  SurfaceSource& source;
  const VoxelizeOptions& options;
  VoxelizeReport& rep;
  const uint32_t B, N;
  Clock clock;
  Lattice lattice;
  uint32_t depth_count = 1, D = 0;
  float h = 0;
  std::vector<SurfaceSample> samples;
  std::vector<Level> levels;
  octree::Octree tree;
  std::vector<BrickJob> jobs;
  glm::vec3 colour_mean{0};
  // Detail octaves the finest lattice cannot draw: their (height variance,
  // per-axis slope variance) join every voxel's statistics.
  octree::Detail detail;
  glm::vec2 folded{0};
  tbb::enumerable_thread_specific<std::vector<FinePoint>> scratch;
  tbb::enumerable_thread_specific<std::vector<int32_t>> filled_scratch;

  Builder(SurfaceSource& s, const VoxelizeOptions& o, VoxelizeReport& r)
      : source(s), options(o), rep(r), B(o.brick_size), N(o.resolution) {}

  void progress(const std::string& stage, double f, uint64_t done = 0, uint64_t total = 0) const {
    if (options.progress_items) {
      options.progress_items(stage, f, done, total);
    } else if (options.progress) {
      options.progress(stage, f);
    }
  }

  void prepare() {
    lattice = make_lattice(source.bounds(), N);
    progress("distance field", 0.0);
    source.prepare(lattice);
    rep.seconds_source = clock.seconds();
    while ((B << (depth_count - 1)) < N) ++depth_count;
    D = depth_count - 1;
    h = float(lattice.voxel);
    detail = source.detail();
    if (detail.octaves > 0) folded = detail_folded_variance(detail, lattice.voxel);
  }

  // Independent height components add their variances, their slope
  // variances and their colour-height covariances (detail.glsl).
  void fold_detail(octree::Voxel& v) const {
    if (detail.octaves == 0) return;
    float var = v.sigma_h * v.sigma_h;
    v.a_s = math::svo_detail_fold_a_s(v.a_s, var, folded.x, detail.colour_slope);
    v.sigma_h = std::sqrt(var + folded.x);
    v.slope_cov.x += folded.y;
    v.slope_cov.y += folded.y;
  }

  void collect_samples() {
    // --- Finest samples: lattice points within half a voxel of the surface.
    progress("surface samples", 0.15);
    std::vector<glm::ivec3> candidates = source.candidate_bricks(B);
    std::atomic<size_t> evaluated{0};
    struct Found {
      Key key;
      SurfaceSample sample;
    };
    tbb::enumerable_thread_specific<std::vector<Found>> found_local;
    tbb::enumerable_thread_specific<std::vector<Key>> shell_points_local;
    tbb::enumerable_thread_specific<std::vector<std::pair<Key, Key>>> unsure_local;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
      auto& found = found_local.local();
      auto& points = scratch.local();
      for (size_t c = r.begin(); c != r.end(); ++c) {
        glm::ivec3 lo = candidates[c] * int(B), hi = lo + glm::ivec3(int(B) - 1);
        // Samples lie within h/2 of the surface; a sheet's shell reaches
        // h/2 beyond its outer faces; a margin for rounding.
        source.evaluate(lo, hi, points, (kShellFaceReach + 0.25f) * h);
        size_t i = 0;
        for (int z = lo.z; z <= hi.z; ++z)
          for (int y = lo.y; y <= hi.y; ++y)
            for (int x = lo.x; x <= hi.x; ++x, ++i) {
              const FinePoint& p = points[i];
              // A sheet's samples are the lattice points within h/2 of the
              // sheet itself, on either side, with its own orientation.
              if (p.near && (p.sheet >= 0 ? p.sheet : std::abs(p.distance)) <= 0.5f * h) {
                found.push_back({pack({x, y, z}),
                                 {p.closest, p.sheet >= 0 ? p.sheet_normal : p.normal, p.colour, p.material,
                                  p.sheet >= 0, p.sheet_offset}});
              } else if (p.near && p.sheet >= 0 && p.distance <= 0.5f * h) {  // inside the shell or near its faces
                shell_points_local.local().push_back(pack({x, y, z}));
              }
            }
        flag_unsure_faces(candidates[c], points, unsure_local.local());
        const size_t n = ++evaluated;
        if (n % 1024 == 0) {
          progress("surface samples", 0.15 + 0.15 * double(n) / double(candidates.size()), n, candidates.size());
        }
      }
    });
    std::vector<Found> found;
    for (auto& f : found_local) found.insert(found.end(), f.begin(), f.end());
    tbb::parallel_sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.key < b.key; });
    if (found.empty()) {
      throw std::runtime_error("the surface leaves no sample at resolution " + std::to_string(N));
    }
    samples.resize(found.size());
    levels.resize(depth_count);
    for (uint32_t d = 0; d < depth_count; ++d) {
      levels[d].cells = B << d;
      levels[d].voxel = lattice.voxel * double(N / levels[d].cells);
    }
    for (size_t i = 0; i < found.size(); ++i) {
      samples[i] = found[i].sample;
      add_bricks_holding(unpack(found[i].key), int(B), int(N / B), levels[D].bricks);
    }
    // The bricks a sheet's shell faces cross, though they hold no sample:
    // without them the brick below rebuilds its face by extrapolation,
    // which carries the far side's sign and normal out through the shell
    // (dark patches on the lion's head at 256^3, far view).
    for (const auto& points : shell_points_local) {
      for (Key k : points) add_bricks_holding(unpack(k), int(B), int(N / B), levels[D].bricks);
    }
    shell_points_local.clear();
    // The bricks whose faces the brick below could not rebuild on the right
    // side (flag_unsure_faces), where that brick is stored.
    for (const auto& pairs : unsure_local) {
      for (const auto& [from, owner] : pairs) {
        if (levels[D].bricks.count(from)) levels[D].bricks.insert(owner);
      }
    }
    rep.samples = samples.size();
    found = {};
    rep.seconds_samples = clock.seconds() - rep.seconds_source;
  }

  // A stored brick's upper faces, where their owner brick is absent, are
  // rebuilt by the renderer from this brick's last two layers (octree.h:
  // linear extrapolation, kept at least half a finest voxel from zero, on
  // the nearer stored sample's side when it falls short). Beside an edge
  // that guess can take the wrong side: fandisk at 256^3, a lattice point
  // 0.62 voxel above its top face, on the brick face just above it, was
  // rebuilt as -0.5 voxel (inside) from the side face's distances below
  // it, and moved a long edge outwards by a voxel. The owners of face
  // points where the rule (octree::reconstructed_distance) decides the side
  // against the extrapolation or on weak evidence (it falls short of the
  // floor) are flagged (brick, owner), to be stored with their exact
  // values: fandisk at 256^3 gains 145 bricks (4%), and no face point of
  // the finest depth is rebuilt on the wrong side
  // (tests/voxelizer/faces_test.cpp).
  void flag_unsure_faces(glm::ivec3 brick, const std::vector<FinePoint>& points,
                         std::vector<std::pair<Key, Key>>& out) const {
    const int b = int(B), limit = int(N / B);
    const float floor = 0.5f * float(h);
    auto f = [&](glm::ivec3 l) { return points[size_t((l.z * b + l.y) * b + l.x)].distance; };
    uint32_t flagged = 0;  // bit s: the owner at brick + axis_bits(s)
    for (int z = 0; z <= b; ++z)
      for (int y = 0; y <= b; ++y)
        for (int x = 0; x <= b; ++x) {
          const glm::ivec3 l(x, y, z);
          const glm::ivec3 axes = glm::ivec3(glm::equal(l, glm::ivec3(b)));
          if (axes == glm::ivec3(0)) continue;
          const glm::ivec3 owner = brick + axes;
          if (glm::any(glm::greaterThanEqual(owner, glm::ivec3(limit)))) continue;  // the domain's shell
          const glm::ivec3 q = l - axes;
          const uint32_t s = uint32_t(axes.x + 2 * axes.y + 4 * axes.z);
          double sum = 0;
          for (uint32_t t = 0; t < 8; ++t) {
            const double w = octree::extrapolation_weight(s, t);
            if (w != 0) sum += w * double(f(q - glm::ivec3(t & 1u, (t >> 1) & 1u, t >> 2)));
          }
          const float kept = octree::reconstructed_distance(sum, f(q), floor, float(h));
          if ((kept < 0) != (sum < 0) || !(std::abs(sum) >= floor)) flagged |= 1u << s;
        }
    for (int s = 1; s < 8; ++s) {
      if (flagged & (1u << s)) out.emplace_back(pack(brick), pack(brick + glm::ivec3(s & 1, (s >> 1) & 1, s >> 2)));
    }
  }

  void coarse_statistics() {
    // --- Coarser levels: statistics over box footprints centred on lattice points.
    for (int d = int(D) - 1; d >= 0; --d) {
      progress("statistics depth " + std::to_string(d), 0.3 + 0.2 * double(D - d) / D);
      Level& level = levels[size_t(d)];
      std::vector<std::pair<Key, uint32_t>> keyed(samples.size());
      tbb::parallel_for(size_t(0), samples.size(), [&](size_t i) {
        glm::dvec3 q = (glm::dvec3(samples[i].position) - lattice.origin) / level.voxel;
        glm::ivec3 k = glm::clamp(glm::ivec3(glm::round(q)), glm::ivec3(0), glm::ivec3(int(level.cells)));
        keyed[i] = {pack(k), uint32_t(i)};
      });
      tbb::parallel_sort(keyed.begin(), keyed.end());
      std::vector<size_t> starts;
      for (size_t i = 0; i < keyed.size(); ++i) {
        if (i == 0 || keyed[i].first != keyed[i - 1].first) starts.push_back(i);
      }
      starts.push_back(keyed.size());
      std::vector<uint32_t> order(keyed.size());
      for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
      level.stats.resize(starts.size() - 1);
      level.sheet.assign(starts.size() - 1, 0);
      level.offset.assign(starts.size() - 1, 0.0f);
      tbb::parallel_for(size_t(0), starts.size() - 1, [&](size_t g) {
        glm::ivec3 k = unpack(keyed[starts[g]].first);
        glm::vec3 centre(lattice.origin + glm::dvec3(k) * level.voxel);
        const auto indices = std::span(order).subspan(starts[g], starts[g + 1] - starts[g]);
        level.stats[g] = surface_statistics(samples, indices, centre);
        size_t sheets = 0;
        double offset = 0;
        for (uint32_t i : indices) sheets += samples[i].sheet, offset += samples[i].sheet ? samples[i].offset : 0.0;
        level.sheet[g] = 2 * sheets > indices.size();
        if (sheets) level.offset[g] = float(offset / double(sheets));
      });
      level.filled.reserve(starts.size());
      for (size_t g = 0; g + 1 < starts.size(); ++g) {
        Key key = keyed[starts[g]].first;
        level.filled.emplace(key, uint32_t(g));
        add_bricks_holding(unpack(key), int(B), int(level.cells / B), level.bricks);
        if (!level.sheet[g]) continue;
        // A sheet's shell reaches a voxel beyond it, two behind it where it
        // lies inside a volume (SurfaceSample::offset): the bricks of the
        // lattice points around it too (their values come from the sheet's
        // plane, fill_bricks), as at the finest level.
        const int r = level.offset[g] > 0 ? 2 : 1, w = 2 * r + 1;
        for (int n = 0; n < w * w * w; ++n) {
          const glm::ivec3 q = unpack(key) + glm::ivec3(n % w - r, (n / w) % w - r, n / (w * w) - r);
          if (glm::all(glm::greaterThanEqual(q, glm::ivec3(0))) &&
              glm::all(glm::lessThanEqual(q, glm::ivec3(int(level.cells))))) {
            add_bricks_holding(q, int(B), int(level.cells / B), level.bricks);
          }
        }
      }
      for (auto& v : level.stats) fold_detail(v);
      rep.filled_voxels += level.stats.size();
    }
    rep.filled_voxels += rep.samples;
    // Every brick's parent exists.
    for (uint32_t d = D; d >= 1; --d) {
      for (Key k : levels[d].bricks) levels[d - 1].bricks.insert(pack(unpack(k) / 2));
    }

    rep.seconds_statistics = clock.seconds() - rep.seconds_source - rep.seconds_samples;
  }

  void build_topology() {
    // --- Topology: nodes depth by depth, children in tiles of 8.
    progress("topology", 0.5);
    tree.brick_size = B;
    tree.depth_count = depth_count;
    tree.origin = glm::vec3(lattice.origin);
    tree.size = float(lattice.voxel * N);
    tree.sigma_rho2 = source.sigma_rho2();
    tree.detail = detail;
    std::vector<glm::ivec3> coords{glm::ivec3(0)};
    tree.nodes.push_back({});
    tree.depth_first_node = {0, 1};
    for (uint32_t d = 0; d < depth_count; ++d) {
      uint32_t first = tree.depth_first_node[d], last = tree.depth_first_node[d + 1];
      for (uint32_t n = first; n < last; ++n) {
        if (levels[d].bricks.count(pack(coords[n]))) {
          tree.nodes[n].brick = uint32_t(jobs.size());
          jobs.push_back({d, coords[n]});
        }
        if (d + 1 == depth_count || tree.nodes[n].brick == octree::kNone) continue;
        bool any = false;
        for (int i = 0; i < 8; ++i) {
          any = any || levels[d + 1].bricks.count(pack(coords[n] * 2 + glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
        }
        if (!any) continue;
        tree.nodes[n].children = uint32_t(tree.nodes.size());
        for (int i = 0; i < 8; ++i) {
          tree.nodes.push_back({});
          coords.push_back(coords[n] * 2 + glm::ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
        }
      }
      if (d + 1 < depth_count) tree.depth_first_node.push_back(uint32_t(tree.nodes.size()));
    }
    tree.brick_count = jobs.size();
    // Bricks on the domain's upper boundary come first: they carry shells (octree.h).
    std::vector<uint32_t> renumber(jobs.size());
    std::vector<BrickJob> ordered;
    ordered.reserve(jobs.size());
    for (int pass = 0; pass < 2; ++pass) {
      for (size_t j = 0; j < jobs.size(); ++j) {
        if (octree::on_upper_boundary(jobs[j].depth, jobs[j].coords) != (pass == 0)) continue;
        renumber[j] = uint32_t(ordered.size());
        ordered.push_back(jobs[j]);
      }
      if (pass == 0) tree.shell_count = ordered.size();
    }
    for (auto& node : tree.nodes) {
      if (node.brick != octree::kNone) node.brick = renumber[node.brick];
    }
    jobs = std::move(ordered);
  }

  void choose_channels() {
    // --- Channels: only what this surface needs.
    glm::dvec3 colour_sum(0);
    for (const auto& s : samples) colour_sum += glm::dvec3(s.colour);
    colour_mean = glm::vec3(colour_sum / double(samples.size()));
    bool colour_varies = false;
    for (const auto& s : samples) colour_varies = colour_varies || glm::length(s.colour - colour_mean) > 0.5f / 255.0f;
    // A channel is stored when it makes a visible difference somewhere: a
    // colour-height correlation of at least 4/255 in 1% of the filled voxels,
    // slopes anisotropic by a factor 2 (variances by 4) in 20% of the sloped ones.
    bool rough = false, bumpy = false;
    size_t filled = 0, correlated = 0, sloped = 0, anisotropic = 0;
    for (uint32_t d = 0; d < D; ++d) {
      for (const auto& v : levels[d].stats) {
        ++filled;
        if (std::max({std::abs(v.a_s.x), std::abs(v.a_s.y), std::abs(v.a_s.z)}) >= 4.0f / 255.0f) ++correlated;
        bumpy = bumpy || v.sigma_h > 1e-4f * float(levels[d].voxel);
        float trace = v.slope_cov.x + v.slope_cov.y;
        rough = rough || trace > 1e-6f;
        if (trace > 1e-3f) {
          ++sloped;
          float diff = v.slope_cov.x - v.slope_cov.y;
          float root = std::sqrt(diff * diff + 4 * v.slope_cov.z * v.slope_cov.z);
          float major = 0.5f * (trace + root), minor = 0.5f * (trace - root);
          if (major > 4.0f * std::max(minor, 0.0f)) ++anisotropic;
        }
      }
    }
    using octree::Channel;
    using octree::Encoding;
    tree.channels.push_back({Channel::Distance, Encoding::F32});
    tree.channels.push_back({Channel::Normal, Encoding::Oct24});
    // The renderer needs sigma_h to draw detail octaves (detail.glsl).
    if (bumpy || detail.octaves > 0) tree.channels.push_back({Channel::HeightDev, Encoding::U8LogRelative});
    if (rough) {
      if (sloped > 0 && anisotropic * 5 > sloped) {
        tree.channels.push_back({Channel::SlopeCov, Encoding::Cov3x8});
      } else {
        tree.channels.push_back({Channel::SlopeDev, Encoding::U8LogSlope});
      }
    }
    // Detail whose colour follows its height makes colour vary and correlate
    // with height wherever the detail is (its octaves below the lattice show
    // only in a_s).
    bool detail_colour = detail.octaves > 0 && glm::length(detail.colour_slope) > 0;
    if (colour_varies || detail_colour) tree.channels.push_back({Channel::Colour, Encoding::Srgb8});
    if ((colour_varies && correlated * 100 >= filled) || detail_colour) {
      tree.channels.push_back({Channel::ColourSlope, Encoding::Signed8});
    }
    // Materials: the source's table; which one each voxel shows only when
    // there is a choice.
    tree.materials = source.materials();
    if (tree.materials.size() > octree::kMaxMaterials) {
      throw std::invalid_argument("the scene has " + std::to_string(tree.materials.size()) + " materials (at most " +
                                  std::to_string(octree::kMaxMaterials) + ")");
    }
    if (tree.materials.size() > 1) tree.channels.push_back({Channel::Material, Encoding::MaterialShare8});
    if (source.shading_normals()) tree.channels.push_back({Channel::ShadingNormal, Encoding::Oct24});
    tree.constant_colour = colour_mean;
    for (const auto& c : tree.channels) {
      tree.brick_data.emplace_back(size_t(tree.pool_samples()) * octree::encoding_bytes(c.encoding));
    }
  }

  void fill_bricks() {
    // --- Bricks: the B^3 lattice points each stored brick owns (its upper
    // faces belong to its neighbours, octree.h), and for bricks on the
    // domain's upper boundary the shell of their (B + 1)^3 block.
    progress("bricks", 0.55);
    const int S = int(B) + 1;  // the finest level evaluates the closed block (band neighbours across upper faces)
    auto pool_sample = [&](size_t j, int x, int y, int z) {
      return x < int(B) && y < int(B) && z < int(B) ? tree.brick_sample(j, uint32_t((z * int(B) + y) * int(B) + x))
                                                    : tree.shell_sample(j, {x, y, z});
    };
    std::atomic<size_t> done{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, jobs.size(), 8), [&](const tbb::blocked_range<size_t>& r) {
      auto& points = scratch.local();
      std::vector<FinePoint> one;
      for (size_t j = r.begin(); j != r.end(); ++j) {
        const BrickJob& job = jobs[j];
        const Level& level = levels[job.depth];
        const glm::ivec3 base = job.coords * int(B);
        const int E = j < tree.shell_count ? S : int(B);  // lattice points written per axis
        if (job.depth == D) {
          // Finest: exact values in the band. Points beyond it take the
          // attributes of band neighbours inside the brick: a cone element that
          // far from the surface covers nothing, so they never reach a pixel.
          source.evaluate(base, base + int(B), points);
          auto at = [&](int x, int y, int z) -> const FinePoint& { return points[size_t((z * S + y) * S + x)]; };
          for (int z = 0; z < E; ++z)
            for (int y = 0; y < E; ++y)
              for (int x = 0; x < E; ++x) {
                const FinePoint& p = at(x, y, z);
                octree::Voxel v;
                v.hbar = p.distance;
                v.abar = colour_mean;
                if (p.near) {
                  v.nbar = p.normal;
                  v.n_shading = p.shading_normal;
                  v.abar = p.colour;
                  v.material = p.material;
                } else {
                  glm::vec3 n(0), a(0);
                  int count = 0;
                  for (int k = 0; k < 27; ++k) {
                    int qx = x + k % 3 - 1, qy = y + (k / 3) % 3 - 1, qz = z + k / 9 - 1;
                    if (qx < 0 || qy < 0 || qz < 0 || qx >= S || qy >= S || qz >= S) continue;
                    const FinePoint& q = at(qx, qy, qz);
                    if (q.near) n += q.normal, a += q.colour, v.material = q.material, ++count;
                  }
                  if (count) v.nbar = glm::normalize(n + glm::vec3(0, 0, 1e-12f)), v.abar = a / float(count);
                }
                fold_detail(v);
                octree::encode_pool_voxel(tree, pool_sample(j, x, y, z), job.depth, v);
              }
        } else {
          const float floor_distance = float(0.5 * level.voxel) - h;
          // Filled-statistics index of every lattice point of the brick and a
          // one-point apron around it: one hash lookup each, then array reads.
          const int A = E + 2;
          auto& filled = filled_scratch.local();
          filled.assign(size_t(A * A * A), -1);
          for (int z = 0; z < A; ++z)
            for (int y = 0; y < A; ++y)
              for (int x = 0; x < A; ++x) {
                glm::ivec3 q = base + glm::ivec3(x - 1, y - 1, z - 1);
                if (glm::any(glm::lessThan(q, glm::ivec3(0))) ||
                    glm::any(glm::greaterThan(q, glm::ivec3(int(level.cells))))) {
                  continue;
                }
                auto it = level.filled.find(pack(q));
                if (it != level.filled.end()) filled[size_t((z * A + y) * A + x)] = int32_t(it->second);
              }
          auto filled_at = [&](int x, int y, int z) { return filled[size_t(((z + 1) * A + y + 1) * A + x + 1)]; };
          for (int z = 0; z < E; ++z)
            for (int y = 0; y < E; ++y)
              for (int x = 0; x < E; ++x) {
                glm::ivec3 p = base + glm::ivec3(x, y, z);
                octree::Voxel v;
                int32_t self = filled_at(x, y, z);
                bool sheet = false;
                float offset = 0;
                if (self >= 0) {
                  v = level.stats[size_t(self)];
                  sheet = level.sheet[size_t(self)];
                  offset = level.offset[size_t(self)];
                } else {
                  // No surface in the footprint: attributes from filled neighbours,
                  // the distance from their planes, never below the footprint's half size.
                  octree::Voxel sum;
                  sum.nbar = glm::vec3(0);
                  sum.abar = glm::vec3(0);
                  float hsum = 0;
                  int count = 0, sheets = 0;
                  float offsets = 0;
                  for (int k = 0; k < 27; ++k) {
                    glm::ivec3 o(k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1);
                    int32_t nb = k == 13 ? -1 : filled_at(x + o.x, y + o.y, z + o.z);
                    if (nb < 0) continue;
                    const octree::Voxel& u = level.stats[size_t(nb)];
                    hsum += u.hbar - float(double(glm::dot(u.nbar, glm::vec3(o))) * level.voxel);
                    sum.nbar += u.nbar;
                    sum.sigma_h += u.sigma_h;
                    sum.slope_cov += u.slope_cov;
                    sum.abar += u.abar;
                    sum.a_s += u.a_s;
                    v.material = u.material;
                    sheets += level.sheet[size_t(nb)];
                    offsets += level.sheet[size_t(nb)] ? level.offset[size_t(nb)] : 0.0f;
                    ++count;
                  }
                  if (count) {
                    float inv = 1.0f / float(count);
                    v.nbar = glm::normalize(sum.nbar + glm::vec3(0, 0, 1e-12f));
                    v.sigma_h = sum.sigma_h * inv;
                    v.slope_cov = sum.slope_cov * inv;
                    v.abar = sum.abar * inv;
                    v.a_s = sum.a_s * inv;
                    float e = hsum * inv;
                    v.hbar = std::abs(e) >= floor_distance ? e : (e < 0 ? -floor_distance : floor_distance);
                    if (2 * sheets > count) {
                      // The neighbours' planes, extrapolated, say where the
                      // sheet is; drawn two-sided, no footprint without
                      // surface is nearer than floor_distance. A centred
                      // shell is outside there (it would swell by as much);
                      // one inside a volume keeps its inside, where its
                      // outer face is the volume's.
                      const float offset = offsets / float(sheets);
                      v = two_sided(v, float(level.voxel), offset);
                      if (offset < 0.5f || v.hbar >= 0) v.hbar = std::max(v.hbar, floor_distance);
                      else v.hbar = std::min(v.hbar, -floor_distance);
                    }
                  } else {
                    // Nothing in the 27 footprints around: at least 1.5 voxels away.
                    glm::ivec3 fine = p * int(N / level.cells);
                    source.evaluate(fine, fine, one);
                    float far = float(1.5 * level.voxel) - h;
                    v.hbar = one[0].distance < 0 ? -far : far;
                    v.abar = colour_mean;
                    // The plane of the nearest coarser filled point, carried to p:
                    // trilinear interpolation mixes this point with filled
                    // ones, and an arbitrary normal there would tilt their
                    // planes (phantom coverage beside silhouettes).
                    glm::dvec3 at = glm::dvec3(p) * level.voxel;
                    for (uint32_t up = job.depth; up-- > 0;) {
                      const Level& coarse = levels[up];
                      glm::ivec3 q = glm::ivec3(glm::round(at / coarse.voxel));
                      auto it = coarse.filled.find(pack(q));
                      if (it == coarse.filled.end()) continue;
                      const octree::Voxel& u = coarse.stats[it->second];
                      float e = u.hbar + float(glm::dot(glm::dvec3(u.nbar), at - glm::dvec3(q) * coarse.voxel));
                      glm::vec3 n = u.nbar;
                      if (coarse.sheet[it->second]) {  // the coarser sheet's shell, from this point's side
                        const float half = 0.5f * kShellVoxels * float(coarse.voxel);
                        e += coarse.offset[it->second] * half;
                        if (e < 0) e = -e, n = -n;
                        e -= half;
                      }
                      v.nbar = n;
                      v.abar = u.abar;
                      v.material = u.material;
                      if ((e < 0) == (v.hbar < 0) && std::abs(e) > far) v.hbar = e;
                      break;
                    }
                  }
                }
                if (sheet) v = two_sided(v, float(level.voxel), offset);
                octree::encode_pool_voxel(tree, pool_sample(j, x, y, z), job.depth, v);
              }
        }
        size_t n = ++done;
        if (n % 256 == 0) progress("bricks", 0.55 + 0.45 * double(n) / double(jobs.size()), n, jobs.size());
      }
    });
  }
};

}  // namespace

octree::Octree voxelize(SurfaceSource& source, const VoxelizeOptions& options, VoxelizeReport* report) {
  const uint32_t B = options.brick_size;
  const uint32_t N = options.resolution;
  if (!power_of_two(B) || B < 2 || B > 32) {
    throw std::invalid_argument("brick size " + std::to_string(B) + " is not a power of two in [2, 32]");
  }
  if (!power_of_two(N) || N < 16 || N < B || N > 65536) {
    throw std::invalid_argument("resolution " + std::to_string(N) +
                                " is not a power of two in [16, 65536] (and >= brick size)");
  }
  VoxelizeReport local_report;
  Builder build(source, options, report ? *report : local_report);
  build.prepare();
  build.collect_samples();
  build.coarse_statistics();
  build.build_topology();
  build.choose_channels();
  build.fill_bricks();
  build.progress("done", 1.0);
  VoxelizeReport& rep = build.rep;
  rep.seconds_total = build.clock.seconds();
  rep.seconds_bricks = rep.seconds_total - rep.seconds_source - rep.seconds_samples - rep.seconds_statistics;
  return std::move(build.tree);
}

}  // namespace svo::voxelizer
