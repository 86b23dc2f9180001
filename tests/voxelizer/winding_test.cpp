// Generalized winding numbers: exact values on closed and open surfaces with
// a known answer, and the fast approximation against the exact sum.
#include "svo/voxelizer/winding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <random>

#include "grid_mesh.h"
#include "svo/voxelizer/mesh.h"

namespace {
using svo::voxelizer::WindingNumber;

// What the fast approximation must reach at beta = 2: the voxelizer decides
// inside (w > 1/2) and sheets (w near 0 or 1 on both sides) with margins of
// 1/4, far above it.
constexpr double kFast = 0.04;

using Soup = svo::voxelizer::MeshArrays;  // positions and triangles only

// The unit cube [0, 1]^3, outward, each face an n x n grid of quads; without
// its top face (z = 1) when `lid` is false.
Soup grid_box(int n, bool lid) {
  Soup s;
  svo::test::add_grid(s, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, n);  // bottom, -z
  if (lid) svo::test::add_grid(s, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, n);
  svo::test::add_grid(s, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}, n);  // -y
  svo::test::add_grid(s, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, n);  // +y
  svo::test::add_grid(s, {0, 0, 0}, {0, 0, 1}, {0, 1, 0}, n);  // -x
  svo::test::add_grid(s, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, n);  // +x
  return s;
}

// A square sheet z = 0, [-1, 1]^2, normal +z.
Soup sheet(int n) {
  Soup s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.positions.emplace_back(-1 + 2.0 * i / n, -1 + 2.0 * j / n, 0.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      s.triangles.emplace_back(a, b, d);
      s.triangles.emplace_back(a, d, c);
    }
  return s;
}

TEST(Winding, TriangleSignFollowsItsBack) {
  // Normal +z: a point below sees its back (positive), above its front.
  const glm::dvec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_GT(WindingNumber::triangle({0.2, 0.2, -0.1}, a, b, c), 0.0);
  EXPECT_LT(WindingNumber::triangle({0.2, 0.2, 0.1}, a, b, c), 0.0);
  // Right above a large triangle's interior: nearly a hemisphere, -1/2.
  EXPECT_NEAR(WindingNumber::triangle({0.1, 0.1, 1e-6}, {-1e3, -1e3, 0}, {1e3, -1e3, 0}, {0, 1e3, 0}), -0.5, 1e-3);
}

TEST(Winding, ClosedBoxIsOneInsideZeroOutside) {
  const Soup box = grid_box(6, true);
  const WindingNumber w(box.positions, box.triangles);
  for (glm::dvec3 q : {glm::dvec3(0.5), glm::dvec3(0.01, 0.5, 0.99), glm::dvec3(0.999, 0.001, 0.5)}) {
    EXPECT_NEAR(w.exact(q), 1.0, 1e-9) << q.x << " " << q.y << " " << q.z;
    EXPECT_NEAR(w(q), 1.0, kFast) << q.x << " " << q.y << " " << q.z;
  }
  for (glm::dvec3 q : {glm::dvec3(1.5), glm::dvec3(-0.01, 0.5, 0.5), glm::dvec3(0.5, 0.5, 1.001)}) {
    EXPECT_NEAR(w.exact(q), 0.0, 1e-9);
    EXPECT_NEAR(w(q), 0.0, kFast);
  }
}

TEST(Winding, LidlessBoxIsFractionalNearTheHole) {
  const Soup box = grid_box(6, false);
  const WindingNumber w(box.positions, box.triangles);
  // Above the floor's centre the missing lid subtends 4 arcsin(1/5) sr: w = 1 - that / 4 pi.
  const double lid = 4 * std::asin(1.0 / 5.0) / (4 * M_PI);
  EXPECT_NEAR(w.exact({0.5, 0.5, 1e-9}), 1 - lid, 1e-6);
  EXPECT_NEAR(w({0.5, 0.5, 1e-9}), 1 - lid, kFast);
  // Below the floor it is minus the lid's share.
  EXPECT_NEAR(w.exact({0.5, 0.5, -1e-9}), -lid, 1e-6);
  // At the centre of the hole, halfway.
  EXPECT_NEAR(w.exact({0.5, 0.5, 1.0}), 0.5, 1e-9);
}

TEST(Winding, SheetIsMinusHalfInFrontPlusHalfBehind) {
  const Soup s = sheet(16);
  const WindingNumber w(s.positions, s.triangles);
  EXPECT_NEAR(w({0.03, -0.02, 1e-4}), -0.5, 2e-3);
  EXPECT_NEAR(w({0.03, -0.02, -1e-4}), 0.5, 2e-3);
  // The jump across the sheet is 1 everywhere on it.
  for (double x : {-0.9, -0.3, 0.4, 0.97}) {
    EXPECT_NEAR(w.exact({x, 0.5 * x, -1e-7}) - w.exact({x, 0.5 * x, 1e-7}), 1.0, 1e-4);
  }
}

TEST(Winding, FastMatchesExactOnRandomPoints) {
  const Soup box = grid_box(24, false);  // 5 x 1152 triangles
  for (double beta : {2.0, 3.0}) {
    const WindingNumber w(box.positions, box.triangles, beta);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.5, 1.5);
    double worst = 0;
    for (int i = 0; i < 400; ++i) {
      const glm::dvec3 q(u(rng), u(rng), u(rng));
      worst = std::max(worst, std::abs(w(q) - w.exact(q)));
    }
    EXPECT_LT(worst, beta == 2.0 ? kFast : 0.5 * kFast) << "beta " << beta;
  }
}

// What make_triangle_mesh decides: a box with one small triangle missing is
// drawn as a solid; without its lid, or as a sheet, two-sided.
TEST(Winding, SmallHolesKeepASolidLargeOnesDrawTwoSided) {
  auto decide = [](Soup m, bool drop_one) {
    if (drop_one) m.triangles.pop_back();
    std::string warning;
    svo::voxelizer::MeshOptions o;
    o.warning = [&](const std::string& w) { warning = w; };
    const svo::voxelizer::TriangleMesh mesh = svo::voxelizer::make_triangle_mesh("box", std::move(m), o);
    EXPECT_GT(mesh.open_edges, 0u);
    EXPECT_NE(warning.find(mesh.two_sided ? "drawn two-sided" : "drawn as a solid"), std::string::npos) << warning;
    return mesh.two_sided;
  };
  EXPECT_FALSE(decide(grid_box(12, true), true));
  EXPECT_TRUE(decide(grid_box(12, false), false));
  EXPECT_TRUE(decide(sheet(8), false));
}

TEST(Winding, EmptySoupIsZero) {
  const WindingNumber w({}, {});
  EXPECT_EQ(w({0, 0, 0}), 0.0);
}

}  // namespace
