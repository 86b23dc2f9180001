// OpenVDB level sets in (a surface source) and out (an octree's finest
// level). One of the two translation units that include OpenVDB.
#include <dlfcn.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/SignedFloodFill.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <mutex>
#include <sstream>
#include <tuple>

#include "mesh_screen.h"
#include "svo/octree/files.h"
#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/vdb.h"
#include "vdb_bricks.h"

namespace svo::voxelizer {

namespace {

void initialize_openvdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

std::string one_line(std::string why) {
  if (auto nl = why.find('\n'); nl != std::string::npos) why.resize(nl);
  return why;
}

// "name (float level set)" and the like, for messages.
std::string describe(const openvdb::GridBase& g) {
  std::string cls = g.getGridClass() == openvdb::GRID_LEVEL_SET    ? "level set"
                    : g.getGridClass() == openvdb::GRID_FOG_VOLUME ? "fog volume"
                    : g.getGridClass() == openvdb::GRID_STAGGERED  ? "staggered"
                                                                   : "unknown class";
  return "\"" + g.getName() + "\" (" + g.valueType() + " " + cls + ")";
}

// The parts of a .vdb file OpenVDB 10 trusts before it reads a grid's
// tree, checked against the file's size: the header, the file's metadata,
// the grid descriptors (names, positions), each grid's metadata (sizes,
// fixed-size values, delayed-load tables) and transform, and the root of
// each float tree. OpenVDB allocates and zeroes a metadata value of the
// size the file states (a 9 KB file asking for gigabytes timed out the vdb
// fuzz target), reads fixed-size values by their type whatever size the
// file states, and reads a root tile's "active" byte straight into a bool
// (undefined for any byte but 0 and 1). The tree's buffers are guarded at
// the end of this file. Returns "" or the problem. Files older than format
// 222 (OpenVDB 3) are refused.
std::string screen_vdb(const std::string& path, uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  uint64_t at = 0;
  auto read = [&](void* out, uint64_t n) {
    if (n > size - std::min(at, size)) return false;
    in.seekg(std::streamoff(at));
    in.read(static_cast<char*>(out), std::streamsize(n));
    at += n;
    return bool(in);
  };
  auto u32 = [&](uint32_t& v) { return read(&v, 4); };
  auto skip = [&](uint64_t n, uint64_t end) {
    if (n > end - std::min(at, end)) return false;
    at += n;
    return true;
  };
  auto string = [&](uint64_t end) {
    uint32_t n = 0;
    return u32(n) && skip(n, end);
  };
  // A string's text where it is short (type names); longer ones skipped.
  auto text = [&](uint64_t end, std::string& out) {
    uint32_t n = 0;
    out.clear();
    if (!u32(n)) return false;
    if (n > 64) return skip(n, end);
    out.resize(n);
    return n <= end - std::min(at, end) && read(out.data(), n);
  };
  // A transform: its map's type name and data (math/Maps.h: Vec3d 24
  // bytes, Mat4d 128; a frustum holds a box, taper, depth and a second map).
  auto transform = [&](uint64_t end, const std::string& what) -> std::string {
    for (int depth = 0; depth < 2; ++depth) {
      std::string type;
      if (!text(end, type)) return what + " transform truncated";
      static const std::pair<const char*, uint64_t> kMaps[] = {
          {"AffineMap", 128},          {"UnitaryMap", 128},           {"ScaleMap", 5 * 24},
          {"UniformScaleMap", 5 * 24}, {"ScaleTranslateMap", 6 * 24}, {"UniformScaleTranslateMap", 6 * 24},
          {"TranslationMap", 24}};
      for (const auto& [name, bytes] : kMaps) {
        if (type == name) return skip(bytes, end) ? "" : what + " transform truncated";
      }
      if (type != "NonlinearFrustumMap" || depth > 0) return what + " transform has an unknown map \"" + type + "\"";
      if (!skip(2 * 24 + 2 * 8, end)) return what + " transform truncated";
    }
    return "";
  };
  // A delayed-load value (io::DelayedLoadMetadata::readValue): a count of
  // leaf nodes, then a mask of one byte per leaf and their compressed sizes
  // (8 bytes each; absent when the size field is 0xffffffff), each either
  // raw (size field 0) or a Blosc buffer of the stated size. OpenVDB
  // allocates the count and what the Blosc header states before it reads:
  // the count must fit the file (a leaf takes at least its 64-byte value
  // mask), each Blosc header must state the array's size, and the whole must
  // fit the value's stated size (OpenVDB reads on past it otherwise).
  auto delayed_load = [&](uint64_t value, uint32_t bytes) -> std::string {
    const uint64_t end = value + bytes;
    uint32_t leaves = 0;
    if (!read(&leaves, 4)) return "truncated";
    if (leaves > size / 64) {
      return "claims " + std::to_string(leaves) + " leaf nodes, more than a file of " + std::to_string(size) +
             " bytes holds";
    }
    for (const uint64_t element : {uint64_t(1), uint64_t(8)}) {
      uint32_t stored = 0;
      if (!u32(stored) || at > end) return "truncated";
      if (element == 8 && stored == 0xffffffffu) break;
      const uint64_t raw = leaves * element;
      if (stored == 0) {
        if (!skip(raw, end)) return "runs past its stated size";
        continue;
      }
      // Blosc's header: version, versionlz, flags, typesize, then the
      // uncompressed size, the block size and the compressed size (u32 each).
      std::array<uint32_t, 4> header{};
      if (stored < 16 || stored > end - std::min(at, end) || !read(header.data(), 16)) {
        return "runs past its stated size";
      }
      // OpenVDB pads an array of fewer than 128 bytes to 128 before Blosc
      // (io/Compression's BLOSC_PAD_BYTES) and accepts 128 back for it.
      const bool padded = header[1] == 128u && raw <= 128u;
      if ((header[1] != raw && !padded) || header[3] != stored) {
        return "states a compressed array of " + std::to_string(header[1]) + " bytes for " + std::to_string(leaves) +
               " leaf nodes";
      }
      at += stored - 16;
    }
    return at <= end ? "" : "runs past its stated size";
  };
  // A MetaMap: count, then name, type name and a sized value each. OpenVDB
  // reads a value of a fixed-size type (TypedMetadata<T>::readValue) by its
  // type's size whatever size the file states, so the two must agree.
  auto metadata = [&](uint64_t end, const std::string& what) -> std::string {
    static const std::pair<const char*, uint32_t> kFixed[] = {
        {"bool", 1},   {"float", 4},  {"double", 8}, {"int32", 4},  {"int64", 8},  {"vec2i", 8},
        {"vec2s", 8},  {"vec2d", 16}, {"vec3i", 12}, {"vec3s", 12}, {"vec3d", 24}, {"vec4i", 16},
        {"vec4s", 16}, {"vec4d", 32}, {"mat4s", 64}, {"mat4d", 128}};
    uint32_t count = 0;
    if (!u32(count)) return what + " metadata truncated";
    for (uint32_t i = 0; i < count; ++i) {
      const std::string entry = what + " metadata entry " + std::to_string(i);
      uint32_t bytes = 0;
      std::string type;
      if (!string(end) || !text(end, type) || !u32(bytes) || bytes > end - std::min(at, end)) {
        return entry + " runs past its end";
      }
      for (const auto& [name, fixed] : kFixed) {
        if (type == name && bytes != fixed) {
          return entry + " (" + type + ") states " + std::to_string(bytes) + " bytes, not " + std::to_string(fixed);
        }
      }
      const uint64_t value = at;
      if (type == "__delayedload" && bytes > 0) {
        if (std::string why = delayed_load(value, bytes); !why.empty()) return entry + " (delayed-load) " + why;
      }
      at = value + bytes;
    }
    return "";
  };
  char magic[8];
  uint32_t version = 0, major = 0, minor = 0;
  char offsets = 0;
  char uuid[36];
  if (!read(magic, 8) || std::memcmp(magic,
                                     "\x20"
                                     "BDV\0\0\0\0",
                                     8) != 0)
    return "not a .vdb file (no VDB magic number)";
  if (!u32(version) || !u32(major) || !u32(minor) || !read(&offsets, 1) || !read(uuid, 36))
    return "VDB header truncated";
  if (version < 222) return "VDB file format " + std::to_string(version) + " predates OpenVDB 3 and is not read";
  if (std::string why = metadata(size, "the file's"); !why.empty()) return why;
  uint32_t grids = 0;
  if (!u32(grids)) return "VDB grid count truncated";
  struct Grid {
    std::array<int64_t, 3> p{};  // grid, block (buffers) and end positions
    bool float_tree = false;     // its topology is read here
  };
  std::vector<Grid> grid_list;
  for (uint32_t g = 0; g < grids; ++g) {
    Grid grid;
    std::string type, parent;
    if (!string(size) || !text(size, type) || !text(size, parent) || !read(grid.p.data(), 24)) {
      return "VDB grid descriptor " + std::to_string(g) + " runs past the end of the file";
    }
    const std::array<int64_t, 3>& p = grid.p;
    if (p[0] < 0 || p[0] > p[1] || p[1] > p[2] || uint64_t(p[2]) > size) {
      return "VDB grid " + std::to_string(g) + " lies outside the file (positions " + std::to_string(p[0]) + ", " +
             std::to_string(p[1]) + ", " + std::to_string(p[2]) + " in " + std::to_string(size) + " bytes)";
    }
    // An instance shares its parent's tree and reads no topology.
    grid.float_tree = parent.empty() && (type == "Tree_float_5_4_3" || type == "Tree_float_5_4_3_HalfFloat");
    grid_list.push_back(grid);
  }
  for (size_t g = 0; g < grid_list.size(); ++g) {
    const std::string what = "grid " + std::to_string(g) + "'s";
    const uint64_t end = uint64_t(grid_list[g].p[1]);
    at = uint64_t(grid_list[g].p[0]);
    uint32_t compression = 0;
    if (!u32(compression)) return "VDB grid " + std::to_string(g) + " truncated";
    if (std::string why = metadata(end, what); !why.empty()) return why;
    if (std::string why = transform(end, what); !why.empty()) return "VDB " + why;
    if (!grid_list[g].float_tree) continue;
    // Tree::readTopology and RootNode::readTopology: buffer count,
    // background, tile and child counts, then each tile's origin, value
    // and active byte.
    int32_t buffers = 0;
    float background = 0;
    uint32_t tiles = 0, children = 0;
    if (!read(&buffers, 4) || !read(&background, 4) || !u32(tiles) || !u32(children) ||
        uint64_t(tiles) * 17 > end - std::min(at, end)) {
      return "VDB " + what + " tree runs past its end";
    }
    for (uint32_t t = 0; t < tiles; ++t) {
      std::array<char, 17> tile;
      read(tile.data(), tile.size());
      if (tile[16] != 0 && tile[16] != 1) {
        return "VDB " + what + " root tile " + std::to_string(t) + " has active flag " +
               std::to_string(int(uint8_t(tile[16]))) + " (0 or 1 expected)";
      }
    }
  }
  return "";
}

class VdbSource : public SurfaceSource {
 public:
  VdbSource(openvdb::FloatGrid::Ptr grid, const VdbOptions& options, const std::string& path)
      : input_(std::move(grid)), path_(path) {
    colour_ = options.colour.value_or(glm::vec3(0.8f));
    sigma_rho2_ = options.sigma_rho >= 0 ? options.sigma_rho * options.sigma_rho : 0.01f;
    const double h = input_->voxelSize()[0];
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    double crossing = 0;
    for (auto v = input_->tree().cbeginValueOn(); v; ++v) {
      if (!std::isfinite(*v)) {
        throw std::runtime_error(path + ": grid \"" + input_->getName() + "\" holds a non-finite distance");
      }
      if (std::abs(*v) >= h) continue;
      const openvdb::CoordBBox box = v.getBoundingBox();
      for (const openvdb::Coord& c : {box.min(), box.max()}) {
        const openvdb::Vec3d w = input_->indexToWorld(c);
        lo = glm::min(lo, glm::dvec3(w.x(), w.y(), w.z()));
        hi = glm::max(hi, glm::dvec3(w.x(), w.y(), w.z()));
      }
      crossing += double(box.volume());
    }
    if (!(crossing > 0)) {
      throw std::runtime_error(path + ": grid \"" + input_->getName() +
                               "\" has no zero crossing (no active voxel within one voxel of the surface)");
    }
    // Rotated transforms: the corners' box bounds the rotated voxels.
    lo -= glm::dvec3(h), hi += glm::dvec3(h);
    for (int k = 0; k < 3; ++k) {
      if (!(std::abs(lo[k]) <= kMaxCoordinate && std::abs(hi[k]) <= kMaxCoordinate)) {
        throw std::runtime_error(path + ": grid \"" + input_->getName() + "\" reaches beyond +-1e15 scene units");
      }
    }
    bounds_ = {glm::vec3(lo), glm::vec3(hi)};
    area_ = crossing * h * h;  // voxels within one voxel: about twice the area
  }

  Box bounds() const override { return bounds_; }
  float sigma_rho2() const override { return sigma_rho2_; }
  double surface_area() const override { return area_; }
  double bytes_per_sample() const override { return 6 * 4 * 1.5; }

  void prepare(const Lattice& lattice) override {
    lattice_ = lattice;
    try {
      auto transform = openvdb::math::Transform::createLinearTransform(lattice.voxel);
      transform->postTranslate(openvdb::Vec3d(lattice.origin.x, lattice.origin.y, lattice.origin.z));
      distance_ = openvdb::FloatGrid::create(float(kBandVoxels * lattice.voxel));
      distance_->setTransform(transform);
      distance_->setGridClass(openvdb::GRID_LEVEL_SET);
      // A level set is rebuilt with the output's band (OpenVDB's
      // levelSetRebuild); the same transform copies the grid as it is.
      openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*input_, *distance_);
    } catch (const openvdb::Exception& e) {
      throw std::runtime_error(path_ + ": resampling to the lattice: " + one_line(e.what()));
    }
    input_.reset();
  }

  std::vector<glm::ivec3> candidate_bricks(uint32_t brick_size) const override {
    // Within half a voxel of the surface.
    return bricks_near_surface(*distance_, 0.5f * float(lattice_.voxel), int(brick_size),
                               int(lattice_.resolution / brick_size));
  }

  using SurfaceSource::evaluate;
  void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const override {
    out.clear();
    // Unregistered accessors (the grid is not modified meanwhile): a
    // registered one goes through TBB's concurrent_hash_map, whose iterator
    // UBSan reports as a misaligned downcast (TBB 2021.8).
    openvdb::tree::ValueAccessor<const openvdb::FloatTree, false> acc(distance_->tree());
    const float band = std::min(kBandVoxels * float(lattice_.voxel), near_within);
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          const openvdb::Coord ijk(x, y, z);
          FinePoint point;
          const float d = acc.getValue(ijk);
          if (std::abs(d) < band && acc.isValueOn(ijk)) {
            // The normal: the distance's gradient (central differences).
            auto at = [&](int dx, int dy, int dz) { return double(acc.getValue(ijk.offsetBy(dx, dy, dz))); };
            glm::dvec3 g(at(1, 0, 0) - at(-1, 0, 0), at(0, 1, 0) - at(0, -1, 0), at(0, 0, 1) - at(0, 0, -1));
            const double length = glm::length(g);
            const glm::dvec3 n = length > 0 && std::isfinite(length) ? g / length : glm::dvec3(0, 0, 1);
            const glm::dvec3 p = lattice_.position({x, y, z});
            point.near = true;
            point.distance = d;
            point.normal = glm::vec3(n);
            point.closest = glm::vec3(p - double(d) * n);
            point.colour = colour_;
          } else {
            // Outside the band: at least the band's width, on the grid's side.
            point.distance = std::copysign(std::max(std::abs(d), band), d);
          }
          out.push_back(point);
        }
  }

 private:
  openvdb::FloatGrid::Ptr input_;
  std::string path_;
  glm::vec3 colour_{0.8f};
  float sigma_rho2_ = 0.01f;
  Box bounds_;
  double area_ = 0;
  Lattice lattice_;
  openvdb::FloatGrid::Ptr distance_;
};

}  // namespace

bool is_vdb_path(const std::string& path) { return screen::lower_extension(path) == ".vdb"; }

std::unique_ptr<SurfaceSource> load_vdb(const std::string& path, const VdbOptions& options) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(path + ": " + one_line(why)); };
  uint64_t file_size = 0;
  try {
    file_size = files::require_regular_file(path, "an OpenVDB file");
  } catch (const files::FileError& e) {
    throw std::runtime_error(e.what());
  }
  if (std::string why = screen_vdb(path, file_size); !why.empty()) fail(why);
  initialize_openvdb();
  openvdb::GridBase::Ptr base;
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    openvdb::GridPtrVecPtr grids = file.readAllGridMetadata();
    std::string names;
    for (const auto& g : *grids) names += (names.empty() ? "" : ", ") + describe(*g);
    openvdb::GridBase::Ptr chosen;
    if (!options.grid.empty()) {
      for (const auto& g : *grids)
        if (g->getName() == options.grid) chosen = g;
      if (!chosen)
        fail("no grid named \"" + options.grid + "\" (the file holds " + (names.empty() ? "none" : names) + ")");
    } else {
      int level_sets = 0;
      for (const auto& g : *grids) {
        if (g->isType<openvdb::FloatGrid>() && g->getGridClass() == openvdb::GRID_LEVEL_SET) chosen = g, ++level_sets;
      }
      if (level_sets == 0) fail("no float level set among its grids (" + (names.empty() ? "none" : names) + ")");
      if (level_sets > 1) fail("several float level sets (" + names + "): name one with --grid NAME");
    }
    if (!chosen->isType<openvdb::FloatGrid>()) {
      fail("grid " + describe(*chosen) + " is not a float grid: a float level set is expected");
    }
    if (chosen->getGridClass() != openvdb::GRID_LEVEL_SET) {
      fail("grid " + describe(*chosen) +
           " is not a level set: a signed distance field (class level set) is expected, e.g. from "
           "vdb_tool's mesh2ls or openvdb::tools::fogToSdf");
    }
    // Sizes from the metadata, before the tree is read.
    if (auto count = chosen->getMetadata<openvdb::Int64Metadata>("file_voxel_count")) {
      if (double(count->value()) > kMaxVdbVoxels) {
        fail("grid " + describe(*chosen) + " has " + std::to_string(count->value()) +
             " active voxels, more than the limit of 1e9");
      }
    }
    base = file.readGrid(chosen->getName());
    file.close();
  } catch (const openvdb::Exception& e) {
    fail(std::string("not an OpenVDB file it can read: ") + e.what());
  } catch (const std::ios_base::failure& e) {
    fail(std::string("read error: ") + e.what());
  } catch (const std::bad_alloc&) {
    fail("OpenVDB ran out of memory reading it (a corrupt file?)");
  } catch (const std::runtime_error&) {
    throw;  // ours, one line already
  } catch (const std::exception& e) {
    fail(std::string("not an OpenVDB file it can read: ") + e.what());
  }
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid) fail("the grid read is not a float grid");
  const openvdb::math::Transform& t = grid->transform();
  const openvdb::Vec3d size = grid->voxelSize();
  if (!t.isLinear() || !t.hasUniformScale() || !(size[0] > 0) || !std::isfinite(size[0])) {
    fail("grid " + describe(*grid) + " has a transform that is not linear with a uniform voxel size");
  }
  if (double(grid->activeVoxelCount()) > kMaxVdbVoxels) {
    fail("grid " + describe(*grid) + " has " + std::to_string(grid->activeVoxelCount()) +
         " active voxels, more than the limit of 1e9");
  }
  const float background = grid->background();
  if (!(background > 0) || !std::isfinite(background)) {
    fail("grid " + describe(*grid) + " has background " + std::to_string(background) + ", not a positive band width");
  }
  for (auto v = grid->tree().cbeginValueAll(); v; ++v) {
    if (!std::isfinite(*v)) fail("grid " + describe(*grid) + " holds a non-finite value");
  }
  return std::make_unique<VdbSource>(grid, options, path);
}

VdbExport export_vdb(const octree::Octree& tree, const std::string& path, const std::string& grid_name) {
  auto fail = [&](const std::string& why) { throw std::runtime_error(path + ": " + one_line(why)); };
  if (tree.channel_index(octree::Channel::Distance) < 0) fail("the octree stores no distance channel");
  initialize_openvdb();
  const uint32_t finest = tree.depth_count - 1;
  const double h = double(tree.size) / double(tree.finest_resolution());
  const float background = float(kBandVoxels * h);
  VdbExport report;
  report.voxel_size = h;
  report.background = background;
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  try {
    auto transform = openvdb::math::Transform::createLinearTransform(h);
    transform->postTranslate(openvdb::Vec3d(tree.origin.x, tree.origin.y, tree.origin.z));
    grid->setTransform(transform);
  } catch (const openvdb::Exception& e) {
    fail(std::string("voxel size ") + std::to_string(h) + ": " + e.what());
  }
  grid->setName(grid_name);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  grid->insertMeta("creator", openvdb::StringMetadata("svo export"));
  openvdb::tree::ValueAccessor<openvdb::FloatTree, false> acc(grid->tree());  // unregistered: see evaluate()
  const int B = int(tree.brick_size);
  // Depth-first over the nodes with their coordinates; the finest level's
  // bricks give their B^3 lattice points.
  struct Item {
    uint32_t node, depth;
    glm::ivec3 c;
  };
  std::vector<Item> stack{{0, 0, glm::ivec3(0)}};
  while (!stack.empty()) {
    const Item it = stack.back();
    stack.pop_back();
    const octree::Node& node = tree.nodes[it.node];
    if (it.depth == finest) {
      if (node.brick == octree::kNone) continue;
      for (int z = 0; z < B; ++z)
        for (int y = 0; y < B; ++y)
          for (int x = 0; x < B; ++x) {
            const uint32_t i = uint32_t(x + B * (y + B * z));
            const float d = octree::decode_voxel(tree, node.brick, i, finest).hbar;
            if (!(std::abs(d) < background)) continue;
            const glm::ivec3 p = it.c * B + glm::ivec3(x, y, z);
            acc.setValue(openvdb::Coord(p.x, p.y, p.z), d);
            ++report.active_voxels;
          }
      continue;
    }
    if (node.children == octree::kNone) continue;
    for (uint32_t k = 0; k < 8; ++k) {
      stack.push_back({node.children + k, it.depth + 1, 2 * it.c + glm::ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1)});
    }
  }
  // Inactive voxels and tiles take the outside or inside background from
  // their active neighbours, as OpenVDB's level sets do.
  openvdb::tools::signedFloodFill(grid->tree());
  openvdb::tools::pruneLevelSet(grid->tree());
  // openvdb::io::File writes by name: into the OutputFile's temporary, then
  // committed (fsync, rename) so that a reader never sees a partial file.
  files::OutputFile out(path);
  try {
    openvdb::io::File file(out.temporary());
    file.write({grid});
    file.close();
  } catch (const openvdb::Exception& e) {
    fail(std::string("writing: ") + e.what());
  }
  out.commit();
  return report;
}

}  // namespace svo::voxelizer

// OpenVDB 10's io::bloscFromStream and io::unzipFromStream read a chunk that
// the file calls uncompressed (a negative size) into the caller's buffer
// before they compare its size with the buffer's: a hostile .vdb writes past
// the buffer (a heap-buffer-overflow the vdb fuzz target found in
// LeafNode::readBuffers). The definitions below interpose OpenVDB's (an
// executable's symbol wins over the shared library's, also for the calls
// from inside it): they compare the size first, then hand the stream to
// OpenVDB's own function. The library's symbol names are those of 10.0.
static_assert(OPENVDB_LIBRARY_MAJOR_VERSION_NUMBER == 10 && OPENVDB_LIBRARY_MINOR_VERSION_NUMBER == 0,
              "another OpenVDB: check whether io::bloscFromStream still reads before it checks the size, and "
              "update the mangled names below");
namespace {

using FromStream = void (*)(std::istream&, char*, size_t);

void checked_from_stream(const char* symbol, std::istream& is, char* data, size_t bytes) {
  static std::mutex mutex;
  static std::map<std::string, FromStream> originals;
  FromStream original = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex);
    FromStream& f = originals[symbol];
    if (!f) f = reinterpret_cast<FromStream>(dlsym(RTLD_NEXT, symbol));
    original = f;
  }
  if (!original) OPENVDB_THROW(openvdb::RuntimeError, "OpenVDB's " << symbol << " not found");
  if (data != nullptr) {
    // The chunk's size, then the stream back where it was.
    const std::streampos start = is.tellg();
    int64_t size = 0;
    if (start != std::streampos(-1) && is.read(reinterpret_cast<char*>(&size), 8)) {
      is.seekg(start);
      const uint64_t stated = uint64_t(0) - uint64_t(size);  // -size, also for INT64_MIN
      if (size <= 0 && stated != bytes) {
        OPENVDB_THROW(openvdb::RuntimeError,
                      "expected a " << bytes << "-byte uncompressed chunk, the file states " << stated << " bytes");
      }
    } else if (start != std::streampos(-1)) {
      is.clear();
      is.seekg(start);
    }
  }
  original(is, data, bytes);
}

}  // namespace

namespace openvdb {
OPENVDB_USE_VERSION_NAMESPACE
namespace OPENVDB_VERSION_NAME {
namespace io {

void bloscFromStream(std::istream& is, char* data, size_t bytes) {
  checked_from_stream("_ZN7openvdb5v10_02io15bloscFromStreamERSiPcm", is, data, bytes);
}

void unzipFromStream(std::istream& is, char* data, size_t bytes) {
  checked_from_stream("_ZN7openvdb5v10_02io15unzipFromStreamERSiPcm", is, data, bytes);
}

}  // namespace io
}  // namespace OPENVDB_VERSION_NAME
}  // namespace openvdb
