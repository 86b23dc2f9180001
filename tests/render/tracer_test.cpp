// The cone tracer on the CPU (render_cpu runs shaders/common/tracer.glsl as
// C++): exact coverage of a plane, silhouette coverage of a sphere against
// the analytic footprint coverage, and paper Fig. 4 on correlated elements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "svo/render/octree_access.h"
#include "test_scenes.h"
#include "trace_setup.h"

namespace svo::math {
// The tracer's code on the native reader, to march single cones.
struct ConeMarcher : render::NativeOctreeReader {
#include "common/tracer.glsl"
};
}  // namespace svo::math

namespace svo::render {
namespace {

float coverage(const Frame& f, uint32_t x, uint32_t y) { return f.colour[size_t(y) * f.width + x].a; }

// The unit vector through the centre of pixel (x, y) plus offset (dx, dy) in pixels.
glm::vec3 pixel_ray(const Camera& c, uint32_t w, uint32_t h, float x, float y) {
  glm::vec3 fw = glm::normalize(c.target - c.eye), u = glm::normalize(glm::cross(fw, c.up)), v = glm::cross(u, fw);
  float t = std::tan(glm::radians(c.fov_deg) * 0.5f);
  float nx = (x / float(w)) * 2 - 1, ny = (y / float(h)) * 2 - 1;
  return glm::normalize(fw + nx * t * float(w) / float(h) * u - ny * t * v);
}

TEST(Tracer, PlaneFacingTheCameraCoversExactlyTheExpectedPixels) {
  // A thin square plate [-0.5, 0.5]^2 at z = 0 seen along -z; the camera puts
  // its edges halfway between pixel centres.
  test::BoxScene plate({-0.5f, -0.5f, -0.02f}, {0.5f, 0.5f, 0.02f});
  octree::Octree tree = test::voxelize(plate, 128);
  RenderSettings s;
  s.width = s.height = 48;
  // 48 pixels span 2 tan(fov/2) * 4 = 1.5 units: the plate spans 32 pixels.
  float z = 4.0f + 0.02f;
  s.camera = test::looking_at_origin({0, 0, z}, 2 * glm::degrees(std::atan(0.75f / z)));
  Frame f = render_cpu(tree, s);
  test::save_for_inspection(f, "plane");
  int wrong = 0;
  for (uint32_t y = 0; y < s.height; ++y) {
    for (uint32_t x = 0; x < s.width; ++x) {
      bool inside = x >= 8 && x < 40 && y >= 8 && y < 40;
      float c = coverage(f, x, y);
      // Pixels whose centre sees the plate are more than half covered, the
      // others less; away from the edges, all or nothing (the pre-filtered edge
      // spreads over about one voxel of the cone's level, about a pixel).
      bool edge = (x >= 6 && x < 10) || (x >= 38 && x < 42) || (y >= 6 && y < 10) || (y >= 38 && y < 42);
      bool ok = inside ? c > 0.5f && (edge || c > 0.99f) : c < 0.5f && (edge || c < 0.01f);
      if (!ok && ++wrong < 10) ADD_FAILURE() << "pixel " << x << "," << y << " coverage " << c;
    }
  }
  EXPECT_EQ(wrong, 0);
}

// Exact coverage of each pixel's footprint disk (radius pixel / sqrt(pi)) by
// a sphere at the origin: the fraction of rays through a fine grid of the
// disk that meet it.
std::vector<float> sphere_coverage(const RenderSettings& s, float radius) {
  const float r_px = 1.0f / std::sqrt(3.14159265f);
  std::vector<float> exact(size_t(s.width) * s.height);
  for (uint32_t y = 0; y < s.height; ++y) {
    for (uint32_t x = 0; x < s.width; ++x) {
      int hits = 0, total = 0;
      for (int j = 0; j < 24; ++j) {
        for (int i = 0; i < 24; ++i) {
          float dx = ((i + 0.5f) / 24 * 2 - 1) * r_px, dy = ((j + 0.5f) / 24 * 2 - 1) * r_px;
          if (dx * dx + dy * dy > r_px * r_px) continue;
          glm::vec3 d = pixel_ray(s.camera, s.width, s.height, x + 0.5f + dx, y + 0.5f + dy);
          glm::vec3 o = s.camera.eye;
          float b = glm::dot(o, d), c = glm::dot(o, o) - radius * radius;
          hits += b * b - c >= 0 && b < 0 ? 1 : 0;
          ++total;
        }
      }
      exact[size_t(y) * s.width + x] = float(hits) / float(total);
    }
  }
  return exact;
}

struct CoverageError {
  double silhouette_mean = 0;  // mean |coverage - exact| where 0 < exact < 1
  int silhouette = 0;
  double elsewhere_max = 0;  // largest |coverage - exact| elsewhere
};

CoverageError coverage_error(const Frame& f, const std::vector<float>& exact) {
  CoverageError e;
  for (size_t i = 0; i < exact.size(); ++i) {
    double d = std::abs(f.colour[i].a - exact[i]);
    if (exact[i] > 0.0f && exact[i] < 1.0f) {
      e.silhouette_mean += d;
      ++e.silhouette;
    } else {
      e.elsewhere_max = std::max(e.elsewhere_max, d);
    }
  }
  e.silhouette_mean /= std::max(e.silhouette, 1);
  return e;
}

TEST(Tracer, SphereSilhouetteCoverageMatchesTheAnalyticFootprintCoverage) {
  const float radius = 0.5f;
  test::SphereScene sphere(radius);
  octree::Octree tree = test::voxelize(sphere, 256);
  RenderSettings s;
  s.width = s.height = 64;
  s.camera = test::looking_at_origin({0.3f, 0.4f, 3.0f}, 25.0f);
  Frame f = render_cpu(tree, s);
  test::save_for_inspection(f, "sphere");
  CoverageError e = coverage_error(f, sphere_coverage(s, radius));
  ASSERT_GT(e.silhouette, 50);
  EXPECT_LT(e.silhouette_mean, 0.03) << "mean absolute coverage error over " << e.silhouette << " silhouette pixels";
  EXPECT_LT(e.elsewhere_max, 0.15);
  std::printf("sphere silhouette: %d pixels, mean absolute coverage error %.4f\n", e.silhouette, e.silhouette_mean);
}

// The supersampling baseline: one ray per pixel is all or nothing; 16
// stratified rays approach the exact coverage.
TEST(Tracer, RayMarchingIsBinaryPerRayAndConvergesWithRays) {
  const float radius = 0.5f;
  test::SphereScene sphere(radius);
  octree::Octree tree = test::voxelize(sphere, 128);
  RenderSettings s;
  s.width = s.height = 48;
  s.camera = test::looking_at_origin({0.3f, 0.4f, 3.0f}, 25.0f);
  s.mode = Mode::RayMarch;
  const std::vector<float> exact = sphere_coverage(s, radius);
  Frame one = render_cpu(tree, s);
  for (const auto& c : one.colour) ASSERT_TRUE(c.a == 0.0f || c.a == 1.0f) << c.a;
  s.spp = 16;
  Frame many = render_cpu(tree, s);
  CoverageError e1 = coverage_error(one, exact), e16 = coverage_error(many, exact);
  std::printf("raymarch silhouette error: 1 ray %.4f, 16 rays %.4f\n", e1.silhouette_mean, e16.silhouette_mean);
  EXPECT_LT(e16.silhouette_mean, 0.06);
  EXPECT_LT(e16.silhouette_mean, 0.5 * e1.silhouette_mean);
  s.spp = 3;
  EXPECT_THROW(render_cpu(tree, s), std::invalid_argument);
}

// Paper Fig. 4: the eye looks along the face x = 0 of a half-space, so the
// rays of the middle column run inside that plane and every cone element
// there sees the same half-covered footprint. OR-ed masks keep
// the pixel half covered; alpha blending of the same coverages thickens it
// towards 1.
TEST(Tracer, CorrelatedElementsKeepAHalfCoveredPixelHalfCovered) {
  test::HalfSpaceScene half({{-0.6f, -0.3f, -0.6f}, {0.6f, 0.3f, 0.6f}});
  octree::Octree tree = test::voxelize(half, 128);
  RenderSettings s;
  s.width = 33;  // odd: the middle column's rays lie in the plane x = 0
  s.height = 16;
  s.camera = test::looking_at_origin({0, 0, 3.0f}, 4.0f);
  for (Mode mode : {Mode::Prefiltered, Mode::Alpha}) {
    s.mode = mode;
    Frame f = render_cpu(tree, s);
    test::save_for_inspection(f, std::string("fig4-") + mode_name(mode));
    double sum = 0;
    for (uint32_t y = 0; y < s.height; ++y) sum += coverage(f, 16, y);
    double mean = sum / s.height;
    std::printf("%s: middle column coverage %.3f after %.1f elements per pixel\n", mode_name(mode), mean,
                f.steps_per_pixel);
    if (mode == Mode::Prefiltered) {
      EXPECT_NEAR(mean, 0.5, 0.05) << "prefiltered";
      for (uint32_t y = 0; y < s.height; ++y) EXPECT_NEAR(coverage(f, 16, y), 0.5f, 0.08f) << "row " << y;
    } else {
      EXPECT_GT(mean, 0.8) << "alpha blending should thicken the edge";
    }
    // Columns left of the edge are covered, right of it empty.
    EXPECT_GT(coverage(f, 10, 8), 0.99f);
    EXPECT_LT(coverage(f, 22, 8), 0.01f);
  }
}

TEST(Tracer, RejectsBadSettingsWithAMessage) {
  test::SphereScene sphere(0.5f);
  octree::Octree tree = test::voxelize(sphere, 32);
  RenderSettings s;
  s.width = 0;
  EXPECT_THROW(render_cpu(tree, s), std::invalid_argument);
  s.width = 8;
  s.camera.target = s.camera.eye;
  EXPECT_THROW(render_cpu(tree, s), std::invalid_argument);
  s.camera = test::looking_at_origin({0, 0, 3}, 40);
  s.lights.assign(kMaxLights + 1, Light{});
  EXPECT_THROW(render_cpu(tree, s), std::invalid_argument);
  s.lights.assign(1, Light{});
  for (float spread : {-0.5f, 5.0f, std::nanf("")}) {
    s.footprint_spread = spread;
    EXPECT_THROW(render_cpu(tree, s), std::invalid_argument) << spread;
  }
  s.footprint_spread = 1;
  for (float voxel : {0.1f, 5.0f, std::nanf("")}) {
    s.shading_voxel = voxel;
    EXPECT_THROW(render_cpu(tree, s), std::invalid_argument) << voxel;
  }
  s.shading_voxel = 1;
  s.lens_parts = 9;
  EXPECT_THROW(render_cpu(tree, s), std::invalid_argument);
}

// How many parts a side a lens is traced in (render::lens_parts): one
// without a lens or in raymarch mode, the count asked for, else from the
// blur's width inside the domain against the coarsest voxel (1 for a
// gentle blur, up to 4), and the frame traces that many cones a pixel.
TEST(Tracer, TheLensIsSplitAsTheBlurWidens) {
  test::SphereScene sphere(0.5f);
  octree::Octree tree = test::voxelize(sphere, 32);
  RenderSettings s;
  s.width = s.height = 16;
  s.camera = test::looking_at_origin({0, 0, 3}, 40);
  EXPECT_EQ(lens_parts(tree, s), 1u);
  s.camera.focus = 3;
  const std::vector<float> apertures{0.005f, 0.05f, 0.2f, 1.0f};
  std::vector<uint32_t> parts;
  for (float aperture : apertures) {
    s.camera.aperture = aperture;
    parts.push_back(lens_parts(tree, s));
  }
  EXPECT_EQ(parts.front(), 1u);
  EXPECT_EQ(parts.back(), 4u);
  EXPECT_TRUE(std::is_sorted(parts.begin(), parts.end()));
  // An octree whose provenance says it holds two-sided shells: finer parts
  // (never coarser, finer for some blur); provenance that does not say so
  // in a boolean, or is not JSON, counts as closed.
  octree::Octree shells = tree;
  shells.source = R"({"input": "open.obj", "two_sided": true})";
  bool finer = false;
  for (size_t i = 0; i < parts.size(); ++i) {
    s.camera.aperture = apertures[i];
    EXPECT_GE(lens_parts(shells, s), parts[i]);
    finer = finer || lens_parts(shells, s) > parts[i];
    for (const char* text : {R"({"two_sided": "yes"})", "two_sided", R"([true])"}) {
      octree::Octree odd = tree;
      odd.source = text;
      EXPECT_EQ(lens_parts(odd, s), parts[i]) << text;
    }
  }
  EXPECT_TRUE(finer);
  s.camera.aperture = 0.2f;
  const Frame chosen = render_cpu(tree, s);
  s.lens_parts = 3;
  EXPECT_EQ(lens_parts(tree, s), 3u);
  const Frame three = render_cpu(tree, s);
  s.lens_parts = 1;
  const Frame one = render_cpu(tree, s);
  // Each part's cone marches the sphere: the steps grow with the cones.
  EXPECT_GT(three.steps_per_pixel, 4 * one.steps_per_pixel);
  EXPECT_GT(chosen.steps_per_pixel, one.steps_per_pixel);
  s.mode = Mode::RayMarch;
  s.lens_parts = 3;
  EXPECT_EQ(lens_parts(tree, s), 1u);
}

// Numbers in [0, 1), the same on every run (a linear congruential generator).
struct Uniform {
  uint32_t state;
  float operator()() {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  }
};

// The Vulkan host runs the tracer only over domain_pixel_rect and writes
// the background elsewhere: every pixel outside it must miss the domain box
// (the test svo_trace_pixel makes), for cameras near and far, aimed at the
// domain, past it and away from it; and the rectangle must be tight enough
// to spare a far view's empty pixels and the whole of a view away from it.
TEST(Tracer, PixelsOutsideTheDomainRectangleMissTheDomain) {
  test::SphereScene sphere(0.5f);
  octree::Octree tree = test::voxelize(sphere, 16);
  PackedOctree packed = pack_octree(tree);
  const glm::vec3 lo = tree.origin, hi = tree.origin + glm::vec3(tree.size);
  Uniform uniform{12345u};
  int tight = 0, empty = 0, whole = 0;
  for (int trial = 0; trial < 300; ++trial) {
    RenderSettings s;
    s.width = 24 + uint32_t(40 * uniform());
    s.height = 24 + uint32_t(40 * uniform());
    glm::vec3 dir = glm::normalize(glm::vec3(uniform(), uniform(), uniform()) * 2.0f - 1.0f);
    s.camera.eye = dir * (0.9f + 6.0f * uniform());
    s.camera.target = glm::vec3(uniform(), uniform(), uniform()) * 4.0f - 2.0f;
    if (trial % 3 == 0) s.camera.target = 2.0f * s.camera.eye + 0.5f * s.camera.target;  // looking away
    s.camera.up = glm::vec3(0, 1, 0);
    s.camera.fov_deg = 10.0f + 110.0f * uniform();
    TraceParams p = make_trace_params(tree, packed, s);
    PixelRect r = domain_pixel_rect(p);
    ASSERT_LE(r.x1, s.width);
    ASSERT_LE(r.y1, s.height);
    if (r.empty())
      ++empty;
    else if (r.x0 == 0 && r.y0 == 0 && r.x1 == s.width && r.y1 == s.height)
      ++whole;
    else
      ++tight;
    for (uint32_t y = 0; y < s.height; ++y) {
      for (uint32_t x = 0; x < s.width; ++x) {
        if (!r.empty() && x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1) continue;
        glm::vec3 d = pixel_ray(s.camera, s.width, s.height, float(x) + 0.5f, float(y) + 0.5f);
        glm::vec3 inv = 1.0f / d;
        glm::vec3 t0 = (lo - s.camera.eye) * inv, t1 = (hi - s.camera.eye) * inv;
        glm::vec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
        float entry = std::max(std::max(std::max(near.x, near.y), near.z), 0.0f);
        float exit = std::min(std::min(far.x, far.y), far.z);
        ASSERT_FALSE(entry < exit) << "trial " << trial << ": pixel " << x << "," << y << " outside [" << r.x0 << ", "
                                   << r.x1 << ") x [" << r.y0 << ", " << r.y1 << ") meets the domain";
      }
    }
  }
  std::printf("rectangles: %d tight, %d empty, %d whole image\n", tight, empty, whole);
  EXPECT_GT(tight, 60);
  EXPECT_GT(empty, 30);
}

// The Vulkan host leaves svo_step's second level out of the kernel where
// cones_may_blend says that no element of the frame can read a coarser
// level than the finest. Marched here with every flag open (the native
// reader), no element of any sampled pixel of such a frame blends two
// levels, for cameras near and far; frames that may blend do (so that a
// bound too generous would show).
TEST(Tracer, FramesWithoutLevelBlendsHaveNoElementThatBlends) {
  test::SphereScene sphere(0.45f);
  octree::Octree tree = test::voxelize(sphere, 64);
  OctreeAccess access(tree);
  const glm::vec3 lo = tree.origin;
  Uniform uniform{777u};
  int narrow = 0, wide = 0, wide_blending = 0;
  for (int trial = 0; trial < 120; ++trial) {
    RenderSettings s;
    s.width = s.height = 32u << uint32_t(6 * uniform());  // 32 to 1024
    glm::vec3 dir = glm::normalize(glm::vec3(uniform(), uniform(), uniform()) * 2.0f - 1.0f);
    s.camera.eye = lo + 0.5f * tree.size + dir * tree.size * (0.8f + 4.0f * uniform());
    s.camera.target = lo + 0.5f * tree.size + (glm::vec3(uniform(), uniform(), uniform()) - 0.5f) * 0.3f * tree.size;
    s.camera.up = glm::vec3(0, 1, 0);
    s.camera.fov_deg = 10.0f + 60.0f * uniform();
    const TraceParams p = access.params(s);
    svo::math::ConeMarcher marcher{access.native(p)};
    int blends = 0;
    for (uint32_t j = 0; j < 16; ++j) {
      for (uint32_t i = 0; i < 16; ++i) {
        const glm::vec2 at((float(i) + 0.5f) * float(s.width) / 16.0f, (float(j) + 0.5f) * float(s.height) / 16.0f);
        const glm::vec3 d = marcher.svo_pixel_direction(at);
        const svo::math::ConeMarcher::SvoCone cone = marcher.svo_make_cone(glm::vec3(p.eye), d, 0.0f, p.eye.w, 0.0f, 1.0f);
        const float t0 = std::max(marcher.svo_box_entry(cone.o, cone.inv_d, glm::vec3(p.domain), p.domain.w), 0.0f);
        const float t1 = marcher.svo_box_exit(cone.o, cone.inv_d, glm::vec3(p.domain), p.domain.w);
        svo::math::ConeMarcher::SvoMarch m = marcher.svo_march_start(t0);
        for (int steps = 0; m.t < t1 && steps < 4096; ++steps) {
          marcher.svo_step(m, cone, svo::math::SVO_MODE_PREFILTERED);
          blends += m.blend > 0.0f;
        }
      }
    }
    if (cones_may_blend(p)) {
      ++wide;
      wide_blending += blends > 0;
    } else {
      ++narrow;
      EXPECT_EQ(blends, 0) << "trial " << trial << ": eye " << s.camera.eye.x << "," << s.camera.eye.y << ","
                           << s.camera.eye.z << ", " << s.width << " pixels, fov " << s.camera.fov_deg;
    }
  }
  std::printf("frames: %d narrow, %d may blend (%d of them blend)\n", narrow, wide, wide_blending);
  EXPECT_GT(narrow, 10);
  EXPECT_GT(wide_blending, 10);
}

// A lens or shadow cones: always open.
TEST(Tracer, LensesAndShadowsMayAlwaysBlend) {
  test::SphereScene sphere(0.45f);
  octree::Octree tree = test::voxelize(sphere, 64);
  OctreeAccess access(tree);
  RenderSettings s;
  s.width = s.height = 1024;
  s.camera.eye = tree.origin + glm::vec3(0.5f * tree.size, 0.5f * tree.size, 1.2f * tree.size);
  s.camera.target = tree.origin + glm::vec3(0.5f * tree.size);
  s.camera.up = glm::vec3(0, 1, 0);
  s.camera.fov_deg = 30.0f;
  ASSERT_FALSE(cones_may_blend(access.params(s)));
  RenderSettings lens = s;
  lens.camera.aperture = 0.01f;
  lens.camera.focus = 1.0f;
  EXPECT_TRUE(cones_may_blend(access.params(lens)));
  RenderSettings shadows = s;
  shadows.shadows = true;
  EXPECT_TRUE(cones_may_blend(access.params(shadows)));
}

}  // namespace
}  // namespace svo::render
