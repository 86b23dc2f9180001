// One of the two translation units that include OpenVDB (slow to compile; vdb_io.cpp is the other).
// The mesh itself is read by mesh_read.cpp.
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "svo/voxelizer/mesh.h"
#include "svo/voxelizer/winding.h"
#include "vdb_bricks.h"

namespace svo::voxelizer {

namespace {

// Closest point to p on triangle (a, b, c), with its barycentric coordinates
// (Ericson, Real-Time Collision Detection, 5.1.5).
glm::dvec3 closest_on_triangle(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3& bary) {
  glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return bary = {1, 0, 0}, a;
  glm::dvec3 bp = p - b;
  double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return bary = {0, 1, 0}, b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    double v = d1 / (d1 - d3);
    return bary = {1 - v, v, 0}, a + v * ab;
  }
  glm::dvec3 cp = p - c;
  double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return bary = {0, 0, 1}, c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    double w = d2 / (d2 - d6);
    return bary = {1 - w, 0, w}, a + w * ac;
  }
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return bary = {0, 1 - w, w}, b + w * (c - b);
  }
  double denom = 1 / (va + vb + vc);
  double v = vb * denom, w = vc * denom;
  bary = {1 - v - w, v, w};
  return a + ab * v + ac * w;
}

// The distance to a shell that ends at an open edge, in the plane across
// the edge: t is the signed distance past the edge in the sheet's plane, z
// the height above the triangle. The shell spans z in [-half - shift,
// half - shift] and ends in a wedge whose apex is the edge, t <= -k |z|
// (k = 0: a flat cap through the edge). Inside the shell, the distance to
// the nearest of its faces and the cap. Returns the distance's gradient
// (along t, along z) and the distance in `distance`.
glm::dvec2 shell_cap(double t, double z, double half, double shift, double k, float& distance) {
  const double hi = half - shift, lo = -half - shift;
  const glm::dvec2 q(t, z), upper(-k * hi, hi), lower(k * lo, lo);  // where the faces meet the cap
  glm::dvec2 nearest = upper;
  double d = std::numeric_limits<double>::infinity();
  auto consider = [&](glm::dvec2 c) {
    if (const double dc = glm::length(q - c); dc < d) d = dc, nearest = c;
  };
  auto segment = [&](glm::dvec2 to) {  // from the apex
    const double tt = glm::dot(to, to);
    consider(tt > 0 ? std::clamp(glm::dot(q, to) / tt, 0.0, 1.0) * to : to);
  };
  segment(upper);
  segment(lower);
  consider({std::min(t, upper.x), hi});  // the faces
  consider({std::min(t, lower.x), lo});
  const bool inside = z >= lo && z <= hi && t + k * std::abs(z) <= 0;
  distance = float(inside ? -d : d);
  if (d > 1e-9 * half) return (inside ? -1.0 : 1.0) * (q - nearest) / d;
  // On the boundary: a face's normal, the cap's, or at the apex, the edge's outward direction.
  if (z >= hi - 1e-9 * half && t <= upper.x) return {0, 1};
  if (z <= lo + 1e-9 * half && t <= lower.x) return {0, -1};
  if (std::abs(z) <= 1e-9 * half) return {1, 0};
  return glm::dvec2(1, z < 0 ? -k : k) / std::sqrt(1 + k * k);
}

glm::dvec3 closest_on_segment(glm::dvec3 p, glm::dvec3 a, glm::dvec3 b) {
  const glm::dvec3 ab = b - a;
  const double ll = glm::dot(ab, ab);
  return ll > 0 ? a + std::clamp(glm::dot(p - a, ab) / ll, 0.0, 1.0) * ab : a;
}

// Open edges are listed by the cells of a grid this many finest voxels wide:
// wider than the farthest a lattice point looks for one, the band
// (kBandVoxels) and half a shell (MeshSource::nearest_open_edge).
constexpr double kEdgeCellVoxels = kBandVoxels + kShellVoxels;
// The slope of a sheet's wedge at an open edge (shell_cap): its faces meet
// the edge at 45 degrees, so that the shell's width does not show beyond
// the edge from any view within 45 degrees of the sheet's normal (a flat
// cap, k = 0, showed half of it from every oblique view, up to a pixel at
// the far view). A shell inside a volume (|offset| = 1), whose outer face
// is on the triangle, ends in a flat cap. Over the 44 open libcgal-demo
// meshes at 128^3 (docs/RESULTS.md, "Open rims, round two"): k = 1 against
// k = 0, PSNR up on 30, down on 8; k = 2 up on 23, down on 10.
constexpr double kCapSlope = 1.0;

class MeshSource : public SurfaceSource {
 public:
  explicit MeshSource(TriangleMesh mesh) : mesh_(std::move(mesh)) {
    if (open_) find_open_sides(), find_neighbours(), find_shell_offsets();
  }

  Box bounds() const override { return mesh_.bounds; }
  float sigma_rho2() const override { return mesh_.sigma_rho2; }
  double surface_area() const override { return mesh_.area; }
  std::vector<std::string> materials() const override { return mesh_.materials; }
  std::string surface() const override { return mesh_.surface; }
  bool two_sided() const override { return mesh_.two_sided; }
  // Only a rim (an open edge that is no seam) gives points a shading normal.
  bool shading_normals() const override {
    return std::any_of(open_edges_.begin(), open_edges_.end(), [](const OpenEdge& e) { return !e.seam; });
  }
  // OpenVDB's narrow band each side, float distance + int32 polygon index, tree overhead.
  double bytes_per_sample() const override { return 2 * vdb_band_voxels() * (4 + 4) * 1.5; }

  void prepare(const Lattice& lattice) override {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    lattice_ = lattice;
    // The grids live in index space, their distances in voxels (scaled by
    // the voxel size where read): OpenVDB refuses a transform whose voxel
    // volume is below 3e-15 ("Non-zero scale values required"), which a
    // 1 mm mesh at 1024^3 would be.
    transform_ = openvdb::math::Transform::createLinearTransform(1.0);
    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh_.positions.size());
    for (const auto& p : mesh_.positions) {
      glm::dvec3 i = (p - lattice.origin) / lattice.voxel;
      points.emplace_back(float(i.x), float(i.y), float(i.z));
    }
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(mesh_.triangles.size());
    for (const auto& t : mesh_.triangles) tris.emplace_back(uint32_t(t.x), uint32_t(t.y), uint32_t(t.z));
    openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points, tris);
    index_ = openvdb::Int32Grid::create(-1);
    distance_ = openvdb::tools::meshToVolume<openvdb::FloatGrid>(adapter, *transform_, vdb_band_voxels(),
                                                                 vdb_band_voxels(), 0, index_.get());
    if (!open_ && (mesh_.open_edges || mesh_.nonmanifold_edges)) check_flood_fill();
    if (!open_) find_neighbours();
    if (open_) index_open_edges();
  }

  std::vector<glm::ivec3> candidate_bricks(uint32_t brick_size) const override {
    // Within half a voxel of the surface (the grid is in voxel units); of
    // an open surface, of its shell's outer faces, half the shell's width
    // beyond the triangles (build.cpp keeps the bricks those faces cross).
    const float within = open_ ? kShellFaceReach : 0.5f;
    return bricks_near_surface(*distance_, within, int(brick_size), int(lattice_.resolution / brick_size));
  }

  using SurfaceSource::evaluate;
  void evaluate(glm::ivec3 lo, glm::ivec3 hi, std::vector<FinePoint>& out, float near_within) const override {
    out.clear();
    auto dist = distance_->getConstAccessor();
    auto index = index_->getConstAccessor();
    const float band = std::min(kBandVoxels * float(lattice_.voxel), near_within);
    const float background = distance_->background();  // voxels: OpenVDB's band (vdb_band_voxels)
    // Of an open surface, the distance to the shell from the closest
    // triangle reaches as far as OpenVDB's band (beyond `band`, not near).
    const float reach = open_ ? std::min(background * float(lattice_.voxel), near_within) : band;
    const float voxel = float(lattice_.voxel);
    const double h = lattice_.voxel;
    for (int z = lo.z; z <= hi.z; ++z)
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          openvdb::Coord ijk(x, y, z);
          FinePoint point;
          const float voxels = dist.getValue(ijk);
          const float d = voxels * voxel;
          int32_t tri = index.getValue(ijk);
          glm::dvec3 p = lattice_.position({x, y, z});
          if (std::abs(d) < reach && tri >= 0 && size_t(tri) < mesh_.triangles.size()) {
            const glm::ivec3& t = mesh_.triangles[size_t(tri)];
            glm::dvec3 bary;
            const auto& v = mesh_.positions;
            glm::dvec3 c = closest_on_triangle(p, v[size_t(t.x)], v[size_t(t.y)], v[size_t(t.z)], bary);
            double exact = glm::length(p - c);
            point.near = exact < band;
            point.closest = glm::vec3(c);
            // The closest triangle's own normal (DESIGN section 6): interpolated
            // vertex normals would bend flat faces next to sharp edges.
            point.normal = mesh_.face_normals[size_t(tri)];
            point.colour = mesh_.colour(size_t(tri), bary);
            point.material = mesh_.face_material.empty() ? 0u : mesh_.face_material[size_t(tri)];
            if (open_) {
              // An open surface: a thin shell around each triangle, so that
              // both of its sides are drawn (as the reference's double-sided
              // triangles are) and no point needs an inside.
              // - Where the triangle bounds a volume (find_shell_offsets),
              //   the shell lies inside it, its outer face on the triangle;
              //   on a sheet it is centred on the triangle.
              // - Its normal is the face's, turned away from the shell's
              //   middle; where the closest point lies on an edge or a
              //   corner, the distance's gradient, which turns around the
              //   edge. The face's normal there flipped between neighbouring
              //   lattice points and notched the rim of the lion's open back.
              // - At an open edge the shell ends in a flat cap through the
              //   edge, across the sheet, instead of the half cylinder that
              //   |d| - half draws a half width beyond it: rims and the
              //   sheet's silhouettes stay where the reference draws them.
              //   Inside the shell too, the distance is the cap's where it
              //   is nearer than a face: with the faces' distance there
              //   (-half on the sheet) interpolation put the rim up to 0.385
              //   voxels beyond the edge. The cap's normal, the gradient,
              //   turns round the edge for the masks; shading reads the
              //   face's (FinePoint::shading_normal), as the reference
              //   shades a sheet up to its edge.
              const double offset = shell_offset_[size_t(tri)];
              const glm::dvec3 n = (offset < 0 ? -1.0 : 1.0) * glm::dvec3(point.normal);  // outward, where it bounds a volume
              const double half = 0.5 * kShellVoxels * h, shift = std::abs(offset) * half;
              const glm::dvec3 off = p - c;
              const double across = glm::dot(off, n);
              const bool on_edge = exact > 1e-3 * h && std::min({bary.x, bary.y, bary.z}) <= 0;
              // Which side of the triangle p lies on: on an edge or a corner,
              // by the features around it where they say (side_of), since
              // beside a sharp convex edge `across` can be negative outside.
              int side = across < 0 ? -1 : 1;
              if (on_edge && shift > 0) {
                if (const int s = side_of(p, c, size_t(tri), bary); s != 0) side = offset < 0 ? -s : s;
              }
              const double middle = double(side) * exact + shift;  // signed, from the shell's middle plane
              point.sheet = float(exact);
              point.sheet_normal = glm::vec3(n);
              point.sheet_offset = float(std::abs(offset));
              // Beyond the band too (not near), the distance to the shell:
              // a march that steps by the distance must not step through
              // the inner face of a shell inside a volume.
              point.distance = float(std::abs(middle) - half);
              const glm::dvec3 gradient = on_edge ? double(side) * off / exact : n;  // of the signed distance
              point.normal = glm::vec3(middle < 0 ? -gradient : gradient);
              // The rim: within reach of an open edge, the distance to the
              // shell ended by its cap through the edge (shell_cap), inside
              // the shell as well as beyond it.
              const bool beyond = on_edge && on_open_side(size_t(tri), bary);
              if (point.near && (!on_edge || beyond) && !open_edges_.empty()) {
                // t: the signed distance past the nearest open edge, in its
                // face's plane; positive where p's closest point lies on it.
                glm::dvec3 away(0), edge_outward(0);
                double gap = 0;
                const double d = nearest_open_edge(p, band + half, away, edge_outward, gap);
                const bool found = d >= 0 && (!beyond || gap < exact + 1e-3 * h);
                const double t = beyond ? d : -d;
                const glm::dvec3 outward = glm::dot(away, away) == 0 ? edge_outward : beyond ? away : -away;
                if (found) {
                  const double k = kCapSlope * (1 - std::abs(offset));
                  const glm::dvec2 g = shell_cap(t, across, half, shift, k, point.distance);
                  point.normal = glm::vec3(g.x * outward + g.y * n);
                  point.shading_normal = glm::vec3(across + shift < 0 ? -n : n);
                }
              }
            } else {
              // OpenVDB's sign (its flood fill) was wrong at 297 lattice points
              // beside fandisk's edges at 256^3, up to half a voxel outside.
              // Where the side of the closest feature disagrees with it, the
              // winding number decides (the feature alone would be wrong
              // inside one of two overlapping solids, near the other's faces).
              bool inside = d < 0;
              if (const int side = side_of(p, c, size_t(tri), bary); side != 0 && (side < 0) != inside) {
                inside = winding()(p) > 0.5;
              }
              point.distance = float(inside ? -exact : exact);
              if (!point.near) point.distance = inside ? -band : band;
              // Where the closest point lies on an edge or a corner, the
              // distance's gradient (DESIGN section 6) instead of a face's
              // normal: it turns continuously around a convex crease, where
              // the closest face's normal jumps between lattice points and
              // interpolation drew the jump as a staircase (the Chinese
              // dragon at 512^3, issue 20 item 2).
              const bool on_edge = std::min({bary.x, bary.y, bary.z}) <= 0;
              if (on_edge && exact > 1e-3 * h) point.normal = glm::vec3((p - c) / (inside ? -exact : exact));
            }
          } else {
            // A solid's distance beyond the band is the band's; a shell's
            // faces lie up to half + shift inside its triangles, so beyond
            // OpenVDB's wider band they are still kBandVoxels away.
            const float shell_depth = float(0.5 * kShellVoxels * h * (1.0 + max_shell_offset_));
            float magnitude = open_ ? std::max(std::abs(d), reach) - shell_depth
                                    : std::max(std::min(std::abs(d), kBandVoxels * voxel), band);
            const bool inside = !open_ && (voxels < 0 || (voxels == -background));
            point.distance = inside ? -magnitude : magnitude;
          }
          out.push_back(point);
        }
  }

 private:
  // A solid with holes the winding number calls small takes its inside from
  // OpenVDB's flood fill, which can still leak through them at a given
  // resolution: libcgal-demo's blob (97.5% closed) at 128^3 was a moire of
  // dots, its inside and outside swapped over whole regions. Checked
  // against the winding number at up to 2000 lattice points of the band
  // (1.5 voxels or more from the surface, where the side is clear); where
  // more than 5% disagree, the mesh is drawn two-sided instead.
  void check_flood_fill() {
    // Two passes over the band: how many points qualify, then every
    // stride-th of them (a list of them all would take 16 bytes a point).
    auto qualifies = [](float v) { return std::abs(v) >= 1.5f && std::abs(v) < 0.9f * float(kBandVoxels); };
    size_t count = 0;
    for (auto v = distance_->cbeginValueOn(); v; ++v) count += qualifies(*v);
    if (count == 0) return;
    const size_t stride = std::max<size_t>(1, count / 2000);
    size_t seen = 0, checked = 0, disagree = 0;
    for (auto v = distance_->cbeginValueOn(); v; ++v) {
      if (!qualifies(*v) || seen++ % stride != 0) continue;
      const openvdb::Coord c = v.getCoord();
      const bool inside = winding()(lattice_.position({c.x(), c.y(), c.z()})) > 0.5;
      disagree += inside != (*v < 0);
      ++checked;
    }
    const double share = double(disagree) / double(checked);
    if (share <= 0.05) return;
    open_ = true;
    mesh_.two_sided = true;
    mesh_.surface += "; but OpenVDB's flood fill leaked through its holes at this resolution (" +
                     std::to_string(int(std::lround(100 * share))) + "% of " + std::to_string(checked) +
                     " points checked against the winding number disagree): drawn two-sided instead";
    find_open_sides();
    find_neighbours();
    find_shell_offsets();
  }

  // Per triangle, bit i: the edge opposite corner i is open (no other
  // triangle has an edge between the same two points); bit 3 + i: corner i
  // lies on an open edge. By position (TriangleMesh::welded), not by vertex
  // index: faces stored with vertices of their own (a box of six separate
  // grids) still meet at their shared edges, which are creases, not rims.
  void find_open_sides() {
    ensure_welded();
    const std::vector<uint32_t>& id = mesh_.welded;
    auto key = [&](int a, int b) { return mesh_.edge_key(a, b); };
    std::unordered_map<uint64_t, uint32_t> uses;
    for (const glm::ivec3& t : mesh_.triangles)
      for (int i = 0; i < 3; ++i) ++uses[key(t[(i + 1) % 3], t[(i + 2) % 3])];
    open_sides_.assign(mesh_.triangles.size(), 0);
    std::unordered_set<uint32_t> open_corners;
    for (size_t f = 0; f < mesh_.triangles.size(); ++f) {
      const glm::ivec3& t = mesh_.triangles[f];
      for (int i = 0; i < 3; ++i) {
        const int a = t[(i + 1) % 3], b = t[(i + 2) % 3];
        if (uses[key(a, b)] != 1) continue;
        open_sides_[f] |= uint8_t(1u << i);
        open_corners.insert(id[size_t(a)]);
        open_corners.insert(id[size_t(b)]);
      }
    }
    for (size_t f = 0; f < mesh_.triangles.size(); ++f)
      for (int i = 0; i < 3; ++i)
        if (open_corners.count(id[size_t(mesh_.triangles[f][i])])) open_sides_[f] |= uint8_t(8u << i);
  }

  // Per triangle of a surface drawn two-sided, where its shell lies: the
  // generalized winding number jumps by 1 through every triangle; halfway
  // through, m = w(in front) + 1/2 is near 1/2 where the triangle bounds a
  // volume behind its face (a scan with holes: the lion's face), near -1/2
  // where it bounds one in front (a piece wound inside out), and near 0 on
  // a sheet (both sides outside). The shell of a triangle that bounds a
  // volume lies inside it, its outer face on the triangle, so that the
  // surface does not swell by half the shell's width where the reference
  // draws it; a sheet's shell is centred on it. The offset is signed (+:
  // inside is behind the face), its magnitude the share of the half width
  // the shell moves (bounds_volume, mesh.h).
  void find_shell_offsets() {
    shell_offset_.assign(mesh_.triangles.size(), 0.0f);
    const WindingNumber& w = winding();
    const glm::dvec3 extent = glm::dvec3(mesh_.bounds.hi) - glm::dvec3(mesh_.bounds.lo);
    const double probe = 1e-6 * glm::length(extent);
    tbb::parallel_for(size_t(0), mesh_.triangles.size(), [&](size_t t) {
      const glm::ivec3 i = mesh_.triangles[t];
      const auto& v = mesh_.positions;
      const glm::dvec3 centre = (v[size_t(i.x)] + v[size_t(i.y)] + v[size_t(i.z)]) / 3.0;
      const double m = w(centre + probe * glm::dvec3(mesh_.face_normals[t])) + 0.5;
      const double strength = bounds_volume(m);
      shell_offset_[t] = float(m < 0 ? -strength : strength);
    });
    max_shell_offset_ = 0;
    for (float o : shell_offset_) max_shell_offset_ = std::max(max_shell_offset_, double(std::abs(o)));
  }

  // OpenVDB's band, each side, in voxels: wider by the shell's width for a
  // surface that may be drawn two-sided (open or non-manifold edges), so
  // that its lattice points there get their distance to the shell from the
  // closest triangle (evaluate), not a bound that trilinear interpolation
  // reads as surface nearby (specks beside the mushroom's cap at 512^3).
  float vdb_band_voxels() const {
    return open_ || mesh_.open_edges || mesh_.nonmanifold_edges ? kBandVoxels + kShellVoxels : kBandVoxels;
  }

  // The winding number of the mesh, made on first use. Thread-safe.
  const WindingNumber& winding() const {
    std::call_once(winding_once_, [this] { winding_ = std::make_unique<WindingNumber>(mesh_.positions, mesh_.triangles); });
    return *winding_;
  }

  // TriangleMesh::welded, by index where the mesh did not come from
  // make_triangle_mesh.
  void ensure_welded() {
    if (mesh_.welded.size() == mesh_.positions.size()) return;
    mesh_.welded.resize(mesh_.positions.size());
    std::iota(mesh_.welded.begin(), mesh_.welded.end(), 0u);
  }

  // The faces around each edge and each corner, by position (welded).
  void find_neighbours() {
    ensure_welded();
    uint32_t ids = 0;
    for (uint32_t w : mesh_.welded) ids = std::max(ids, w + 1);
    corner_first_.assign(size_t(ids) + 1, 0);
    for (const glm::ivec3& t : mesh_.triangles)
      for (int i = 0; i < 3; ++i) ++corner_first_[mesh_.welded[size_t(t[i])] + 1];
    for (size_t i = 1; i < corner_first_.size(); ++i) corner_first_[i] += corner_first_[i - 1];
    corner_faces_.resize(corner_first_.back());
    std::vector<uint32_t> fill(corner_first_.begin(), corner_first_.end() - 1);
    for (size_t f = 0; f < mesh_.triangles.size(); ++f)
      for (int i = 0; i < 3; ++i) corner_faces_[fill[mesh_.welded[size_t(mesh_.triangles[f][i])]]++] = uint32_t(f);
  }

  // Which side of the surface p lies on, by the feature its closest point
  // c lies on (Baerentzen and Aanaes 2005): the face's normal inside a
  // face; on an edge or at a corner, the angle-weighted sum of the normals
  // of the faces around it (by position, TriangleMesh::welded), whose sign
  // is exact for a closed, consistently wound mesh. +1 outside, -1 inside,
  // 0 where the test is not clear (p on the surface, or an edge that is not
  // shared by exactly two faces).
  int side_of(glm::dvec3 p, glm::dvec3 c, size_t tri, glm::dvec3 bary) const {
    const glm::dvec3 off = p - c;
    const double gap = glm::length(off);
    if (!(gap > 0)) return 0;
    const glm::ivec3& t = mesh_.triangles[tri];
    uint32_t corners[2] = {0, 0};
    int n = 0;
    for (int i = 0; i < 3; ++i)
      if (bary[i] > 0) corners[std::min(n++, 1)] = mesh_.welded[size_t(t[i])];
    glm::dvec3 normal(mesh_.face_normals[tri]);
    if (n == 2) {  // on an edge: the two faces that share it
      normal = glm::dvec3(0);
      int faces = 0;
      for (uint32_t k = corner_first_[corners[0]]; k < corner_first_[corners[0] + 1]; ++k) {
        const glm::ivec3& u = mesh_.triangles[corner_faces_[k]];
        bool has = false;
        for (int i = 0; i < 3; ++i) has |= mesh_.welded[size_t(u[i])] == corners[1];
        if (has) normal += glm::dvec3(mesh_.face_normals[corner_faces_[k]]), ++faces;
      }
      if (faces != 2) return 0;
    } else if (n == 1) {  // at a corner: each face around it by its angle there
      normal = glm::dvec3(0);
      for (uint32_t k = corner_first_[corners[0]]; k < corner_first_[corners[0] + 1]; ++k) {
        const glm::ivec3& u = mesh_.triangles[corner_faces_[k]];
        int at = 0;
        while (at < 2 && mesh_.welded[size_t(u[at])] != corners[0]) ++at;
        const glm::dvec3 o = mesh_.positions[size_t(u[at])];
        const glm::dvec3 e1 = mesh_.positions[size_t(u[(at + 1) % 3])] - o, e2 = mesh_.positions[size_t(u[(at + 2) % 3])] - o;
        const double angle = std::atan2(glm::length(glm::cross(e1, e2)), glm::dot(e1, e2));
        normal += angle * glm::dvec3(mesh_.face_normals[corner_faces_[k]]);
      }
    }
    const double along = glm::dot(off, normal), size = glm::length(normal);
    if (!(std::abs(along) > 1e-3 * gap * size)) return 0;
    return along > 0 ? 1 : -1;
  }

  // The open edges (find_open_sides), each with its face's normal and its
  // outward direction in the face's plane, listed by the cells of a grid
  // kEdgeCellVoxels wide that they pass near: a point finds every open edge
  // within reach (nearest_open_edge) in its own cell's list.
  void index_open_edges() {
    open_edges_.clear();
    edge_cells_.clear();
    const double cell = kEdgeCellVoxels * lattice_.voxel;
    std::vector<uint64_t> keys;
    for (size_t f = 0; f < mesh_.triangles.size(); ++f) {
      if (!(open_sides_[f] & 7u)) continue;
      const glm::ivec3& u = mesh_.triangles[f];
      const glm::dvec3 nf(mesh_.face_normals[f]);
      for (int i = 0; i < 3; ++i) {
        if (!(open_sides_[f] & (1u << i))) continue;
        OpenEdge e{mesh_.positions[size_t(u[(i + 1) % 3])], mesh_.positions[size_t(u[(i + 2) % 3])], nf, {}};
        e.outward = glm::cross(e.b - e.a, nf);
        if (glm::dot(e.outward, e.a - mesh_.positions[size_t(u[i])]) < 0) e.outward = -e.outward;
        const double length = glm::length(e.outward);
        if (!(length > 0)) continue;  // a degenerate face
        e.outward /= length;
        const uint32_t index = uint32_t(open_edges_.size());
        open_edges_.push_back(e);
        // The cells around points a fifth of a cell apart along the edge: a
        // point within reach (at most 0.85 cells) of the edge is within a
        // cell of one of them, and its own cell is among those around it.
        const int steps = std::max(1, int(std::ceil(glm::length(e.b - e.a) / (0.2 * cell))));
        keys.clear();
        for (int j = 0; j <= steps; ++j) {
          const glm::ivec3 at(glm::floor((e.a + (e.b - e.a) * (double(j) / steps) - lattice_.origin) / cell));
          for (int k = 0; k < 27; ++k) keys.push_back(cell_key(at + glm::ivec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1)));
        }
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        for (uint64_t key : keys) edge_cells_[key].push_back(index);
      }
    }
    // A seam: faces that meet without sharing their corners (a T-junction,
    // a crack between two patches) leave open edges along each other, where
    // the surface goes on. Its ends are no rim: capped, the shell split
    // along every seam (libcgal-demo's ALSTOM_TEST4, 142 of its 231 open
    // edges). An edge is one where another open edge passes within a
    // hundredth of a voxel of its quarter, middle and three-quarter points.
    const double close = 0.01 * lattice_.voxel;
    for (size_t i = 0; i < open_edges_.size(); ++i) {
      OpenEdge& e = open_edges_[i];
      int covered = 0;
      for (const double s : {0.25, 0.5, 0.75}) {
        const glm::dvec3 p = e.a + s * (e.b - e.a);
        const auto listed = edge_cells_.find(cell_key(glm::ivec3(glm::floor((p - lattice_.origin) / cell))));
        if (listed == edge_cells_.end()) continue;
        for (uint32_t j : listed->second) {
          if (j == i) continue;
          if (glm::length(p - closest_on_segment(p, open_edges_[j].a, open_edges_[j].b)) < close) {
            ++covered;
            break;
          }
        }
      }
      e.seam = covered == 3;
    }
  }

  static uint64_t cell_key(glm::ivec3 c) {
    auto bits = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFFu); };
    return bits(c.x) | bits(c.y) << 21 | bits(c.z) << 42;
  }

  // The open edge nearest to p within `reach` (at most a cell of
  // index_open_edges; seams left out), by the distance in space (a face at
  // an angle brings far points close to its edge in its own plane): its
  // distance in space in `gap`, and p's distance from it in its face's
  // plane, returned, with the direction from the edge to p in that plane in
  // `away` (zero where p is on the edge) and the edge's outward direction in
  // `edge_outward`; -1 where no open edge is that near.
  double nearest_open_edge(glm::dvec3 p, double reach, glm::dvec3& away, glm::dvec3& edge_outward, double& gap) const {
    const glm::ivec3 c(glm::floor((p - lattice_.origin) / (kEdgeCellVoxels * lattice_.voxel)));
    const auto cell = edge_cells_.find(cell_key(c));
    if (cell == edge_cells_.end()) return -1;
    gap = reach;
    const OpenEdge* best = nullptr;
    glm::dvec3 along(0);
    for (uint32_t i : cell->second) {
      const OpenEdge& e = open_edges_[i];
      if (e.seam) continue;
      const glm::dvec3 q = closest_on_segment(p, e.a, e.b);
      if (const double d = glm::length(p - q); d < gap) {
        gap = d, best = &e;
        along = p - q - glm::dot(p - q, e.normal) * e.normal;  // in the face's plane
      }
    }
    if (!best) return -1;
    const double in_plane = glm::length(along);
    away = in_plane > 1e-9 * reach ? along / in_plane : glm::dvec3(0);
    edge_outward = best->outward;
    return in_plane;
  }

  // Whether the closest point of barycentric coordinates `bary` on triangle
  // `tri` lies on an open edge or a corner of one.
  bool on_open_side(size_t tri, glm::dvec3 bary) const {
    const uint8_t sides = open_sides_[tri];
    if (!sides) return false;
    int zeros = 0, last = 0, other = 0;
    for (int i = 0; i < 3; ++i) {
      if (bary[i] <= 0)
        ++zeros, last = i;
      else
        other = i;
    }
    if (zeros == 1) return sides & (1u << last);   // on the edge opposite corner `last`
    if (zeros == 2) return sides & (8u << other);  // at corner `other`
    return false;
  }

  TriangleMesh mesh_;
  // Drawn as shells; OpenVDB's sign (a flood-fill guess there) is unused.
  bool open_ = mesh_.two_sided;
  std::vector<uint8_t> open_sides_;  // find_open_sides()
  std::vector<float> shell_offset_;  // find_shell_offsets()
  double max_shell_offset_ = 0;      // the largest |shell_offset_|
  std::vector<uint32_t> corner_first_, corner_faces_;  // find_neighbours()
  struct OpenEdge {
    glm::dvec3 a, b, normal, outward;  // ends, the face's normal, outward in the face's plane
    bool seam = false;                 // another open edge runs along it (index_open_edges)
  };
  std::vector<OpenEdge> open_edges_;                                 // index_open_edges()
  std::unordered_map<uint64_t, std::vector<uint32_t>> edge_cells_;  // index_open_edges()
  mutable std::once_flag winding_once_;
  mutable std::unique_ptr<WindingNumber> winding_;
  Lattice lattice_;
  openvdb::math::Transform::Ptr transform_;
  openvdb::FloatGrid::Ptr distance_;
  openvdb::Int32Grid::Ptr index_;
};

}  // namespace

std::unique_ptr<SurfaceSource> load_mesh(const std::string& path, const MeshOptions& options) {
  return std::make_unique<MeshSource>(read_mesh(path, options));
}

std::unique_ptr<SurfaceSource> mesh_source(TriangleMesh mesh) { return std::make_unique<MeshSource>(std::move(mesh)); }

}  // namespace svo::voxelizer
