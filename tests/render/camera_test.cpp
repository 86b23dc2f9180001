// Cameras and lights from text, JSON files and presets (render/camera.h).
#include "svo/render/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "svo/voxelizer/build.h"
#include "svo/voxelizer/scenes.h"
#include "temp_dir.h"

namespace svo::render {
namespace {

using testing::TempDir;

// The message of the std::invalid_argument (or other exception) `f` throws; "" if none.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(ParseCamera, ReadsTenNumbers) {
  Camera c = parse_camera("1,2,3, 0,0,0, 0,1,0, 35.5");
  EXPECT_EQ(c.eye, glm::vec3(1, 2, 3));
  EXPECT_EQ(c.target, glm::vec3(0, 0, 0));
  EXPECT_EQ(c.up, glm::vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(c.fov_deg, 35.5f);
  EXPECT_EQ(c.aperture, 0);
  EXPECT_EQ(parse_camera("+1e1,-2,3,0,0,0,0,0,1,90").eye, glm::vec3(10, -2, 3));
}

TEST(ParseCamera, ErrorsNameTheProblem) {
  EXPECT_EQ(error_of([] { parse_camera("1,2,3"); }),
            "--camera '1,2,3': expected 10 numbers ex,ey,ez,tx,ty,tz,ux,uy,uz,fov, got 3");
  EXPECT_EQ(error_of([] { parse_camera("1,2,3,0,0,0,0,1,0,40,7"); }),
            "--camera '1,2,3,0,0,0,0,1,0,40,7': expected 10 numbers ex,ey,ez,tx,ty,tz,ux,uy,uz,fov, got 11");
  EXPECT_EQ(error_of([] { parse_camera("1,x,3,0,0,0,0,1,0,40"); }),
            "--camera '1,x,3,0,0,0,0,1,0,40': value 2 'x' is not a finite number");
  EXPECT_EQ(error_of([] { parse_camera("1,2,3,0,0,0,0,1,0,inf"); }),
            "--camera '1,2,3,0,0,0,0,1,0,inf': value 10 'inf' is not a finite number");
  EXPECT_EQ(error_of([] { parse_camera("1,2,3,0,nan,0,0,1,0,40"); }),
            "--camera '1,2,3,0,nan,0,0,1,0,40': value 5 'nan' is not a finite number");
  EXPECT_EQ(error_of([] { parse_camera("1,2,,0,0,0,0,1,0,40"); }),
            "--camera '1,2,,0,0,0,0,1,0,40': value 3 '' is not a finite number");
  EXPECT_EQ(error_of([] { parse_camera("1,2,3,1,2,3,0,1,0,40"); }),
            "--camera '1,2,3,1,2,3,0,1,0,40': eye and target are the same point (1, 2, 3)");
  EXPECT_EQ(error_of([] { parse_camera("0,5,0,0,0,0,0,2,0,40"); }),
            "--camera '0,5,0,0,0,0,0,2,0,40': up (0, 2, 0) is parallel to the view direction (0, -1, 0)");
  // Issue 22: an eye far out is said to be far out (its squared distance
  // overflowed a float, which read as "the same point").
  EXPECT_EQ(error_of([] { parse_camera("1e30,0,0,0,0,0,0,1,0,40"); }),
            "--camera '1e30,0,0,0,0,0,0,1,0,40': eye (1e+30, 0, 0) is too far out (1e+30 from the target): "
            "coordinates must be within +-1e+18, beyond which float arithmetic overflows");
  EXPECT_EQ(
      error_of([] {
        parse_camera("0,0,1,0,-2e20,0,0,1,0,40");
      }).rfind("--camera '0,0,1,0,-2e20,0,0,1,0,40': target (0, -2e+20, 0) is too far out (2e+20 from the eye)", 0),
      0u);
  EXPECT_NO_THROW(parse_camera("1e18,0,0,0,0,0,0,1,0,40"));
  EXPECT_EQ(error_of([] { parse_camera("1e6,0,0,1e6,0.5,0,0,0,1,40"); }),
            "--camera '1e6,0,0,1e6,0.5,0,0,0,1,40': eye (1e+06, 0, 0) and target (1e+06, 0.5, 0) are too close for "
            "float precision (0.5 apart; at least 1e-6 x max(1, |eye|) = 1)");
  EXPECT_EQ(error_of([] { parse_camera("0,0,5,0,0,0,0,0,0,40"); }),
            "--camera '0,0,5,0,0,0,0,0,0,40': up is the zero vector");
  for (const char* fov : {"0", "180", "-10", "200"}) {
    std::string text = std::string("0,0,5,0,0,0,0,1,0,") + fov;
    EXPECT_EQ(error_of([&] { parse_camera(text); }),
              "--camera '" + text + "': fov " + fov + " is outside (0, 180) degrees");
  }
  EXPECT_THROW(parse_camera(""), std::invalid_argument);
}

TEST(CameraJson, RoundTrip) {
  TempDir dir;
  Camera c;
  c.eye = {1.25f, -2.5f, 3.125f};
  c.target = {0.1f, 0.2f, 0.3f};
  c.up = {0, 0, 1};
  c.fov_deg = 27.5f;
  save_camera_json(dir / "cam.json", c);
  Camera back = load_camera_json(dir / "cam.json");
  EXPECT_EQ(back.eye, c.eye);
  EXPECT_EQ(back.target, c.target);
  EXPECT_EQ(back.up, c.up);
  EXPECT_EQ(back.fov_deg, c.fov_deg);
  EXPECT_EQ(back.aperture, 0);

  c.aperture = 0.05f;
  c.focus = 2.75f;
  save_camera_json(dir / "cam.json", c);  // over the existing file
  back = load_camera_json(dir / "cam.json");
  EXPECT_EQ(back.aperture, c.aperture);
  EXPECT_EQ(back.focus, c.focus);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporary left
}

TEST(CameraJson, ErrorsNameTheFileAndTheProblem) {
  TempDir dir;
  auto load = [&](const std::string& text) {
    std::string path = dir / "cam.json";
    std::ofstream(path) << text;
    std::string message = error_of([&] { load_camera_json(path); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    return message.substr(std::min(message.size(), path.size() + 2));
  };
  const std::string ok_up = R"("up": [0, 1, 0], "fov": 40)";
  EXPECT_EQ(load(R"({"target": [0, 0, 0], )" + ok_up + "}"), "missing key \"eye\"");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0]})"), "missing key \"fov\"");
  EXPECT_EQ(load(R"({"eye": "far", "target": [0, 0, 0], )" + ok_up + "}"), "\"eye\" must be an array of 3 numbers");
  EXPECT_EQ(load(R"({"eye": [0, 3], "target": [0, 0, 0], )" + ok_up + "}"), "\"eye\" must be an array of 3 numbers");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, "x"], )" + ok_up + "}"),
            "\"target\" must be an array of 3 numbers");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": "wide"})"),
            "\"fov\" must be a number");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 190})"),
            "fov 190 is outside (0, 180) degrees");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 3], )" + ok_up + "}"),
            "eye and target are the same point (0, 0, 3)");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 0, 1], "fov": 40})"),
            "up (0, 0, 1) is parallel to the view direction (0, 0, -1)");
  EXPECT_EQ(load(R"({"eye": [0, 0, 3], "target": [0, 0, 0], )" + ok_up + R"(, "aperture": 0.1})"),
            "focus must be > 0 with an aperture");
  EXPECT_EQ(load("[1, 2, 3]"), "expected a JSON object with eye, target, up and fov");
  EXPECT_EQ(load("{\"eye\": [").rfind("not a JSON camera file: ", 0), 0u);
  EXPECT_EQ(error_of([&] { load_camera_json(dir / "missing.json"); }), (dir / "missing.json") + ": does not exist");
}

TEST(ParseLight, DirectionalAndPoint) {
  Light d = parse_light("dir:0,1,0", glm::vec3(0));
  EXPECT_FALSE(d.point);
  EXPECT_EQ(d.vector, glm::vec3(0, 1, 0));
  EXPECT_EQ(d.radiance, glm::vec3(3));
  Light d2 = parse_light("dir:1,1,0,2.5,0.1", glm::vec3(0));
  EXPECT_EQ(d2.radiance, glm::vec3(2.5f));
  EXPECT_FLOAT_EQ(d2.size, 0.1f);
  // A point light without intensity is as bright at the scene centre as the default directional light.
  Light p = parse_light("point:0,2,0", glm::vec3(0, 1, 0));
  EXPECT_TRUE(p.point);
  EXPECT_EQ(p.vector, glm::vec3(0, 2, 0));
  EXPECT_FLOAT_EQ(p.radiance.x, 3.0f);
  EXPECT_FLOAT_EQ(parse_light("point:0,3,0", glm::vec3(0, 1, 0)).radiance.x, 12.0f);
  EXPECT_FLOAT_EQ(parse_light("point:0,3,0,7", glm::vec3(0, 1, 0)).radiance.x, 7.0f);
}

TEST(ParseLight, Errors) {
  EXPECT_EQ(error_of([] { parse_light("sun:0,1,0", glm::vec3(0)); }),
            "--light 'sun:0,1,0': expected dir:X,Y,Z[,IRRADIANCE[,ANGLE]] or point:X,Y,Z[,INTENSITY[,RADIUS]]");
  EXPECT_EQ(error_of([] { parse_light("dir:0,1", glm::vec3(0)); }),
            "--light 'dir:0,1': expected 3 to 5 numbers after 'dir:', got 2");
  EXPECT_EQ(error_of([] { parse_light("dir:0,0,0", glm::vec3(0)); }), "--light 'dir:0,0,0': direction is zero");
  EXPECT_EQ(error_of([] { parse_light("point:0,a,0", glm::vec3(0)); }),
            "--light 'point:0,a,0': value 2 'a' is not a finite number");
  EXPECT_EQ(error_of([] { parse_light("point:0,1,0,-1", glm::vec3(0)); }),
            "--light 'point:0,1,0,-1': intensity must be >= 0");
}

// ---- Presets on a voxelized bumpy sphere (radius 0.7 at the origin).

class Presets : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = voxelizer::make_scene("bumpy-sphere").release();
    voxelizer::VoxelizeOptions options;
    options.resolution = 64;
    tree_ = new octree::Octree(voxelizer::voxelize(*scene_, options));
  }
  static void TearDownTestSuite() {
    delete tree_;
    delete scene_;
  }
  // Whether the ray eye + t dir (t > 0) meets the box [lo, hi].
  static bool hits_box(glm::vec3 eye, glm::vec3 dir, glm::vec3 lo, glm::vec3 hi) {
    float t0 = 0, t1 = 1e30f;
    for (int a = 0; a < 3; ++a) {
      float ta = (lo[a] - eye[a]) / dir[a], tb = (hi[a] - eye[a]) / dir[a];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
  }
  static voxelizer::AnalyticScene* scene_;
  static octree::Octree* tree_;
};
voxelizer::AnalyticScene* Presets::scene_ = nullptr;
octree::Octree* Presets::tree_ = nullptr;

TEST_F(Presets, FarFramesTheObject) {
  const octree::Octree& tree = *tree_;
  const auto [lo, hi] = object_bounds(tree);
  EXPECT_LT(glm::max(lo.x, glm::max(lo.y, lo.z)),
            -0.7f);  // the bricks' bounds hold the sphere (radius 0.7 and its bumps)
  EXPECT_GT(glm::min(hi.x, glm::min(hi.y, hi.z)), 0.7f);
  for (float aspect : {1.0f, 0.5f, 2.0f}) {
    Camera c = view_preset(tree, "far", aspect);
    EXPECT_NO_THROW(validate_camera(c, "far"));
    EXPECT_LT(glm::length(c.target), 0.1f) << "aimed at the sphere's centre";
    // The sphere's share of the narrower field: its base (radius 0.7) fills
    // most of it, its outer bound (0.8, above the bumps) stays inside it.
    // The framed bricks reach up to a brick (8 voxels, 0.22 here) beyond the
    // surface, hence 0.55 (framing the whole domain gave 0.44).
    const float d = glm::length(c.eye - c.target);
    const float half = std::atan(std::tan(glm::radians(0.5f * c.fov_deg)) * std::min(1.0f, aspect));
    auto share = [&](float r) { return std::tan(std::asin(r / d)) / std::tan(half); };
    EXPECT_GT(share(0.7f), 0.55f) << "aspect " << aspect << ": framed, not lost in the domain";
    EXPECT_LT(share(0.8f), 1.0f) << "aspect " << aspect;
    EXPECT_GT(c.eye.y, c.target.y);  // elevated
  }
}

TEST_F(Presets, OrbitAndDistance) {
  const float size = object_size(*tree_);
  EXPECT_NEAR(size, glm::length(object_bounds(*tree_).second - object_bounds(*tree_).first), 1e-6f);
  // Azimuth 90, elevation 0: the eye on +x of the target; 2 object sizes away.
  Camera side = view_preset(*tree_, "far", 1.0f, PresetOptions{90, 0, 2});
  glm::vec3 to_eye = side.eye - side.target;
  EXPECT_NEAR(glm::length(to_eye), 2 * size, 1e-4f * size);
  EXPECT_NEAR(glm::normalize(to_eye).x, 1.0f, 1e-5f);
  // Elevation 60: from above; mid keeps its target and is 2x closer than far along the same direction.
  Camera far = view_preset(*tree_, "far", 1.0f, PresetOptions{-20, 60, 0});
  Camera mid = view_preset(*tree_, "mid", 1.0f, PresetOptions{-20, 60, 0});
  glm::vec3 d = glm::normalize(far.eye - far.target);
  EXPECT_NEAR(d.y, std::sin(glm::radians(60.0f)), 1e-5f);
  EXPECT_NEAR(glm::length(mid.eye - mid.target), glm::length(far.eye - far.target) / 2, 1e-4f);
  EXPECT_THROW(view_preset(*tree_, "far", 1.0f, PresetOptions{0, 90, 0}), std::invalid_argument);
  EXPECT_THROW(view_preset(*tree_, "far", 1.0f, PresetOptions{0, 0, -1}), std::invalid_argument);
  // Straight down: the up vector changes so the camera stays valid.
  EXPECT_NO_THROW(validate_camera(view_preset(*tree_, "far", 1.0f, PresetOptions{0, 89.9f, 0}), "down"));
}

TEST(DefaultLights, KeyFromTheCamerasUpperSideAndADimFill) {
  Camera c;
  c.eye = glm::vec3(5, 1, 2);
  c.target = glm::vec3(0, 0, 0);
  c.up = glm::vec3(0, 1, 0);
  const std::vector<Light> lights = default_lights(c);
  ASSERT_EQ(lights.size(), 2u);
  const glm::vec3 forward = glm::normalize(c.target - c.eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, c.up)), up = glm::cross(right, forward);
  const glm::vec3 key = glm::normalize(lights[0].vector), fill = glm::normalize(lights[1].vector);
  EXPECT_GT(glm::dot(key, up), 0.5f);                             // from above the camera
  EXPECT_LT(glm::dot(key, forward), 0.0f);                        // from the camera's side of the object
  EXPECT_LT(glm::dot(key, forward), -0.25f);                      // not grazing
  EXPECT_GT(glm::dot(key, forward), -0.9f);                       // not a head light: --shadows show
  EXPECT_LT(glm::dot(key, right) * glm::dot(fill, right), 0.0f);  // from the other side
  EXPECT_LT(lights[1].radiance.x, 0.3f * lights[0].radiance.x);
  EXPECT_GT(lights[1].radiance.x, 0.0f);
}

TEST_F(Presets, MidIsTwiceAsCloseTowardsTheSurface) {
  Camera far = view_preset(*tree_, "far"), mid = view_preset(*tree_, "mid");
  EXPECT_NEAR(glm::length(mid.eye - mid.target), glm::length(far.eye - far.target) / 2, 1e-4f);
  EXPECT_LT(glm::length(mid.target), 0.05f);   // the sphere's centre
  EXPECT_GT(scene_->distance(mid.eye), 0.1f);  // outside the sphere
}

TEST_F(Presets, CloseLooksObliquelyAtANearbySurfacePoint) {
  Camera c = view_preset(*tree_, "close");
  EXPECT_NO_THROW(validate_camera(c, "close"));
  const float voxel = tree_->voxel_size(tree_->depth_count - 1);
  float distance = glm::length(c.eye - c.target);
  // No detail octaves: the finest voxel spans 1/64 of the field of view, or
  // more where that would be farther than half the mid view's distance
  // (at 64^3 it is: 64 voxels are wider than the sphere).
  Camera mid_camera = view_preset(*tree_, "mid");
  const float mid_distance = glm::length(mid_camera.eye - mid_camera.target);
  const float field = 2 * distance * std::tan(glm::radians(0.5f * c.fov_deg));
  EXPECT_NEAR(distance, close_distance(*tree_), 1e-4f);
  EXPECT_NEAR(distance, std::min(64 * voxel / (2 * std::tan(glm::radians(20.0f))), mid_distance / 2), 1e-4f);
  EXPECT_LE(field / voxel, 64.01f);
  // A portrait image: the narrower field is the horizontal one.
  EXPECT_NEAR(close_distance(*tree_, 0.25f),
              std::min(64 * voxel / (0.5f * std::tan(glm::radians(20.0f))), glm::length([&] {
                                                                              Camera m =
                                                                                  view_preset(*tree_, "mid", 0.25f);
                                                                              return m.eye - m.target;
                                                                            }()) /
                                                                                2),
              1e-4f);
  // With detail octaves the surface holds detail at any zoom: 8 voxels away.
  octree::Octree detailed = *tree_;
  detailed.detail.octaves = 3;
  EXPECT_NEAR(close_distance(detailed), std::max(8 * voxel, 0.02f * tree_->size), 1e-4f);
  EXPECT_LT(std::abs(scene_->distance(c.target)), 0.5f * voxel) << "target off the surface";
  EXPECT_GT(scene_->distance(c.eye), 2 * voxel) << "eye inside or on the surface";
  // Oblique: between 10 and 65 degrees from the surface normal.
  glm::vec3 n = scene_->normal(c.target), to_eye = glm::normalize(c.eye - c.target);
  float degrees = glm::degrees(std::acos(glm::dot(n, to_eye)));
  EXPECT_GT(degrees, 10.0f);
  EXPECT_LT(degrees, 65.0f);
  // On the visible side of the mid view.
  Camera mid = view_preset(*tree_, "mid");
  EXPECT_LT(glm::length(c.target - mid.eye), glm::length(mid.target - mid.eye));
}

TEST_F(Presets, UnknownNameAndEmptyTree) {
  EXPECT_EQ(error_of([&] { view_preset(*tree_, "closer"); }), "unknown view 'closer' (views: far, mid, close)");
  octree::Octree empty;
  empty.depth_first_node = {0, 1};
  empty.nodes.resize(1);
  EXPECT_NO_THROW(view_preset(empty, "far"));
  EXPECT_THROW(view_preset(empty, "mid"), std::runtime_error);
  EXPECT_THROW(view_preset(empty, "close"), std::runtime_error);
}

}  // namespace
}  // namespace svo::render
